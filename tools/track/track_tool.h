/* raystream-track internals shared by the tool's main loop and its benchmark. */
#ifndef TRACK_TOOL_H
#define TRACK_TOOL_H

#include <signal.h>

#include "raystream/rs_pose.h"
#include "raystream/rs_track.h"

/* Runs the benchmark and prints its report; returns the process exit code. */
int track_bench(int samples, const struct rs_pose_layout *layout);

/* Plays `src` into a new pty (path printed on stdout) until count/duration/end/stop. */
int track_serve_pty(struct rs_track_source *src, long long count, double duration_s,
                    volatile sig_atomic_t *stop);

#endif
