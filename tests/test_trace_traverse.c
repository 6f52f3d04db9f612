/* rs_trace part 1, traversal: closest-hit and any-hit through the packed BVH of every
 * builder against brute force, the paper's hit counting, skip_slot and the ray interval,
 * axis-parallel rays, scaled and offset scenes, degenerate triangles, and watertightness:
 * over 10^6 rays from inside closed meshes aimed at their vertices and edges. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_trace.h"

static uint64_t rng_state = 0xda942042e4dd58b5ull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

static const enum rs_bvh_builder builders[4] = {RS_BVH_NONE, RS_BVH_LINEAR, RS_BVH_PAPER,
                                                RS_BVH_SAH};

struct world {
	struct rs_scene *scene;
	struct rs_packed packed;
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t node_count;
};

static struct world make_world_packed(const float *pos, size_t verts, const uint32_t *idx,
                                      size_t tris, enum rs_bvh_builder builder,
                                      struct rs_pack_desc pd)
{
	struct world w = {0};
	struct rs_error err;
	uint32_t mat;
	assert_int_equal(rs_scene_create(NULL, &w.scene, &err), RS_OK);
	assert_int_equal(rs_scene_add_material(w.scene, &(struct rs_material){0}, &mat, NULL),
	                 RS_OK);
	struct rs_mesh_desc md = {.positions = pos,
	                          .vertex_count = verts,
	                          .indices = idx,
	                          .triangle_count = tris,
	                          .material = mat};
	if (rs_scene_add_mesh(w.scene, &md, &err) != RS_OK)
		fail_msg("add mesh: %s", err.message);
	struct rs_bvh_desc d = {.builder = builder};
	size_t cap = rs_bvh_node_bound(&d, tris);
	w.nodes = malloc(cap * sizeof *w.nodes);
	w.order = malloc(tris * sizeof *w.order);
	assert_int_equal(rs_bvh_build(&d, rs_scene_positions(w.scene),
	                              rs_scene_vertex_count(w.scene), rs_scene_indices(w.scene),
	                              tris, w.nodes, cap, w.order, &w.node_count, &err),
	                 RS_OK);
	assert_int_equal(rs_pack_layout(&pd, w.node_count, tris, 1, &w.packed, &err), RS_OK);
	assert_int_equal(rs_pack_alloc(&w.packed, &err), RS_OK);
	assert_int_equal(rs_pack_scene(w.scene, w.nodes, w.node_count, w.order, &w.packed, &err),
	                 RS_OK);
	return w;
}

/* Packed with the defaults: compact nodes, six directional orders. */
static struct world make_world(const float *pos, size_t verts, const uint32_t *idx, size_t tris,
                               enum rs_bvh_builder builder)
{
	return make_world_packed(pos, verts, idx, tris, builder, (struct rs_pack_desc){0});
}

static void free_world(struct world *w)
{
	rs_pack_free(&w->packed);
	free(w->nodes);
	free(w->order);
	rs_scene_destroy(&w->scene);
}

struct mesh {
	float *pos;
	uint32_t *idx;
	size_t verts, tris;
};

static struct mesh random_mesh(size_t tris, double scale, double offset)
{
	struct mesh m = {malloc(9 * tris * sizeof(float)), malloc(3 * tris * sizeof(uint32_t)),
	                 3 * tris, tris};
	for (size_t t = 0; t < tris; t++) {
		/* Coordinates on a 1/64 grid within +-64: exact in float even + 1e4. */
		double c[3] = {floor(rnd() * 4096) / 64 - 32, floor(rnd() * 4096) / 64 - 32,
		               floor(rnd() * 4096) / 64 - 32};
		for (int k = 0; k < 3; k++) {
			for (int a = 0; a < 3; a++) {
				double p = c[a] + floor((rnd() - 0.5) * 256) / 64;
				m.pos[9 * t + 3 * k + a] = (float)(p * scale + offset);
			}
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

/* Half the rays are aimed at a random point of a random triangle of m (so most hit
 * something, not necessarily that triangle), half go anywhere. */
static struct rs_ray random_ray_at(const struct mesh *m)
{
	struct rs_ray r = {{0}, {0}, 0.0, INFINITY, RS_NO_SLOT};
	for (int a = 0; a < 3; a++) {
		r.origin[a] = rnd() * 100 - 50;
		r.dir[a] = rnd() * 2 - 1;
	}
	if (m && rnd() < 0.5) {
		const float *p = &m->pos[9 * (size_t)(rnd() * (double)m->tris)];
		double b1 = rnd(), b2 = rnd() * (1 - b1);
		for (int a = 0; a < 3; a++)
			r.dir[a] = p[a] + b1 * ((double)p[3 + a] - p[a]) +
			           b2 * ((double)p[6 + a] - p[a]) - r.origin[a];
	}
	return r;
}

/* Same closest hit: the same triangle at the bit-identical t (the same code computes it),
 * or a different triangle at a t within 1e-12 relative (a genuine tie at a shared point). */
static void assert_same_hit(bool h1, const struct rs_hit *a, bool h2, const struct rs_hit *b)
{
	assert_int_equal(h1, h2);
	if (!h1)
		return;
	if (a->triangle == b->triangle)
		assert_true(a->t == b->t && a->u == b->u && a->v == b->v);
	else
		assert_true(fabs(a->t - b->t) <= 1e-12 * fabs(a->t));
}

static void closest_and_any_match_brute_force(void **state)
{
	struct mesh m = random_mesh(1500, 1.0, 0.0);
	for (int b = 0; b < 4; b++) {
		struct world w = make_world(m.pos, m.verts, m.idx, m.tris, builders[b]);
		int hits = 0;
		for (int i = 0; i < 4000; i++) {
			struct rs_ray r = random_ray_at(&m);
			enum rs_triangle_test test =
			    i & 1 ? RS_TRIANGLE_WATERTIGHT : RS_TRIANGLE_MOLLER_TRUMBORE;
			struct rs_hit h1, h2;
			bool a = rs_trace_closest(&w.packed, test, &r, &h1, NULL);
			bool c = rs_trace_closest_brute(&w.packed, test, &r, &h2);
			assert_same_hit(a, &h1, c, &h2);
			hits += a;
			/* Shadow feeler towards a point at a random fraction of the way. */
			r.tmax = rnd() * 120;
			bool occ = rs_trace_occluded(&w.packed, test, &r, NULL);
			c = rs_trace_closest_brute(&w.packed, test, &r, &h2);
			assert_int_equal(occ, c);
		}
		assert_true(hits > 400);
		free_world(&w);
	}
	mesh_free(&m);
}

/* Counting as the paper: NONE tests its one box, then every triangle. */
static void none_counts_one_box_and_every_triangle(void **state)
{
	struct mesh m = random_mesh(300, 1.0, 0.0);
	struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_NONE);
	struct rs_trace_counters c = {0};
	struct rs_ray r = {{0, 0, 0}, {0.3, 0.2, 0.1}, 0, INFINITY, RS_NO_SLOT}; /* from inside */
	struct rs_hit h;
	rs_trace_closest(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &r, &h, &c);
	assert_int_equal(c.box_tests, 1);
	assert_int_equal(c.triangle_tests, 300);
	r.skip_slot = 7; /* a skipped slot is neither tested nor counted */
	rs_trace_closest(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &r, &h, &c);
	assert_int_equal(c.box_tests, 2);
	assert_int_equal(c.triangle_tests, 599);
	struct rs_ray away = {{500, 500, 500}, {1, 1, 1}, 0, INFINITY, RS_NO_SLOT};
	rs_trace_closest(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &away, &h, &c);
	assert_int_equal(c.box_tests, 3);
	assert_int_equal(c.triangle_tests, 599);
	free_world(&w);
	mesh_free(&m);
}

/* LINEAR tests every box of the list; a ray meeting none tests no triangle. */
static void linear_counts_every_box(void **state)
{
	struct mesh m = random_mesh(1001, 1.0, 0.0);
	struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_LINEAR);
	struct rs_trace_counters c = {0};
	struct rs_ray away = {{500, 500, 500}, {1, 1, 1}, 0, INFINITY, RS_NO_SLOT};
	rs_trace_occluded(&w.packed, RS_TRIANGLE_WATERTIGHT, &away, &c);
	assert_int_equal(c.box_tests, 126);
	assert_int_equal(c.triangle_tests, 0);
	memset(&c, 0, sizeof c);
	struct rs_ray r = {{0, 0, 0}, {0.3, 0.2, 0.1}, 0, INFINITY, RS_NO_SLOT};
	struct rs_hit h;
	rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, &h, &c);
	assert_int_equal(c.box_tests, 126);
	assert_true(c.triangle_tests >= 1 && c.triangle_tests <= 1001);
	free_world(&w);
	mesh_free(&m);
}

/* A tree: a ray missing the root tests one box only. */
static void tree_miss_costs_one_box(void **state)
{
	struct mesh m = random_mesh(1000, 1.0, 0.0);
	for (int b = 2; b < 4; b++) {
		struct world w = make_world(m.pos, m.verts, m.idx, m.tris, builders[b]);
		struct rs_trace_counters c = {0};
		struct rs_ray away = {{500, 500, 500}, {1, 1, 1}, 0, INFINITY, RS_NO_SLOT};
		assert_false(rs_trace_occluded(&w.packed, RS_TRIANGLE_WATERTIGHT, &away, &c));
		assert_int_equal(c.box_tests, 1);
		assert_int_equal(c.triangle_tests, 0);
		free_world(&w);
	}
	mesh_free(&m);
}

/* skip_slot: a ray leaving a triangle's surface does not hit that triangle again. */
static void skip_slot_ignores_the_origin_triangle(void **state)
{
	struct mesh m = random_mesh(500, 1.0, 0.0);
	struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_SAH);
	int checked = 0;
	for (int i = 0; i < 2000; i++) {
		struct rs_ray r = random_ray_at(&m);
		struct rs_hit h, h2;
		if (!rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, &h, NULL) ||
		    fmin(fmin(h.u, h.v), 1 - h.u - h.v) < 1e-6)
			continue; /* near an edge the restart point may fall just outside */
		/* Start exactly on the hit point, going back along the ray: without the skip
		 * the start triangle is met again at t ~ 0. */
		struct rs_ray back = {{0}, {0}, -1e-9, INFINITY, h.slot};
		for (int a = 0; a < 3; a++) {
			back.origin[a] = r.origin[a] + h.t * r.dir[a];
			back.dir[a] = -r.dir[a];
		}
		bool hit = rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &back, &h2, NULL);
		if (hit)
			assert_int_not_equal(h2.slot, h.slot);
		assert_int_equal(
		    hit, rs_trace_closest_brute(&w.packed, RS_TRIANGLE_WATERTIGHT, &back, &h2));
		back.skip_slot = RS_NO_SLOT;
		assert_true(rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &back, &h2, NULL));
		if (!(fabs(h2.t) < 1e-9))
			fail_msg("ray %d: restart met slot %u at t %g (left slot %u)", i, h2.slot,
			         h2.t, h.slot);
		checked++;
	}
	assert_true(checked > 100);
	free_world(&w);
	mesh_free(&m);
}

static void interval_bounds_the_hit(void **state)
{
	struct mesh m = random_mesh(800, 1.0, 0.0);
	struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_SAH);
	for (int i = 0; i < 2000; i++) {
		struct rs_ray r = random_ray_at(&m);
		r.tmin = rnd() * 30;
		r.tmax = r.tmin + rnd() * 60;
		struct rs_hit h, h2;
		bool a = rs_trace_closest(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &r, &h, NULL);
		bool b = rs_trace_closest_brute(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &r, &h2);
		assert_same_hit(a, &h, b, &h2);
		if (a)
			assert_true(h.t > r.tmin && h.t < r.tmax);
		assert_int_equal(
		    a, rs_trace_occluded(&w.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &r, NULL));
	}
	free_world(&w);
	mesh_free(&m);
}

/* Rays along the axes and in axis planes (inverse direction +-inf, origins on box planes
 * since both lie on the same 1/64 grid). */
static void axis_parallel_rays_match_brute_force(void **state)
{
	struct mesh m = random_mesh(1000, 1.0, 0.0);
	for (int b = 0; b < 4; b++) {
		struct world w = make_world(m.pos, m.verts, m.idx, m.tris, builders[b]);
		for (int i = 0; i < 3000; i++) {
			struct rs_ray r = {{0}, {0}, 0.0, INFINITY, RS_NO_SLOT};
			for (int a = 0; a < 3; a++)
				r.origin[a] = floor(rnd() * 4096) / 64 - 32;
			int axis = i % 3;
			r.dir[axis] = i & 4 ? 1.0 : -1.0;
			if (i & 8)
				r.dir[(axis + 1) % 3] = i & 16 ? -0.0 : 0.5;
			struct rs_hit h1, h2;
			bool a1 =
			    rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, &h1, NULL);
			bool a2 =
			    rs_trace_closest_brute(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, &h2);
			assert_same_hit(a1, &h1, a2, &h2);
		}
		free_world(&w);
	}
	mesh_free(&m);
}

/* True when the ray meets the triangle at less than ~3 degrees, where float rounding of
 * the scaled vertices moves t by more than the tolerance below. */
static bool grazing(const struct mesh *m, uint32_t tri, const double d[3])
{
	const float *p = &m->pos[9 * (size_t)tri];
	double e1[3], e2[3];
	for (int a = 0; a < 3; a++) {
		e1[a] = (double)p[3 + a] - p[a];
		e2[a] = (double)p[6 + a] - p[a];
	}
	double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
	               e1[0] * e2[1] - e1[1] * e2[0]};
	double dn = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
	double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	double dd = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	return fabs(dn) < 0.05 * nn * dd;
}

/* The same grid scene scaled by 1e-4 and 1e4 and offset by 1e4 gives the same triangles;
 * t scales with the coordinates (directions are kept). Tolerance: the scaled coordinates
 * are rounded to float (2^-24 relative), amplified by the hit geometry: 1e-5 relative. */
static void scaled_and_offset_scenes_agree(void **state)
{
	const double scales[3] = {1e-4, 1e4, 1.0}, offsets[3] = {0.0, 0.0, 1e4};
	struct mesh base = random_mesh(1000, 1.0, 0.0);
	struct world w0 = make_world(base.pos, base.verts, base.idx, base.tris, RS_BVH_SAH);
	for (int k = 0; k < 3; k++) {
		uint64_t seed = rng_state;
		struct mesh m = random_mesh(1000, 1.0, 0.0); /* same grid values, rescaled below */
		memcpy(m.pos, base.pos, 9 * base.tris * sizeof(float));
		for (size_t i = 0; i < 9 * m.tris; i++)
			m.pos[i] = (float)(base.pos[i] * scales[k] + offsets[k]);
		struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_SAH);
		int compared = 0;
		for (int i = 0; i < 3000; i++) {
			struct rs_ray r = random_ray_at(&base);
			struct rs_ray rs = r;
			for (int a = 0; a < 3; a++)
				rs.origin[a] = r.origin[a] * scales[k] + offsets[k];
			struct rs_hit h0, h1;
			bool a0 =
			    rs_trace_closest(&w0.packed, RS_TRIANGLE_WATERTIGHT, &r, &h0, NULL);
			bool a1 =
			    rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &rs, &h1, NULL);
			/* Skip rays within 1e-4 of an edge, where float rounding may flip them. */
			if (a0 && fmin(fmin(h0.u, h0.v), 1 - h0.u - h0.v) < 1e-4)
				continue;
			if (a1 && fmin(fmin(h1.u, h1.v), 1 - h1.u - h1.v) < 1e-4)
				continue;
			assert_int_equal(a0, a1);
			if (!a0 || grazing(&base, h0.triangle, r.dir))
				continue;
			assert_int_equal(h0.triangle, h1.triangle);
			/* plus: packing rounds positions relative to the scene's centre
			 * (docs/tracer.md R1), half a float ulp of the half-size (~70 s) */
			assert_true(fabs(h1.t - h0.t * scales[k]) <=
			            1e-5 * h0.t * scales[k] + 1e-6 * 128 * scales[k]);
			compared++;
		}
		assert_true(compared > 500);
		free_world(&w);
		mesh_free(&m);
		rng_state = seed;
	}
	free_world(&w0);
	mesh_free(&base);
}

static void degenerate_triangles_in_a_scene_never_hit(void **state)
{
	struct mesh m = random_mesh(400, 1.0, 0.0);
	/* Every other triangle collapsed to a segment (two coincident vertices). */
	for (size_t t = 0; t < m.tris; t += 2) {
		float *p = &m.pos[9 * t];
		for (int a = 0; a < 3; a++)
			p[6 + a] = t % 4 ? p[a] : p[3 + a];
	}
	for (int b = 0; b < 4; b++) {
		struct world w = make_world(m.pos, m.verts, m.idx, m.tris, builders[b]);
		for (int i = 0; i < 3000; i++) {
			struct rs_ray r = random_ray_at(&m);
			if (i % 2) { /* aim exactly at a vertex of a degenerate triangle */
				const float *p = &m.pos[9 * (size_t)(2 * (i % 200))];
				for (int a = 0; a < 3; a++)
					r.dir[a] = (double)p[a] - r.origin[a];
			}
			for (int k = 0; k < 2; k++) {
				struct rs_hit h;
				if (rs_trace_closest(&w.packed, (enum rs_triangle_test)k, &r, &h,
				                     NULL)) {
					assert_true(h.triangle % 2 == 1);
					assert_true(isfinite(h.t) && isfinite(h.u) &&
					            isfinite(h.v));
				}
			}
		}
		free_world(&w);
	}
	mesh_free(&m);
}

static void unusable_rays_miss(void **state)
{
	struct mesh m = random_mesh(50, 1.0, 0.0);
	struct world w = make_world(m.pos, m.verts, m.idx, m.tris, RS_BVH_SAH);
	struct rs_ray bad[3] = {{{0, 0, 0}, {0, 0, 0}, 0, INFINITY, RS_NO_SLOT},
	                        {{NAN, 0, 0}, {1, 0, 0}, 0, INFINITY, RS_NO_SLOT},
	                        {{0, 0, 0}, {1, INFINITY, 0}, 0, INFINITY, RS_NO_SLOT}};
	for (int i = 0; i < 3; i++) {
		struct rs_hit h;
		assert_false(
		    rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &bad[i], &h, NULL));
		assert_int_equal(h.slot, RS_NO_SLOT);
		assert_false(rs_trace_occluded(&w.packed, RS_TRIANGLE_WATERTIGHT, &bad[i], NULL));
	}
	free_world(&w);
	mesh_free(&m);
}

/* ---- counting ------------------------------------------------------------------------ */

/* Reference walk: recursive depth-first over the unpacked nodes, children found from the
 * leaf/interior flags alone (a full binary tree is determined by its pre-order flags),
 * triangles read from the scene arrays. Returns the end of i's subtree. */
struct ref_walk {
	const struct world *w;
	struct rs_ray ray; /* in the packed frame: bounds and vertices are read from packed */
	double inv[3];
	uint64_t boxes, tris;
	bool found;
	double t;
};

static size_t ref_visit(struct ref_walk *rw, size_t i)
{
	const struct rs_bvh_node *n = &rw->w->nodes[i];
	/* Subtree end by decoding (an interior node opens two subtrees, a leaf closes one),
	 * without reading escapes. */
	size_t end = i, open = 1;
	while (open) {
		open = rw->w->nodes[end].level > 0 ? open + 1 : open - 1;
		end++;
	}
	rw->boxes++;
	struct rs_pack_node box; /* only its bounds: the topology comes from the BVH */
	rs_pack_read_node(&rw->w->packed, (uint32_t)i, &box);
	if (!rs_intersect_box(box.lo, box.hi, rw->ray.origin, rw->inv, rw->ray.tmin, rw->ray.tmax))
		return end;
	if (n->level > 0) {
		size_t c = ref_visit(rw, i + 1);
		ref_visit(rw, c);
		return end;
	}
	for (uint32_t s = n->first; s < n->first + n->count; s++) {
		double v[3][3], t, u, w;
		for (uint32_t k = 0; k < 3; k++)
			for (int a = 0; a < 3; a++)
				v[k][a] = rs_pack_texel(&rw->w->packed.triangles,
				                        RS_PACK_TRIANGLE_TEXELS, s, k)[a];
		rw->tris++;
		if (rs_intersect_triangle(RS_TRIANGLE_WATERTIGHT, v[0], v[1], v[2], &rw->ray, &t,
		                          &u, &w)) {
			rw->found = true;
			rw->t = t;
			rw->ray.tmax = t;
		}
	}
	return end;
}

/* The threaded walk of the packed textures counts exactly the tests of a depth-first walk
 * of the tree (same order, same tmax shrinking): the escapes implement the recursion. The
 * builder's own order (the directional ones are checked against it below and in
 * test_pack). */
static void counters_match_a_recursive_walk(void **state)
{
	struct mesh m = random_mesh(700, 1.0, 0.0);
	for (int b = 0; b < 4; b++) {
		struct world w =
		    make_world_packed(m.pos, m.verts, m.idx, m.tris, builders[b],
		                      (struct rs_pack_desc){.orders = RS_PACK_ORDERS_SINGLE});
		for (int i = 0; i < 2000; i++) {
			struct rs_ray r = random_ray_at(&m);
			struct ref_walk rw = {
			    &w,    r,  {1.0 / r.dir[0], 1.0 / r.dir[1], 1.0 / r.dir[2]}, 0, 0,
			    false, 0.0};
			for (int a = 0; a < 3; a++)
				rw.ray.origin[a] -= w.packed.origin[a];
			/* Flat builders are forests: walk each top-level leaf in turn. */
			for (size_t top = 0; top < w.node_count;)
				top = ref_visit(&rw, top);
			struct rs_trace_counters c = {0};
			struct rs_hit h;
			bool found =
			    rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, &h, &c);
			assert_int_equal(found, rw.found);
			if (found)
				assert_true(h.t == rw.t);
			assert_int_equal(c.box_tests, rw.boxes);
			assert_int_equal(c.triangle_tests, rw.tris);
		}
		free_world(&w);
	}
	mesh_free(&m);
}

/* Walking a ray's directional order (six) or octant order (eight) finds exactly the hit of
 * the builder's order (the closest-hit rule does not depend on visiting order, R4) for every
 * builder and format, and on this scene tests fewer boxes in all. */
static void node_orders_find_the_same_hits(void **state)
{
	struct mesh m = random_mesh(700, 1.0, 0.0);
	const enum rs_pack_orders orders[2] = {RS_PACK_ORDERS_DIRECTIONAL, RS_PACK_ORDERS_OCTANT};
	for (int b = 0; b < 4; b++)
		for (int k = 0; k < 4; k++) {
			enum rs_pack_nodes f = k % 2 ? RS_PACK_NODES_PAPER : RS_PACK_NODES_COMPACT;
			struct world one = make_world_packed(
			    m.pos, m.verts, m.idx, m.tris, builders[b],
			    (struct rs_pack_desc){.nodes = f, .orders = RS_PACK_ORDERS_SINGLE});
			struct world many = make_world_packed(
			    m.pos, m.verts, m.idx, m.tris, builders[b],
			    (struct rs_pack_desc){.nodes = f, .orders = orders[k / 2]});
			assert_int_equal(many.packed.node_orders, k / 2 ? 8 : 6);
			struct rs_trace_counters c1 = {0}, cn = {0};
			for (int i = 0; i < 2000; i++) {
				struct rs_ray r = random_ray_at(&m);
				struct rs_hit h1, hn;
				bool f1 = rs_trace_closest(&one.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                           &h1, &c1);
				bool fn = rs_trace_closest(&many.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                           &hn, &cn);
				assert_int_equal(f1, fn);
				if (f1) {
					assert_true(h1.t == hn.t);
					assert_int_equal(h1.triangle, hn.triangle);
				}
				assert_int_equal(
				    rs_trace_occluded(&one.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                      NULL),
				    rs_trace_occluded(&many.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                      NULL));
			}
			if (builders[b] == RS_BVH_SAH)
				assert_true(cn.box_tests < c1.box_tests);
			free_world(&one);
			free_world(&many);
		}
	mesh_free(&m);
}

/* ---- watertightness ------------------------------------------------------------------ */

struct closed {
	float *pos;
	uint32_t *idx;
	size_t verts, tris;
	uint32_t (*edges)[2];
	size_t edge_count;
};

static uint32_t midpoint(struct closed *c, uint32_t a, uint32_t b)
{
	uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
	for (size_t e = 0; e < c->edge_count; e++)
		if (c->edges[e][0] == lo && c->edges[e][1] == hi)
			return (uint32_t)(c->verts - c->edge_count + e);
	c->edges[c->edge_count][0] = lo;
	c->edges[c->edge_count][1] = hi;
	c->edge_count++;
	float *p = &c->pos[3 * c->verts];
	double q[3], len = 0;
	for (int k = 0; k < 3; k++) {
		q[k] = ((double)c->pos[3 * a + k] + c->pos[3 * b + k]) * 0.5;
		len += q[k] * q[k];
	}
	for (int k = 0; k < 3; k++)
		p[k] = (float)(q[k] / sqrt(len));
	return (uint32_t)c->verts++;
}

/* Icosphere: 20 * 4^levels triangles sharing vertices by index, radius 1. */
static struct closed icosphere(int levels)
{
	const double t = (1.0 + sqrt(5.0)) / 2.0;
	const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
	                         {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
	                         {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
	const uint32_t f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
	                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
	                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
	                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
	size_t max_tris = 20u << (2 * levels);
	struct closed c = {malloc(3 * (max_tris + 12) * sizeof(float)),
	                   malloc(3 * max_tris * sizeof(uint32_t)),
	                   12,
	                   20,
	                   NULL,
	                   0};
	double n = sqrt(1 + t * t);
	for (int i = 0; i < 12; i++)
		for (int k = 0; k < 3; k++)
			c.pos[3 * i + k] = (float)(v[i][k] / n);
	memcpy(c.idx, f, sizeof f);
	for (int l = 0; l < levels; l++) {
		uint32_t *next = malloc(3 * 4 * c.tris * sizeof(uint32_t));
		c.edges = malloc(3 * c.tris * sizeof *c.edges);
		c.edge_count = 0;
		size_t base_verts = c.verts;
		(void)base_verts;
		for (size_t i = 0; i < c.tris; i++) {
			uint32_t a = c.idx[3 * i], b = c.idx[3 * i + 1], d = c.idx[3 * i + 2];
			uint32_t ab = midpoint(&c, a, b), bd = midpoint(&c, b, d),
			         da = midpoint(&c, d, a);
			uint32_t q[4][3] = {{a, ab, da}, {b, bd, ab}, {d, da, bd}, {ab, bd, da}};
			memcpy(&next[12 * i], q, sizeof q);
		}
		free(c.edges);
		c.edges = NULL;
		free(c.idx);
		c.idx = next;
		c.tris *= 4;
	}
	return c;
}

/* Cube [-1, 1]^3, each face an n x n grid of quads split into two triangles. */
static struct closed grid_cube(int n)
{
	size_t per_face = (size_t)(n + 1) * (n + 1);
	struct closed c = {malloc(3 * 6 * per_face * sizeof(float)),
	                   malloc(3 * 12 * (size_t)n * n * sizeof(uint32_t)),
	                   0,
	                   0,
	                   NULL,
	                   0};
	for (int face = 0; face < 6; face++) {
		int axis = face / 2;
		double side = face % 2 ? -1.0 : 1.0;
		size_t base = c.verts;
		for (int i = 0; i <= n; i++)
			for (int j = 0; j <= n; j++) {
				float *p = &c.pos[3 * c.verts++];
				p[axis] = (float)side;
				p[(axis + 1) % 3] = (float)(-1.0 + 2.0 * i / n);
				p[(axis + 2) % 3] = (float)(-1.0 + 2.0 * j / n);
			}
		for (int i = 0; i < n; i++)
			for (int j = 0; j < n; j++) {
				uint32_t a = (uint32_t)(base + (size_t)i * (n + 1) + j);
				uint32_t b = a + 1, d = a + (uint32_t)(n + 1), e = d + 1;
				uint32_t *t = &c.idx[3 * c.tris];
				/* Alternate the diagonal so both diagonal directions occur. */
				if ((i + j) % 2) {
					uint32_t q[6] = {a, b, e, a, e, d};
					memcpy(t, q, sizeof q);
				} else {
					uint32_t q[6] = {a, b, d, b, e, d};
					memcpy(t, q, sizeof q);
				}
				c.tris += 2;
			}
	}
	return c;
}

/* Rays from inside aimed exactly at vertices (from the centre the direction is the
 * vertex itself, exactly), at points on edges, and at vertices from random interior
 * points. Every one must hit with the watertight test; returns the misses. */
static size_t count_misses(const struct closed *c, enum rs_triangle_test test, size_t rays,
                           double inner_radius)
{
	struct world w = make_world(c->pos, c->verts, c->idx, c->tris, RS_BVH_SAH);
	size_t misses = 0;
	for (size_t i = 0; i < rays; i++) {
		struct rs_ray r = {{0, 0, 0}, {0, 0, 0}, 0.0, INFINITY, RS_NO_SLOT};
		size_t tri = (size_t)(rnd() * (double)c->tris);
		int k = (int)(rnd() * 3);
		const float *p = &c->pos[3 * c->idx[3 * tri + k]];
		const float *q = &c->pos[3 * c->idx[3 * tri + (k + 1) % 3]];
		double target[3];
		int kind = (int)(i % 4);
		double s = kind == 1 ? 0.5 : rnd();
		for (int a = 0; a < 3; a++) {
			target[a] = kind == 0 || kind == 3 ? (double)p[a]
			                                   : p[a] + s * ((double)q[a] - p[a]);
			if (kind >= 2)
				r.origin[a] = (rnd() * 2 - 1) * inner_radius;
			r.dir[a] = target[a] - r.origin[a];
		}
		struct rs_hit h;
		misses += !rs_trace_closest(&w.packed, test, &r, &h, NULL);
	}
	free_world(&w);
	return misses;
}

/* Wide nodes find exactly the compact nodes' hits (the same triangle at the same t, R4) for
 * every builder, and on scenes far from the origin, tiny, huge and flat; on the SAH tree
 * they test about as many child boxes as the binary walk tests boxes (in a quarter of the
 * node fetches). */
static void wide_nodes_find_the_compact_hits(void **state)
{
	const struct {
		double scale, offset;
		bool flat;
	} shapes[] = {{1.0, 0.0, false},    {1.0, 1.0e6, false}, {1.0e-30, 0.0, false},
	              {1.0e30, 0.0, false}, {1.0, 0.0, true},    {1.0e-3, 55.5, true}};
	for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++)
		for (int b = 0; b < 4; b++) {
			if (k > 0 && builders[b] != RS_BVH_SAH)
				continue;
			struct mesh m = random_mesh(700, 1.0, 0.0);
			struct mesh g = random_mesh(700, 1.0, 0.0);
			for (size_t i = 0; i < 9 * m.tris; i++)
				g.pos[i] =
				    shapes[k].flat && i % 3 == 2
				        ? (float)shapes[k].offset
				        : (float)(m.pos[i] * shapes[k].scale + shapes[k].offset);
			struct world c = make_world(g.pos, g.verts, g.idx, g.tris, builders[b]);
			struct world w =
			    make_world_packed(g.pos, g.verts, g.idx, g.tris, builders[b],
			                      (struct rs_pack_desc){.nodes = RS_PACK_NODES_WIDE4});
			struct world one = make_world_packed(
			    g.pos, g.verts, g.idx, g.tris, builders[b],
			    (struct rs_pack_desc){.orders = RS_PACK_ORDERS_SINGLE});
			struct rs_trace_counters cc = {0}, cw = {0}, c1 = {0};
			int hits = 0;
			for (int i = 0; i < 1500; i++) {
				struct rs_ray r = random_ray_at(&m);
				for (int a = 0; a < 3; a++) {
					r.origin[a] =
					    r.origin[a] * shapes[k].scale + shapes[k].offset;
					if (shapes[k].flat && a == 2)
						r.origin[a] = shapes[k].offset +
						              (rnd() - 0.5) * 100 * shapes[k].scale;
				}
				if (shapes[k].flat && i % 2) { /* at a flat triangle's centre */
					const float *p =
					    &g.pos[9 * (size_t)(rnd() * (double)g.tris)];
					for (int a = 0; a < 3; a++)
						r.dir[a] =
						    ((double)p[a] + p[3 + a] + p[6 + a]) / 3 -
						    r.origin[a];
				}
				struct rs_hit hc, hw;
				bool fc = rs_trace_closest(&c.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                           &hc, &cc);
				bool fw = rs_trace_closest(&w.packed, RS_TRIANGLE_WATERTIGHT, &r,
				                           &hw, &cw);
				rs_trace_closest(&one.packed, RS_TRIANGLE_WATERTIGHT, &r, NULL,
				                 &c1);
				assert_int_equal(fc, fw);
				if (fc) {
					assert_true(hc.t == hw.t);
					assert_int_equal(hc.triangle, hw.triangle);
					hits++;
				}
				r.tmax = fc ? hc.t * rnd() * 1.5 : r.tmax;
				assert_int_equal(
				    rs_trace_occluded(&c.packed, RS_TRIANGLE_WATERTIGHT, &r, NULL),
				    rs_trace_occluded(&w.packed, RS_TRIANGLE_WATERTIGHT, &r, NULL));
			}
			assert_true(hits > 200);
			/* as many child-box tests as the binary walk's box tests, give or take */
			if (builders[b] == RS_BVH_SAH)
				assert_true(cw.box_tests < c1.box_tests * 11 / 10);
			free_world(&c);
			free_world(&w);
			free_world(&one);
			mesh_free(&m);
			mesh_free(&g);
		}
}

static void watertight_icosphere_has_no_misses(void **state)
{
	struct closed c = icosphere(3); /* 1280 triangles */
	size_t wt = count_misses(&c, RS_TRIANGLE_WATERTIGHT, 600000, 0.5);
	size_t mt = count_misses(&c, RS_TRIANGLE_MOLLER_TRUMBORE, 100000, 0.5);
	print_message("icosphere: watertight misses %zu of 600000; Moller-Trumbore %zu of 100000\n",
	              wt, mt);
	assert_int_equal(wt, 0);
	free(c.pos);
	free(c.idx);
}

static void watertight_grid_cube_has_no_misses(void **state)
{
	struct closed c = grid_cube(8); /* 768 triangles, coplanar neighbours */
	size_t wt = count_misses(&c, RS_TRIANGLE_WATERTIGHT, 500000, 0.9);
	size_t mt = count_misses(&c, RS_TRIANGLE_MOLLER_TRUMBORE, 100000, 0.9);
	print_message("grid cube: watertight misses %zu of 500000; Moller-Trumbore %zu of 100000\n",
	              wt, mt);
	assert_int_equal(wt, 0);
	free(c.pos);
	free(c.idx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(closest_and_any_match_brute_force),
	    cmocka_unit_test(none_counts_one_box_and_every_triangle),
	    cmocka_unit_test(linear_counts_every_box),
	    cmocka_unit_test(tree_miss_costs_one_box),
	    cmocka_unit_test(counters_match_a_recursive_walk),
	    cmocka_unit_test(node_orders_find_the_same_hits),
	    cmocka_unit_test(wide_nodes_find_the_compact_hits),
	    cmocka_unit_test(skip_slot_ignores_the_origin_triangle),
	    cmocka_unit_test(interval_bounds_the_hit),
	    cmocka_unit_test(axis_parallel_rays_match_brute_force),
	    cmocka_unit_test(scaled_and_offset_scenes_agree),
	    cmocka_unit_test(degenerate_triangles_in_a_scene_never_hit),
	    cmocka_unit_test(unusable_rays_miss),
	    cmocka_unit_test(watertight_icosphere_has_no_misses),
	    cmocka_unit_test(watertight_grid_cube_has_no_misses),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
