/* raystream-track internals shared by the tool's main loop and its benchmark. */
#ifndef TRACK_TOOL_H
#define TRACK_TOOL_H

#include "raystream/rs_pose.h"

/* Runs the benchmark and prints its report; returns the process exit code. */
int track_bench(int samples, const struct rs_pose_layout *layout);

#endif
