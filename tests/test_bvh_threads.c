/* rs_bvh's SAH builder on several threads, and with or without its run-time chosen AVX code:
 * the tree (nodes and triangle order, to the byte) is the one-thread tree for every thread
 * count and for either path, on meshes big enough for the threaded
 * paths (subtrees on the threads, big nodes binned and partitioned in chunks), including signed
 * zeros and coincident centroids, whose min/max and list-order splits would show any dependence on
 * how the work was divided. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_bvh.h"

#include "../lib/bvh/bvh_sah.h" /* rs_bvh__wide_allowed, rs_bvh__wide() */
#include "../lib/bvh/bvh_v4.h"  /* RS_BVH_WIDE */

struct mesh {
	float *pos;
	uint32_t *idx;
	size_t verts, tris;
};

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

static struct mesh mesh_alloc(size_t tris)
{
	struct mesh m = {malloc(9 * tris * sizeof(float)), malloc(3 * tris * sizeof(uint32_t)),
	                 3 * tris, tris};
	assert_non_null(m.pos);
	assert_non_null(m.idx);
	for (size_t i = 0; i < 3 * tris; i++)
		m.idx[i] = (uint32_t)i;
	return m;
}

/* Small triangles in a 100-unit cube, every seventh long and thin, a few floor-sized ones
 * (the size split). */
static struct mesh random_mesh(size_t tris)
{
	struct mesh m = mesh_alloc(tris);
	for (size_t t = 0; t < tris; t++) {
		double c[3] = {rnd() * 100, rnd() * 100, rnd() * 100};
		double s = t % 997 == 0 ? 150.0 : t % 7 == 0 ? 20.0 : 2.0;
		for (int k = 0; k < 9; k++)
			m.pos[9 * t + k] = (float)(c[k % 3] + (rnd() - 0.5) * s);
	}
	return m;
}

/* A grid of triangles on the plane z = 0 around the origin, z written as +0 or -0 at
 * random, each triangle present three times (coincident centroids: list-order splits). */
static struct mesh zero_grid(size_t side)
{
	struct mesh m = mesh_alloc(3 * side * side);
	size_t t = 0;
	for (size_t i = 0; i < side; i++) {
		for (size_t j = 0; j < side; j++) {
			float x = (float)i - (float)side / 2, y = (float)j - (float)side / 2;
			const float v[9] = {x, y, 0.0f, x + 1, y, 0.0f, x, y + 1, 0.0f};
			for (int copy = 0; copy < 3; copy++, t++) {
				memcpy(&m.pos[9 * t], v, sizeof v);
				for (int k = 0; k < 3; k++)
					m.pos[9 * t + 3 * k + 2] = rnd() < 0.5 ? -0.0f : 0.0f;
				if (x == 0.0f && rnd() < 0.5)
					m.pos[9 * t] = -0.0f;
			}
		}
	}
	return m;
}

struct built {
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t count;
};

static struct built build_desc(const struct mesh *m, struct rs_bvh_desc d)
{
	uint32_t threads = d.threads;
	size_t cap = rs_bvh_node_bound(&d, m->tris);
	struct built b = {malloc(cap * sizeof *b.nodes), malloc(m->tris * sizeof *b.order), 0};
	assert_non_null(b.nodes);
	assert_non_null(b.order);
	/* Poisoned: a triangle order the build failed to write cannot pass for a right one. */
	memset(b.order, 0xff, m->tris * sizeof *b.order);
	struct rs_error err;
	if (rs_bvh_build(&d, m->pos, m->verts, m->idx, m->tris, b.nodes, cap, b.order, &b.count,
	                 &err) != RS_OK)
		fail_msg("build on %u threads: %s", threads, err.message);
	if (rs_bvh_check(b.nodes, b.count, m->pos, m->idx, b.order, m->tris, &err) != RS_OK)
		fail_msg("tree built on %u threads: %s", threads, err.message);
	return b;
}

static struct built build_leaves(const struct mesh *m, uint32_t threads, uint32_t leaf_size)
{
	struct rs_bvh_desc d = {.builder = RS_BVH_SAH, .threads = threads, .leaf_size = leaf_size};
	return build_desc(m, d);
}

static struct built build(const struct mesh *m, uint32_t threads)
{
	return build_leaves(m, threads, 0);
}

static void built_free(struct built *b)
{
	free(b->nodes);
	free(b->order);
}

/* b is the one-thread tree `one` to the byte: nodes and triangle order. */
static void assert_same_tree(const struct built *b, const struct built *one, size_t tris)
{
	assert_int_equal(b->count, one->count);
	assert_memory_equal(b->nodes, one->nodes, one->count * sizeof *one->nodes);
	assert_memory_equal(b->order, one->order, tris * sizeof *one->order);
}

static void assert_same_for_every_thread_count(const struct mesh *m)
{
	struct built one = build(m, 1);
	const uint32_t counts[] = {2, 3, 4, 7};
	for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
		struct built b = build(m, counts[k]);
		if (b.count != one.count)
			fail_msg("%zu triangles, %u threads: %zu nodes, one thread %zu", m->tris,
			         counts[k], b.count, one.count);
		for (size_t i = 0; i < one.count; i++)
			if (memcmp(&b.nodes[i], &one.nodes[i], sizeof one.nodes[i]) != 0)
				fail_msg("%zu triangles, %u threads: node %zu differs", m->tris,
				         counts[k], i);
		if (memcmp(b.order, one.order, m->tris * sizeof *one.order) != 0)
			fail_msg("%zu triangles, %u threads: triangle order differs", m->tris,
			         counts[k]);
		built_free(&b);
	}
	built_free(&one);
}

/* 9,000 triangles: past the threaded build's floor and the chunked binning and partition's
 * (the root only, in two chunks); 40,000 and 70,000: the root, its children and some
 * grandchildren are binned and partitioned in chunks on the threads (each chunk within its
 * own range, then its two blocks moved to their places) where one thread partitions in one
 * pass, and each must put every record in the same place. */
static void random_mesh_tree_is_independent_of_threads(void **state)
{
	(void)state;
	const size_t sizes[] = {9000, 40000, 70000};
	for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
		struct mesh m = random_mesh(sizes[k]);
		assert_same_for_every_thread_count(&m);
		free(m.pos);
		free(m.idx);
	}
}

/* Builds one after another in one process, as a renderer does on every set_scene: the
 * builder's scratch comes from memory the previous build freed, which held its own
 * placeholders for deferred subtrees. A node must never be taken for a placeholder because
 * of what that memory held (it was: a stale level sent subtrees to the wrong places, and
 * a Release build crashed or packed a broken tree). ASan's quarantine keeps freed memory
 * from being reused, so it is the Release run of this test that would catch it. */
static void repeated_builds_are_independent_of_earlier_ones(void **state)
{
	(void)state;
	for (int k = 0; k < 24; k++) {
		struct mesh m = random_mesh(20000 + (size_t)(k % 3) * 1500);
		struct built one = build(&m, 1), many = build(&m, 2 + (uint32_t)(k % 3));
		assert_same_tree(&many, &one, m.tris);
		built_free(&one);
		built_free(&many);
		free(m.pos);
		free(m.idx);
	}
}

/* 300,000 triangles on two threads: subtrees of n / 16 records, above the size at which the
 * upper nodes bin in chunks on the threads; a subtree, already on a thread, must bin on its
 * own (two threads, one build each: a nested loop on the threads would hang or race). */
static void big_subtrees_bin_on_their_own_thread(void **state)
{
	(void)state;
	struct mesh m = random_mesh(300000);
	struct built one = build(&m, 1), two = build(&m, 2);
	assert_same_tree(&two, &one, m.tris);
	built_free(&one);
	built_free(&two);
	free(m.pos);
	free(m.idx);
}

static void signed_zeros_and_duplicates_are_independent_of_threads(void **state)
{
	(void)state;
	struct mesh m = zero_grid(120); /* 43,200 triangles */
	assert_same_for_every_thread_count(&m);
	free(m.pos);
	free(m.idx);
}

/* leaf_size 1024 on 9,300 triangles: 800 copies of one triangle far from the rest make a
 * node of the upper tree (above the subtrees of n / (8 threads) records) that is a leaf (its
 * centroids coincide and it fits a leaf). The threads read each subtree's triangle order as
 * it is done; such a leaf's must be read too. */
static void leaves_above_the_subtrees_keep_their_order(void **state)
{
	(void)state;
	struct mesh m = random_mesh(9300);
	for (size_t t = 8500; t < m.tris; t++) {
		const float v[9] = {500.0f, 500.0f, 500.0f, 510.0f, 500.0f,
		                    500.0f, 500.0f, 510.0f, 500.0f};
		memcpy(&m.pos[9 * t], v, sizeof v);
	}
	struct built one = build_leaves(&m, 1, 1024);
	int top_leaf = 0;
	for (size_t i = 0; i < one.count; i++)
		top_leaf |= one.nodes[i].count == 800;
	assert_true(top_leaf);
	const uint32_t counts[] = {2, 3, 4, 7};
	for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
		struct built b = build_leaves(&m, counts[k], 1024);
		assert_same_tree(&b, &one, m.tris);
		built_free(&b);
	}
	built_free(&one);
	free(m.pos);
	free(m.idx);
}

/* The threads share the work: the SAH cost is the one-thread tree's, not merely close. */
static void threads_keep_the_sah_cost(void **state)
{
	(void)state;
	struct mesh m = random_mesh(20000);
	struct built one = build(&m, 1), four = build(&m, 4);
	struct rs_bvh_stats a, b;
	rs_bvh_stats(one.nodes, one.count, 1.0f, &a);
	rs_bvh_stats(four.nodes, four.count, 1.0f, &b);
	assert_true(a.sah_cost == b.sah_cost);
	assert_true(a.sah_cost > 0.0);
	built_free(&one);
	built_free(&four);
	free(m.pos);
	free(m.idx);
}

static void thread_count_is_validated(void **state)
{
	(void)state;
	struct rs_bvh_desc d;
	rs_bvh_desc_resolve(NULL, &d);
	assert_int_equal(d.threads, 1);
	struct mesh m = random_mesh(10);
	struct rs_bvh_node nodes[32];
	uint32_t order[10];
	size_t count = 7;
	struct rs_bvh_desc bad = {.threads = RS_BVH_MAX_THREADS + 1};
	struct rs_error err;
	assert_int_equal(
	    rs_bvh_build(&bad, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "threads"));
	assert_int_equal(count, 0);
	/* Below the threaded build's floor, many threads build the one-thread tree. */
	struct rs_bvh_desc many = {.threads = 16};
	assert_int_equal(
	    rs_bvh_build(&many, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_OK);
	assert_int_equal(rs_bvh_check(nodes, count, m.pos, m.idx, order, m.tris, &err), RS_OK);
	free(m.pos);
	free(m.idx);
}

/* The mesh is checked as the threads read it: the first bad triangle is named, whatever
 * chunk finds a bad one first. */
static void bad_input_is_named_the_same_on_threads(void **state)
{
	(void)state;
	struct mesh m = random_mesh(40000);
	m.pos[9 * 30000 + 4] = -INFINITY; /* triangle 30000's vertex 90001 */
	m.idx[3 * 35000 + 2] = (uint32_t)m.verts + 5;
	struct rs_bvh_desc d = {.threads = 1};
	size_t cap = rs_bvh_node_bound(&d, m.tris), count = 3;
	struct rs_bvh_node *nodes = malloc(cap * sizeof *nodes);
	uint32_t *order = malloc(m.tris * sizeof *order);
	assert_non_null(nodes);
	assert_non_null(order);
	const uint32_t threads[] = {1, 2, 7};
	for (size_t k = 0; k < 3; k++) {
		d.threads = threads[k];
		struct rs_error err;
		assert_int_equal(rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, cap, order,
		                              &count, &err),
		                 RS_ERR_BAD_DATA);
		assert_string_equal(err.message, "bvh: vertex 90001 is not finite");
		assert_int_equal(count, 0);
	}
	m.pos[9 * 30000 + 4] = 1.0f;
	struct rs_error err;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, cap, order, &count, &err),
	    RS_ERR_BAD_DATA);
	assert_string_equal(err.message, "bvh: triangle 35000 uses vertex 120005 of 120000");
	free(nodes);
	free(order);
	free(m.pos);
	free(m.idx);
}

/* The AVX code (the sweeps' plane costs four planes at a time, the plane partition) builds
 * the tree the SSE code builds, or which path the CPU picks would change images and hit
 * numbers from machine to machine. Bin counts that leave 0 to 3 planes after the last group
 * of four, and the most; coordinates rounded to integers for equal costs between planes
 * (the first must win on both paths). */
static void wide_and_narrow_build_the_same_tree(void **state)
{
	(void)state;
	const uint32_t bins[] = {2, 5, 7, 16, 33, 256};
	for (int coarse = 0; coarse < 2; coarse++) {
		struct mesh m = random_mesh(coarse ? 3000 : 20000);
		for (size_t i = 0; coarse && i < 9 * m.tris; i++)
			m.pos[i] = (float)(int)m.pos[i];
		for (size_t j = 0; j < sizeof bins / sizeof bins[0]; j++) {
			struct rs_bvh_desc d = {
			    .builder = RS_BVH_SAH, .sah_bins = bins[j], .threads = j % 2 ? 2 : 1};
			rs_bvh__wide_allowed = 0;
			struct built narrow = build_desc(&m, d);
			rs_bvh__wide_allowed = 1;
			struct built wide = build_desc(&m, d);
			if (wide.count != narrow.count)
				fail_msg("%zu triangles, %u bins: %zu nodes wide, %zu narrow",
				         m.tris, bins[j], wide.count, narrow.count);
			assert_same_tree(&wide, &narrow, m.tris);
			built_free(&narrow);
			built_free(&wide);
		}
		free(m.pos);
		free(m.idx);
	}
}

/* The switch reaches the build: cleared, no build runs the AVX code; set, every build on a
 * CPU with AVX does (else the test above compares a path with itself, and says so). */
static void the_switch_picks_the_path(void **state)
{
	(void)state;
	rs_bvh__wide_allowed = 0;
	assert_int_equal(rs_bvh__wide(), 0);
	rs_bvh__wide_allowed = 1;
#ifdef RS_BVH_WIDE
	assert_int_equal(rs_bvh__wide(), __builtin_cpu_supports("avx") ? 1 : 0);
	if (!rs_bvh__wide())
		printf("no AVX on this CPU: both paths above were the SSE one\n");
#else
	assert_int_equal(rs_bvh__wide(), 0);
	printf("no AVX code in this build: both paths above were the same\n");
#endif
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(random_mesh_tree_is_independent_of_threads),
	    cmocka_unit_test(signed_zeros_and_duplicates_are_independent_of_threads),
	    cmocka_unit_test(big_subtrees_bin_on_their_own_thread),
	    cmocka_unit_test(repeated_builds_are_independent_of_earlier_ones),
	    cmocka_unit_test(leaves_above_the_subtrees_keep_their_order),
	    cmocka_unit_test(threads_keep_the_sah_cost),
	    cmocka_unit_test(thread_count_is_validated),
	    cmocka_unit_test(bad_input_is_named_the_same_on_threads),
	    cmocka_unit_test(wide_and_narrow_build_the_same_tree),
	    cmocka_unit_test(the_switch_picks_the_path),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
