/* raystream-bench: what its tables and modes share (public headers only). */
#ifndef RS_BENCH_H
#define RS_BENCH_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_render.h"

/* Frames timed per setting, at most (--repeats). */
#define BENCH_MAX_FRAMES 32
/* Instances of one --instance-updates row, at most (the scene's triangle limit). */
#define BENCH_MAX_INSTANCES 65535u
/* Scenes of one --times run, at most. */
#define BENCH_MAX_SCENES 16

struct bench_options {
	uint32_t table; /* 1: hit numbers and build times; 2: fps over a render backend */
	bool times;     /* --times: frame times of one setting per scene (was raystream-glbench) */
	bool builds;    /* --builds: BVH build time against Embree's (builds.c) */
	uint32_t animate; /* --animate N: per-frame update against set_scene (animate.c); 0: off */
	bool instance_updates; /* --instance-updates: moving N instances (instances.c) */
	bool error; /* --times --error: the first frame against the CPU reference tracer */
	uint32_t size, flat_size, none_max_tris, passes, lights, repeats, threads;
	const char *only;                     /* --scene: one of bench_scenes, or NULL for all */
	const char *scenes[BENCH_MAX_SCENES]; /* --times: the scenes named */
	size_t scene_count;
	const char *backend;           /* tables 2 and --times: the backend opened (resolved) */
	enum rs_bvh_builder builder;   /* table 2: the BVH every backend and the peer use */
	bool peer;                     /* table 2: run the Embree peer (when built) */
	struct rs_pack_desc pack;      /* --nodes; table 1 defaults to the paper's layout */
	bool pack_set;                 /* --nodes given */
	enum rs_scene_storage storage; /* table 2: --scene-storage */
	enum rs_kernel_stage kernels;  /* table 2: --kernels */
	struct rs_render_desc render;  /* the render options as given (--times renders with it) */
	cJSON *json;                   /* --json: rows are added here; NULL: not asked for */
};

/* The paper's scenes, in its order. */
#define BENCH_SCENE_COUNT 6
extern const char *const bench_scenes[BENCH_SCENE_COUNT];

/* Median, smallest and largest of n values. */
struct bench_summary {
	double median, min, max;
};
struct bench_summary bench_summarize(const double *v, uint32_t n);

/* Per-frame figures of n timed frames: wall clock around rs_renderer_render() (readback
 * into host memory included), process CPU time (a GL driver's threads included: on a
 * shared machine far steadier than wall time), the renderer's own render/readback times
 * and each kernel's. */
struct bench_frames {
	uint32_t n;
	double wall_ms[BENCH_MAX_FRAMES], cpu_ms[BENCH_MAX_FRAMES];
	double render_ms[BENCH_MAX_FRAMES], readback_ms[BENCH_MAX_FRAMES];
	uint32_t kernel_count;
	struct {
		char name[24];
		uint32_t calls;
		double ms[BENCH_MAX_FRAMES];
	} kernels[RS_RENDER_MAX_KERNELS];
};

/* Render n (<= BENCH_MAX_FRAMES) timed frames of `r` into `frame`. The one timing loop of
 * every mode. */
enum rs_status bench_time_frames(struct rs_renderer *r, struct rs_frame *frame, uint32_t n,
                                 struct bench_frames *out, struct rs_error *err);

/* One progress line on stderr ("raystream-bench: ..."), once the run has taken 2 s: a
 * quick run stays quiet, a long one says where it is. */
void bench_progress(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* The figures as JSON: a summary object {median, min, max}. */
cJSON *bench_json_summary(struct bench_summary s);

int bench_table1(const struct bench_options *o);
int bench_table2(const struct bench_options *o);
int bench_times(const struct bench_options *o);
int bench_builds(const struct bench_options *o);           /* BVH build time against Embree's */
int bench_animate(const struct bench_options *o);          /* per-frame update against set_scene */
int bench_instance_updates(const struct bench_options *o); /* moving N instances a frame */

#endif
