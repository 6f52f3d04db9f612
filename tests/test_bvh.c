/* rs_bvh: every builder's layout against the definition of the threaded pre-order tree
 * (decoded independently of the stored escapes), the paper builder against its closed
 * form, rs_bvh_check catching corruption, and input validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_bvh.h"

struct mesh {
	float *pos;
	uint32_t *idx;
	size_t verts, tris;
};

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* Small random triangles scattered in a 100-unit cube (plus some long thin ones), so
 * every builder gets overlapping and well-separated boxes. */
static struct mesh random_mesh(size_t tris)
{
	struct mesh m = {malloc(9 * tris * sizeof(float) + 1),
	                 malloc(3 * tris * sizeof(uint32_t) + 1), 3 * tris, tris};
	for (size_t t = 0; t < tris; t++) {
		double c[3] = {rnd() * 100, rnd() * 100, rnd() * 100};
		double s = (t % 7 == 0) ? 20.0 : 2.0;
		for (int k = 0; k < 3; k++) {
			for (int a = 0; a < 3; a++)
				m.pos[9 * t + 3 * k + a] = (float)(c[a] + (rnd() - 0.5) * s);
			m.idx[3 * t + k] = (uint32_t)(3 * t + k);
		}
	}
	return m;
}

static void mesh_free(struct mesh *m)
{
	free(m->pos);
	free(m->idx);
}

struct built {
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t count;
};

static struct built build(enum rs_bvh_builder b, const struct mesh *m)
{
	struct rs_bvh_desc d = {.builder = b};
	size_t cap = rs_bvh_node_bound(&d, m->tris);
	struct built out = {malloc((cap + 1) * sizeof *out.nodes),
	                    malloc((m->tris + 1) * sizeof(uint32_t)), 0};
	struct rs_error err;
	enum rs_status s = rs_bvh_build(&d, m->pos, m->verts, m->idx, m->tris, out.nodes, cap,
	                                out.order, &out.count, &err);
	if (s != RS_OK)
		fail_msg("build %s: %s", rs_bvh_builder_name(b), err.message);
	return out;
}

static void built_free(struct built *b)
{
	free(b->nodes);
	free(b->order);
}

/* Decode the tree from the leaf/interior flags alone (a full binary tree is determined by
 * its pre-order flag sequence): returns the first node after i's subtree, i.e. the
 * definition of escape(i), and its height. */
static size_t decode(const struct rs_bvh_node *n, size_t count, size_t i, uint32_t *height)
{
	assert_true(i < count);
	if (n[i].level == 0) {
		*height = 0;
		return i + 1;
	}
	uint32_t h1, h2;
	size_t c2 = decode(n, count, i + 1, &h1);
	size_t end = decode(n, count, c2, &h2);
	*height = 1 + (h1 > h2 ? h1 : h2);
	return end;
}

static void box_of_slots(const struct mesh *m, const uint32_t *order, uint32_t first,
                         uint32_t count, float lo[3], float hi[3])
{
	for (int a = 0; a < 3; a++) {
		lo[a] = FLT_MAX;
		hi[a] = -FLT_MAX;
	}
	for (uint32_t s = first; s < first + count; s++)
		for (int k = 0; k < 3; k++)
			for (int a = 0; a < 3; a++) {
				float p = m->pos[3 * m->idx[3 * order[s] + k] + a];
				lo[a] = p < lo[a] ? p : lo[a];
				hi[a] = p > hi[a] ? p : hi[a];
			}
}

/* Escape, level and tight bounds of every node against the definition. For trees the
 * subtree is decoded from the flags; flat lists are forests of leaves. Bounds must be
 * the exact bounds of the triangles below (the union is exact in float). */
static void assert_definition(const struct built *b, const struct mesh *m, int flat)
{
	for (size_t i = 0; i < b->count; i++) {
		uint32_t h = 0;
		size_t end = flat ? i + 1 : decode(b->nodes, b->count, i, &h);
		assert_int_equal(b->nodes[i].escape, end);
		assert_int_equal(b->nodes[i].level, h);
		/* Tight bounds over the slots of all leaves in [i, end). */
		float lo[3], hi[3], l2[3], h2[3];
		box_of_slots(m, b->order, 0, 0, lo, hi);
		for (size_t j = i; j < end; j++) {
			if (b->nodes[j].level != 0)
				continue;
			box_of_slots(m, b->order, b->nodes[j].first, b->nodes[j].count, l2, h2);
			for (int a = 0; a < 3; a++) {
				lo[a] = l2[a] < lo[a] ? l2[a] : lo[a];
				hi[a] = h2[a] > hi[a] ? h2[a] : hi[a];
			}
		}
		assert_memory_equal(lo, b->nodes[i].lo, sizeof lo);
		assert_memory_equal(hi, b->nodes[i].hi, sizeof hi);
	}
	if (!flat && b->count) {
		uint32_t h;
		assert_int_equal(decode(b->nodes, b->count, 0, &h), b->count); /* one root */
	}
}

static void assert_permutation(const uint32_t *order, size_t n)
{
	unsigned char *seen = calloc(n + 1, 1);
	for (size_t i = 0; i < n; i++) {
		assert_true(order[i] < n);
		assert_false(seen[order[i]]);
		seen[order[i]] = 1;
	}
	free(seen);
}

static const size_t sizes[] = {1,   2,   3,   4,    5,    7,    8,    9,   15,  16,
                               17,  31,  32,  33,   63,   64,   65,   127, 128, 129,
                               255, 256, 257, 1000, 1023, 1024, 1025, 4097};
#define NSIZES (sizeof sizes / sizeof sizes[0])

static void check_builder(enum rs_bvh_builder builder)
{
	for (size_t k = 0; k < NSIZES; k++) {
		struct mesh m = random_mesh(sizes[k]);
		struct built b = build(builder, &m);
		struct rs_error err;
		enum rs_status s =
		    rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err);
		if (s != RS_OK)
			fail_msg("%s n=%zu: %s", rs_bvh_builder_name(builder), sizes[k],
			         err.message);
		assert_permutation(b.order, m.tris);
		assert_definition(&b, &m, builder == RS_BVH_NONE || builder == RS_BVH_LINEAR);
		built_free(&b);
		mesh_free(&m);
	}
}

static void none_layout_matches_definition(void **state)
{
	check_builder(RS_BVH_NONE);
}
static void linear_layout_matches_definition(void **state)
{
	check_builder(RS_BVH_LINEAR);
}
static void paper_layout_matches_definition(void **state)
{
	check_builder(RS_BVH_PAPER);
}
static void sah_layout_matches_definition(void **state)
{
	check_builder(RS_BVH_SAH);
}

/* The paper tree in closed form: 2^k leaves, node (L, j) covers input triangles
 * [j 2^L, (j+1) 2^L), escape = i + 2^(L+1) - 1 (the corrected formula 2). */
static void paper_matches_closed_form(void **state)
{
	for (size_t k = 0; k < NSIZES; k++) {
		struct mesh m = random_mesh(sizes[k]);
		struct built b = build(RS_BVH_PAPER, &m);
		size_t leaves = 1;
		while (leaves < m.tris)
			leaves <<= 1;
		assert_int_equal(b.count, 2 * leaves - 1);
		for (size_t i = 0; i < b.count; i++) {
			const struct rs_bvh_node *n = &b.nodes[i];
			assert_int_equal(n->escape, i + ((size_t)2 << n->level) - 1);
			size_t a = (size_t)n->order << n->level, e = a + ((size_t)1 << n->level);
			if (n->level == 0) {
				assert_int_equal(n->first, a < m.tris ? a : 0);
				assert_int_equal(n->count, a < m.tris ? 1 : 0);
			}
			e = e < m.tris ? e : m.tris;
			float lo[3], hi[3];
			box_of_slots(&m, b.order, (uint32_t)(a < e ? a : 0),
			             (uint32_t)(a < e ? e - a : 0), lo, hi);
			assert_memory_equal(lo, n->lo, sizeof lo);
			assert_memory_equal(hi, n->hi, sizeof hi);
		}
		for (size_t t = 0; t < m.tris; t++)
			assert_int_equal(b.order[t], t); /* input order kept */
		built_free(&b);
		mesh_free(&m);
	}
}

static void linear_boxes_hold_consecutive_eights(void **state)
{
	struct mesh m = random_mesh(1001);
	struct built b = build(RS_BVH_LINEAR, &m);
	assert_int_equal(b.count, 126);
	for (size_t i = 0; i < b.count; i++) {
		assert_int_equal(b.nodes[i].first, 8 * i);
		assert_int_equal(b.nodes[i].count, i + 1 < b.count ? 8 : 1);
	}
	built_free(&b);
	mesh_free(&m);
}

static void sah_leaves_respect_leaf_size(void **state)
{
	struct mesh m = random_mesh(5000);
	struct built b = build(RS_BVH_SAH, &m);
	for (size_t i = 0; i < b.count; i++)
		if (b.nodes[i].level == 0)
			assert_true(b.nodes[i].count >= 1 && b.nodes[i].count <= 4);
	built_free(&b);
	mesh_free(&m);
}

/* All centroids equal: binning finds no plane; the builder must still split to leaf_size
 * and produce a valid tree. */
static void sah_handles_coincident_triangles(void **state)
{
	struct mesh m = random_mesh(777);
	for (size_t t = 0; t < m.tris; t++)
		memcpy(&m.pos[9 * t], &m.pos[0], 9 * sizeof(float));
	struct built b = build(RS_BVH_SAH, &m);
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, NULL),
	                 RS_OK);
	assert_definition(&b, &m, 0);
	built_free(&b);
	mesh_free(&m);
}

/* A floor far larger than the mesh (the shape that makes the SAH builder put large
 * triangles aside): the tree stays valid and the floor triangles end up in a subtree of
 * their own, so their box does not pollute the boxes of the small ones. */
static void sah_keeps_a_large_floor_apart(void **state)
{
	struct mesh m = random_mesh(2000);
	/* A floor ten times wider than the mesh, under it: a fan of 4 triangles around
	 * (50, -1, 50), like the stage under the cow herd. */
	const float corner[5][2] = {
	    {-450, -450}, {550, -450}, {550, 550}, {-450, 550}, {-450, -450}};
	for (size_t t = 0; t < 4; t++) {
		const float q[9] = {50,
		                    -1,
		                    50,
		                    corner[t][0],
		                    -1,
		                    corner[t][1],
		                    corner[t + 1][0],
		                    -1,
		                    corner[t + 1][1]};
		memcpy(&m.pos[9 * t], q, sizeof q);
	}
	struct built b = build(RS_BVH_SAH, &m);
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, NULL),
	                 RS_OK);
	assert_definition(&b, &m, 0);
	int found = 0;
	for (size_t c = 0; c < b.count; c++) {
		size_t tris = 0, large = 0;
		for (size_t j = c; j < b.nodes[c].escape; j++)
			for (uint32_t sl = b.nodes[j].first;
			     sl < b.nodes[j].first + b.nodes[j].count; sl++) {
				tris++;
				large += b.order[sl] < 4;
			}
		found |= tris == 4 && large == 4;
	}
	assert_true(found);
	built_free(&b);
	mesh_free(&m);
}

static void sah_costs_less_than_paper(void **state)
{
	struct mesh m = random_mesh(4096);
	struct built sah = build(RS_BVH_SAH, &m), paper = build(RS_BVH_PAPER, &m);
	struct rs_bvh_stats s1, s2;
	rs_bvh_stats(sah.nodes, sah.count, 1.0f, &s1);
	rs_bvh_stats(paper.nodes, paper.count, 1.0f, &s2);
	assert_true(s1.sah_cost < s2.sah_cost);
	assert_int_equal(s2.depth, 13);
	assert_int_equal(s2.nodes, 8191);
	assert_int_equal(s2.leaves, 4096);
	built_free(&sah);
	built_free(&paper);
	mesh_free(&m);
}

/* NONE: one box; a ray meeting it tests it and every triangle. */
static void none_stats_cost_is_one_box_plus_all_triangles(void **state)
{
	struct mesh m = random_mesh(100);
	struct built b = build(RS_BVH_NONE, &m);
	struct rs_bvh_stats s;
	rs_bvh_stats(b.nodes, b.count, 1.0f, &s);
	assert_int_equal(b.count, 1);
	assert_true(fabs(s.sah_cost - 101.0) < 1e-9);
	built_free(&b);
	mesh_free(&m);
}

/* Coordinates near FLT_MAX (sums overflow float) and near FLT_MIN still give valid trees
 * from every builder. */
static void builders_survive_extreme_coordinates(void **state)
{
	const float scales[2] = {3e36f, 1e-36f};
	for (int k = 0; k < 2; k++) {
		struct mesh m = random_mesh(500);
		for (size_t i = 0; i < 9 * m.tris; i++)
			m.pos[i] = (m.pos[i] - 50.0f) * scales[k];
		for (int b = 0; b <= RS_BVH_PAPER; b++) {
			struct built bt = build((enum rs_bvh_builder)b, &m);
			assert_int_equal(
			    rs_bvh_check(bt.nodes, bt.count, m.pos, m.idx, bt.order, m.tris, NULL),
			    RS_OK);
			built_free(&bt);
		}
		mesh_free(&m);
	}
}

static void check_catches_corruption(void **state)
{
	struct mesh m = random_mesh(300);
	struct built b = build(RS_BVH_SAH, &m);
	struct rs_error err;
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_OK);

	b.nodes[0].escape--;
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_ERR_BAD_DATA);
	b.nodes[0].escape++;

	size_t leaf = 0;
	while (b.nodes[leaf].level != 0)
		leaf++;
	float keep = b.nodes[leaf].hi[1];
	b.nodes[leaf].hi[1] = b.nodes[leaf].lo[1];
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_ERR_BAD_DATA);
	b.nodes[leaf].hi[1] = keep;

	uint32_t o = b.order[1];
	b.order[1] = b.order[0];
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_ERR_BAD_DATA);
	b.order[1] = o;

	b.nodes[1].order += 1;
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_ERR_BAD_DATA);
	b.nodes[1].order -= 1;
	assert_int_equal(rs_bvh_check(b.nodes, b.count, m.pos, m.idx, b.order, m.tris, &err),
	                 RS_OK);
	built_free(&b);
	mesh_free(&m);
}

static void build_rejects_bad_input(void **state)
{
	struct mesh m = random_mesh(10);
	struct rs_bvh_desc d = {0};
	struct rs_bvh_node nodes[32];
	uint32_t order[10];
	size_t count = 99;
	struct rs_error err;
	m.pos[4] = NAN;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_BAD_DATA);
	assert_int_equal(count, 0);
	m.pos[4] = 1.0f;
	m.idx[7] = (uint32_t)m.verts;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_BAD_DATA);
	m.idx[7] = 0;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 18, order, &count, &err),
	    RS_ERR_INVALID);
	d.sah_bins = 1;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_INVALID);
	d.sah_bins = 0;
	d.builder = (enum rs_bvh_builder)9;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_INVALID);
	d.builder = RS_BVH_SAH;
	d.traversal_cost = -1.0f;
	assert_int_equal(
	    rs_bvh_build(&d, m.pos, m.verts, m.idx, m.tris, nodes, 32, order, &count, &err),
	    RS_ERR_INVALID);
	mesh_free(&m);
}

static void zero_triangles_give_zero_nodes(void **state)
{
	size_t count = 5;
	assert_int_equal(rs_bvh_build(NULL, NULL, 0, NULL, 0, NULL, 0, NULL, &count, NULL), RS_OK);
	assert_int_equal(count, 0);
	assert_int_equal(rs_bvh_check(NULL, 0, NULL, NULL, NULL, 0, NULL), RS_OK);
}

static void names_and_defaults(void **state)
{
	enum rs_bvh_builder b;
	for (int i = 0; i <= RS_BVH_PAPER; i++) {
		assert_int_equal(
		    rs_bvh_builder_parse(rs_bvh_builder_name((enum rs_bvh_builder)i), &b, NULL),
		    RS_OK);
		assert_int_equal(b, i);
	}
	assert_int_equal(rs_bvh_builder_parse("kd", &b, NULL), RS_ERR_INVALID);
	struct rs_bvh_desc d;
	rs_bvh_desc_resolve(NULL, &d);
	assert_int_equal(d.builder, RS_BVH_SAH);
	assert_int_equal(d.leaf_size, 4);
	assert_int_equal(d.sah_bins, 16);
	assert_true(d.traversal_cost == 1.0f);
	rs_bvh_desc_resolve(&(struct rs_bvh_desc){.builder = RS_BVH_LINEAR}, &d);
	assert_int_equal(d.leaf_size, 8);
	assert_int_equal(rs_bvh_node_bound(&(struct rs_bvh_desc){.builder = RS_BVH_PAPER}, 5), 15);
	assert_int_equal(rs_bvh_node_bound(&(struct rs_bvh_desc){.builder = RS_BVH_LINEAR}, 17), 3);
	assert_int_equal(rs_bvh_node_bound(&(struct rs_bvh_desc){.builder = RS_BVH_NONE}, 17), 1);
	assert_int_equal(rs_bvh_node_bound(NULL, 17), 33);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(none_layout_matches_definition),
	    cmocka_unit_test(linear_layout_matches_definition),
	    cmocka_unit_test(paper_layout_matches_definition),
	    cmocka_unit_test(sah_layout_matches_definition),
	    cmocka_unit_test(paper_matches_closed_form),
	    cmocka_unit_test(linear_boxes_hold_consecutive_eights),
	    cmocka_unit_test(sah_leaves_respect_leaf_size),
	    cmocka_unit_test(sah_handles_coincident_triangles),
	    cmocka_unit_test(sah_keeps_a_large_floor_apart),
	    cmocka_unit_test(sah_costs_less_than_paper),
	    cmocka_unit_test(none_stats_cost_is_one_box_plus_all_triangles),
	    cmocka_unit_test(builders_survive_extreme_coordinates),
	    cmocka_unit_test(check_catches_corruption),
	    cmocka_unit_test(build_rejects_bad_input),
	    cmocka_unit_test(zero_triangles_give_zero_nodes),
	    cmocka_unit_test(names_and_defaults),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
