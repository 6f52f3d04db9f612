/* raystream-optsynth internals shared by the generator and the benchmark. */
#ifndef OPTSYNTH_H
#define OPTSYNTH_H

#include <stdint.h>

#include "raystream/rs_optical.h"

struct optsynth_options {
	int frames, width, height, runs;
	double rate, baseline;
	const char *script;
	uint64_t seed;
	struct rs_optical_synth_desc synth;
	int verifier; /* the layout's verifier light drawn, DIR/layout.json written */
};

/* The markers drawn: rs_pose_layout_default(), with o->verifier its _verified() form. */
void optsynth_layout(const struct optsynth_options *o, struct rs_pose_layout *out);

/* One frame pair i of a sequence: its true pose T (time_s set) and both images. Returns 1
 * for a frame, 0 after the last, -1 on error (err set). */
typedef int (*optsynth_frame_fn)(void *ctx, const struct optsynth_options *o,
                                 const struct rs_optical_rig *rig,
                                 const struct rs_pose_layout *layout, int i, struct rs_pose *T,
                                 uint8_t *img0, uint8_t *img1, struct rs_error *err);

/* Writes DIR/rig.yaml (the example rig), DIR/{left,right}_%04d.png and DIR/truth.txt of
 * the frames `frame` gives, naming them on stdout; returns the exit code. */
int optsynth_write(const char *dir, const struct optsynth_options *o, optsynth_frame_fn frame,
                   void *ctx);

/* The hard-case sequence `name` (edges, corners, stray, ghosts) into DIR; the exit code. */
int optsynth_hard(const char *dir, const struct optsynth_options *o, const char *name);

/* Whether `name` is a hard-case sequence. */
int optsynth_hard_known(const char *name);

/* Prints the benchmark report (markdown); returns the exit code. */
int optsynth_bench(const struct optsynth_options *o);

#endif
