/* Shared by test_cowrays*.c: a Cow scene from rs_scenegen packed with a builder, a fixed
 * set of random rays with brute-force reference answers, and the comparison. Each
 * executable checks some builders so each stays well under a minute under ASan. */
#ifndef TEST_COWRAYS_COMMON_H
#define TEST_COWRAYS_COMMON_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_scenegen.h"
#include "raystream/rs_trace.h"

#define COW_RAYS 100000
/* Shadow feelers from the hits of every COW_FEELER_EVERY-th ray (each costs a brute
 * pass, so not from all of them). */
#define COW_FEELER_EVERY 3

static uint64_t cow_rng = 0x6a09e667f3bcc909ull;
static double cow_rnd(void)
{
	cow_rng ^= cow_rng << 13;
	cow_rng ^= cow_rng >> 7;
	cow_rng ^= cow_rng << 17;
	return (double)(cow_rng >> 11) / 9007199254740992.0;
}

struct cow_world {
	struct rs_packed packed;
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t node_count;
};

struct cow_ref {
	struct rs_ray ray;
	struct rs_hit hit;
	bool found;
	struct rs_ray feeler; /* tmax = 1 reaches the light; valid when has_feeler */
	bool has_feeler, occluded;
};

static struct rs_scene *cow_scene(uint32_t cows)
{
	struct rs_scenegen_desc d = {.kind = RS_SCENEGEN_COW, .cows = cows}; /* the shipped cow */
	struct rs_scene *scene = NULL;
	struct rs_error err;
	if (rs_scenegen_build(&d, &scene, &err) != RS_OK)
		fail_msg("scenegen: %s", err.message);
	return scene;
}

static struct cow_world cow_pack(const struct rs_scene *scene, enum rs_bvh_builder builder)
{
	struct cow_world w = {0};
	struct rs_error err;
	struct rs_bvh_desc d = {.builder = builder};
	size_t tris = rs_scene_triangle_count(scene);
	size_t cap = rs_bvh_node_bound(&d, tris);
	w.nodes = malloc(cap * sizeof *w.nodes);
	w.order = malloc(tris * sizeof *w.order);
	assert_int_equal(rs_bvh_build(&d, rs_scene_positions(scene), rs_scene_vertex_count(scene),
	                              rs_scene_indices(scene), tris, w.nodes, cap, w.order,
	                              &w.node_count, &err),
	                 RS_OK);
	assert_int_equal(rs_bvh_check(w.nodes, w.node_count, rs_scene_positions(scene),
	                              rs_scene_indices(scene), w.order, tris, &err),
	                 RS_OK);
	assert_int_equal(rs_pack_layout(NULL, w.node_count, tris, rs_scene_material_count(scene),
	                                &w.packed, &err),
	                 RS_OK);
	assert_int_equal(rs_pack_alloc(&w.packed, &err), RS_OK);
	assert_int_equal(rs_pack_scene(scene, w.nodes, w.node_count, w.order, &w.packed, &err),
	                 RS_OK);
	return w;
}

static void cow_world_free(struct cow_world *w)
{
	rs_pack_free(&w->packed);
	free(w->nodes);
	free(w->order);
}

static enum rs_triangle_test cow_test_of(size_t i)
{
	return i & 1 ? RS_TRIANGLE_WATERTIGHT : RS_TRIANGLE_MOLLER_TRUMBORE;
}

/* The reference: every triangle of the scene, straight from the scene arrays (so packing
 * and slot order are checked too), each tested with rs_intersect_triangle() unless the ray
 * misses the triangle's own bounding box grown by 1e-7 of the scene extent. That box test
 * is written here, independently of the BVH code, and is conservative by a wide margin
 * (rounding in it is ~1e-16 relative); it only makes brute force ~5x cheaper so the test
 * stays short. cow_check_reference() compares it with rs_trace_closest_brute(). */
struct cow_brute {
	size_t tris;
	double origin[3]; /* the packed frame (docs/tracer.md R1), as rs_pack_scene() sets it */
	double (*v)[3][3];
	double *lo[3], *hi[3]; /* boxes, one array per axis so the filter loop vectorises */
	unsigned char *pass;
};

static struct cow_brute cow_brute_make(const struct rs_scene *scene)
{
	struct cow_brute b = {rs_scene_triangle_count(scene), {0}, NULL, {0}, {0}, NULL};
	const double *pos = rs_scene_positions_f64(scene);
	const uint32_t *idx = rs_scene_indices(scene);
	struct rs_bounds sb;
	rs_scene_bounds(scene, &sb);
	for (int a = 0; a < 3; a++)
		b.origin[a] = 0.5 * (sb.lo[a] + sb.hi[a]);
	double margin = 0;
	for (int a = 0; a < 3; a++)
		margin = fmax(margin, 1e-7 * (fabs(sb.lo[a]) + fabs(sb.hi[a])));
	b.v = malloc(b.tris * sizeof *b.v);
	b.pass = malloc(b.tris);
	for (int a = 0; a < 3; a++) {
		b.lo[a] = malloc(b.tris * sizeof(double));
		b.hi[a] = malloc(b.tris * sizeof(double));
	}
	for (size_t t = 0; t < b.tris; t++) {
		for (int k = 0; k < 3; k++)
			for (int a = 0; a < 3; a++)
				b.v[t][k][a] = (float)(pos[3 * idx[3 * t + k] + a] - b.origin[a]);
		for (int a = 0; a < 3; a++) {
			b.lo[a][t] = fmin(b.v[t][0][a], fmin(b.v[t][1][a], b.v[t][2][a])) - margin;
			b.hi[a][t] = fmax(b.v[t][0][a], fmax(b.v[t][1][a], b.v[t][2][a])) + margin;
		}
	}
	return b;
}

static void cow_brute_free(struct cow_brute *b)
{
	free(b->v);
	free(b->pass);
	for (int a = 0; a < 3; a++) {
		free(b->lo[a]);
		free(b->hi[a]);
	}
}

static bool cow_brute_closest(const struct cow_brute *b, enum rs_triangle_test test,
                              const struct rs_ray *ray, struct rs_hit *out)
{
	struct rs_ray r = *ray;
	for (int a = 0; a < 3; a++)
		r.origin[a] -= b->origin[a];
	double inv[3];
	/* A zero component: the ray stays in its plane, so the slab is a yes or no (lo <= o <=
	 * hi, faces included), never a product: (hi - o) * 1e300 on the hi face is 0, a far
	 * of 0 that would drop the box for any tmin > 0. The filter must be conservative. */
	for (int a = 0; a < 3; a++)
		inv[a] = r.dir[a] == 0.0 ? 0.0 : 1.0 / r.dir[a];
	for (size_t t = 0; t < b->tris; t++) {
		double tn = r.tmin, tf = r.tmax;
		for (int a = 0; a < 3; a++) {
			if (r.dir[a] == 0.0) {
				if (r.origin[a] < b->lo[a][t] || r.origin[a] > b->hi[a][t])
					tf = -1.0; /* outside the slab: never entered */
				continue;
			}
			double t0 = (b->lo[a][t] - r.origin[a]) * inv[a];
			double t1 = (b->hi[a][t] - r.origin[a]) * inv[a];
			double near = t0 < t1 ? t0 : t1, far = t0 < t1 ? t1 : t0;
			tn = near > tn ? near : tn;
			tf = far < tf ? far : tf;
		}
		b->pass[t] = tn <= tf;
	}
	bool found = false;
	for (size_t t = 0; t < b->tris; t++) {
		double th, u, v;
		if (!b->pass[t] || !rs_intersect_triangle(test, b->v[t][0], b->v[t][1], b->v[t][2],
		                                          &r, &th, &u, &v))
			continue;
		found = true;
		r.tmax = th;
		*out = (struct rs_hit){th, u, v, RS_NO_SLOT, (uint32_t)t, RS_NO_SLOT};
	}
	return found;
}

/* Rays from anywhere in the scene box (grown by 20%): half aimed at a random point of a
 * random triangle, a few along the axes, the rest in random directions. The same
 * COW_RAYS rays every time; references are computed for rays [begin, end) only. */
static struct cow_ref *cow_references(const struct rs_scene *scene, size_t begin, size_t end)
{
	struct cow_brute brute = cow_brute_make(scene);
	struct cow_ref *refs = calloc(COW_RAYS, sizeof *refs);
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	size_t tris = brute.tris;
	for (size_t i = 0; i < COW_RAYS; i++) {
		struct cow_ref *r = &refs[i];
		r->ray = (struct rs_ray){{0}, {0}, 0.0, INFINITY, RS_NO_SLOT};
		for (int a = 0; a < 3; a++) {
			double ext = b.hi[a] - b.lo[a];
			r->ray.origin[a] = b.lo[a] - 0.1 * ext + cow_rnd() * 1.2 * ext;
			r->ray.dir[a] = cow_rnd() * 2 - 1;
		}
		double kind = cow_rnd();
		if (kind < 0.5) {
			const double(*v)[3] = brute.v[(size_t)(cow_rnd() * (double)tris)];
			double b1 = cow_rnd(), b2 = cow_rnd() * (1 - b1);
			for (int a = 0; a < 3; a++)
				r->ray.dir[a] = v[0][a] + b1 * (v[1][a] - v[0][a]) +
				                b2 * (v[2][a] - v[0][a]) -
				                (r->ray.origin[a] - brute.origin[a]);
		} else if (kind < 0.55) {
			int axis = (int)(cow_rnd() * 3);
			for (int a = 0; a < 3; a++)
				r->ray.dir[a] = a == axis ? (cow_rnd() < 0.5 ? -1.0 : 1.0) : 0.0;
		}
		/* Drawn for every ray so the sequence does not depend on [begin, end). */
		double light_s[3] = {cow_rnd(), 0.0, cow_rnd()};
		if (i < begin || i >= end)
			continue;
		r->found = cow_brute_closest(&brute, cow_test_of(i), &r->ray, &r->hit);
		if (!r->found || i % COW_FEELER_EVERY != 0)
			continue;
		/* Feeler from the hit point to a random light above the scene; tmin keeps the
		 * start triangle out without a (builder-specific) skip slot. */
		r->has_feeler = true;
		r->feeler = (struct rs_ray){{0}, {0}, 1e-6, 1.0, RS_NO_SLOT};
		for (int a = 0; a < 3; a++) {
			double ext = b.hi[a] - b.lo[a];
			double light = a == 1 ? b.hi[1] + ext : b.lo[a] + light_s[a] * ext;
			r->feeler.origin[a] = r->ray.origin[a] + r->hit.t * r->ray.dir[a];
			r->feeler.dir[a] = light - r->feeler.origin[a];
		}
		struct rs_hit h;
		r->occluded = cow_brute_closest(&brute, cow_test_of(i), &r->feeler, &h);
	}
	cow_brute_free(&brute);
	return refs;
}

/* The box-filtered reference equals rs_trace_closest_brute() (every triangle tested, no
 * filter at all) on a sample of the rays: same triangle, bit-identical t. */
static void cow_check_reference(const struct cow_world *w, const struct cow_ref *refs, size_t begin,
                                size_t end, size_t stride)
{
	for (size_t i = begin; i < end; i += stride) {
		struct rs_hit h;
		bool found = rs_trace_closest_brute(&w->packed, cow_test_of(i), &refs[i].ray, &h);
		assert_int_equal(found, refs[i].found);
		if (found) {
			assert_int_equal(h.triangle, refs[i].hit.triangle);
			assert_true(h.t == refs[i].hit.t);
		}
	}
}

/* Same triangle at the bit-identical t (the same code computes it from the same floats),
 * or another triangle at a t within 1e-12 relative: a tie at a shared edge or vertex. */
static void cow_compare(const struct cow_world *w, const struct cow_ref *refs, size_t begin,
                        size_t end, const char *name)
{
	size_t hits = 0, occluded = 0;
	for (size_t i = begin; i < end; i++) {
		const struct cow_ref *r = &refs[i];
		struct rs_hit h;
		bool found = rs_trace_closest(&w->packed, cow_test_of(i), &r->ray, &h, NULL);
		if (found != r->found)
			fail_msg("%s ray %zu: traversal %d, brute force %d", name, i, found,
			         r->found);
		if (found && h.triangle != r->hit.triangle &&
		    !(fabs(h.t - r->hit.t) <= 1e-12 * r->hit.t))
			fail_msg("%s ray %zu: triangle %u t %.17g, brute force %u t %.17g", name, i,
			         h.triangle, h.t, r->hit.triangle, r->hit.t);
		if (found && h.triangle == r->hit.triangle && h.t != r->hit.t)
			fail_msg("%s ray %zu: t %.17g, brute force %.17g", name, i, h.t, r->hit.t);
		hits += found;
		if (!r->has_feeler)
			continue;
		bool occ = rs_trace_occluded(&w->packed, cow_test_of(i), &r->feeler, NULL);
		if (occ != r->occluded)
			fail_msg("%s feeler %zu: any-hit %d, brute force %d", name, i, occ,
			         r->occluded);
		occluded += occ;
	}
	/* Guard against a ray set that tests nothing. */
	assert_true(hits > (end - begin) / 4);
	assert_true(occluded > 50);
}

#endif
