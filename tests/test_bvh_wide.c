/* rs_bvh's SAH builder with and without its run-time chosen AVX code (the sweeps' plane
 * costs, four planes at a time): the tree (nodes and triangle order, to the byte) must be
 * the same, or which path the CPU picks would change images and hit numbers from machine to
 * machine. On a CPU without AVX both builds take the same path and the test says so. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_bvh.h"

#include "../lib/bvh/bvh_sah.h"
#include "../lib/bvh/bvh_v4.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

struct mesh {
	float *pos;
	uint32_t *idx;
	size_t verts, tris;
};

/* Triangles of three sizes in a box stretched along x (so the axes' bins differ), a few of
 * them as wide as the box (the size split), some sharing vertices with coarse coordinates
 * (equal costs between planes, where the first must win on both paths). */
static struct mesh random_mesh(size_t tris, int coarse)
{
	struct mesh m = {malloc(9 * tris * sizeof(float)), malloc(3 * tris * sizeof(uint32_t)),
	                 3 * tris, tris};
	assert_non_null(m.pos);
	assert_non_null(m.idx);
	for (size_t t = 0; t < tris; t++) {
		double c[3] = {rnd() * 400, rnd() * 100, rnd() * 60};
		double s = t % 501 == 0 ? 300.0 : t % 5 == 0 ? 15.0 : 1.5;
		for (int k = 0; k < 9; k++) {
			double v = c[k % 3] + (rnd() - 0.5) * s;
			m.pos[9 * t + k] = coarse ? (float)(int)v : (float)v;
		}
		for (int k = 0; k < 3; k++)
			m.idx[3 * t + k] = (uint32_t)(3 * t + k);
	}
	return m;
}

struct built {
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t count;
};

static struct built build(const struct mesh *m, uint32_t bins, uint32_t threads, int wide)
{
	rs_bvh__wide_allowed = wide;
	struct rs_bvh_desc d = {.builder = RS_BVH_SAH, .sah_bins = bins, .threads = threads};
	size_t cap = rs_bvh_node_bound(&d, m->tris);
	struct built b = {malloc(cap * sizeof *b.nodes), malloc(m->tris * sizeof *b.order), 0};
	assert_non_null(b.nodes);
	assert_non_null(b.order);
	memset(b.order, 0xff, m->tris * sizeof *b.order);
	struct rs_error err;
	enum rs_status st = rs_bvh_build(&d, m->pos, m->verts, m->idx, m->tris, b.nodes, cap,
	                                 b.order, &b.count, &err);
	rs_bvh__wide_allowed = 1;
	if (st != RS_OK)
		fail_msg("build, %u bins, wide %d: %s", bins, wide, err.message);
	return b;
}

static void built_free(struct built *b)
{
	free(b->nodes);
	free(b->order);
}

/* Bin counts that leave 0, 1, 2 and 3 planes after the last group of four, and the most. */
static void wide_and_narrow_build_the_same_tree(void **state)
{
	(void)state;
	const uint32_t bins[] = {2, 5, 7, 16, 33, 256};
	const size_t sizes[] = {3000, 20000};
	for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
		for (int coarse = 0; coarse < 2; coarse++) {
			struct mesh m = random_mesh(sizes[k], coarse);
			for (size_t j = 0; j < sizeof bins / sizeof bins[0]; j++) {
				uint32_t threads = j % 2 ? 2 : 1;
				struct built narrow = build(&m, bins[j], threads, 0);
				struct built wide = build(&m, bins[j], threads, 1);
				if (wide.count != narrow.count)
					fail_msg(
					    "%zu triangles, %u bins: %zu nodes wide, %zu narrow",
					    m.tris, bins[j], wide.count, narrow.count);
				for (size_t i = 0; i < narrow.count; i++)
					if (memcmp(&wide.nodes[i], &narrow.nodes[i],
					           sizeof narrow.nodes[i]) != 0)
						fail_msg("%zu triangles, %u bins: node %zu differs",
						         m.tris, bins[j], i);
				assert_memory_equal(wide.order, narrow.order,
				                    m.tris * sizeof *narrow.order);
				built_free(&narrow);
				built_free(&wide);
			}
			free(m.pos);
			free(m.idx);
		}
	}
}

/* The switch reaches the build: cleared, no build runs the AVX code; set, every build on a
 * CPU with AVX does (otherwise the comparison above would compare a path with itself). */
static void the_switch_picks_the_path(void **state)
{
	(void)state;
	rs_bvh__wide_allowed = 0;
	assert_int_equal(rs_bvh__wide(), 0);
	rs_bvh__wide_allowed = 1;
#ifdef RS_BVH_WIDE
	assert_int_equal(rs_bvh__wide(), __builtin_cpu_supports("avx") ? 1 : 0);
	if (!rs_bvh__wide())
		printf("no AVX on this CPU: both builds above took the narrow path\n");
#else
	assert_int_equal(rs_bvh__wide(), 0);
	printf("no AVX path in this build: both builds above took the narrow path\n");
#endif
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(wide_and_narrow_build_the_same_tree),
	    cmocka_unit_test(the_switch_picks_the_path),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
