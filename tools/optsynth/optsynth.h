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
};

/* Prints the benchmark report (markdown); returns the exit code. */
int optsynth_bench(const struct optsynth_options *o);

#endif
