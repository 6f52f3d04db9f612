/* raystream-bench: what its tables share (public headers only). */
#ifndef RS_BENCH_H
#define RS_BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_render.h"

struct bench_options {
	uint32_t table; /* 1: hit numbers and build times; 2: fps over a render backend */
	uint32_t size, flat_size, none_max_tris, passes, lights, repeats, threads;
	const char *only;              /* --scene: one of bench_scenes, or NULL for all */
	const char *backend;           /* table 2: the backend under test */
	enum rs_bvh_builder builder;   /* table 2: the BVH every backend and the peer use */
	bool peer;                     /* table 2: run the Embree peer (when built) */
	struct rs_pack_desc pack;      /* --nodes; table 1 defaults to the paper's layout */
	bool pack_set;                 /* --nodes given */
	enum rs_scene_storage storage; /* table 2: --scene-storage */
};

/* The paper's scenes, in its order. */
#define BENCH_SCENE_COUNT 6
extern const char *const bench_scenes[BENCH_SCENE_COUNT];

/* Smallest and largest of v[0..n). */
void bench_min_max(const double *v, uint32_t n, double *out_min, double *out_max);

int bench_table1(const struct bench_options *o);
int bench_table2(const struct bench_options *o);
int bench_table3(const struct bench_options *o); /* BVH build time against Embree's */

#endif
