/* Stackless traversal of the packed threaded BVH, reading only the float textures (as the
 * GLES kernel does), and brute force for checking it. Counting follows the paper: every
 * box tested is one test, every triangle tested is one test; a skipped slot (skip_slot)
 * is not tested and not counted. */
#include <math.h>

#include "raystream/rs_trace.h"

#include "accel_internal.h"

/* Rays the tests cannot give a defined answer for: non-finite values or a zero direction. */
static bool ray_usable(const struct rs_ray *ray)
{
	for (int a = 0; a < 3; a++)
		if (!isfinite(ray->origin[a]) || !isfinite(ray->dir[a]))
			return false;
	if (ray->dir[0] == 0.0 && ray->dir[1] == 0.0 && ray->dir[2] == 0.0)
		return false;
	return !isnan(ray->tmin) && !isnan(ray->tmax) && ray->tmin < ray->tmax;
}

/* Float texel to index; NaN, negative or huge (corrupt data) map to UINT32_MAX. */
static uint32_t to_index(float f)
{
	return f >= 0.0f && f < 4294967040.0f ? (uint32_t)f : UINT32_MAX;
}

static void load_triangle(const struct rs_packed *packed, uint32_t slot, double v[3][3],
                          uint32_t *out_id)
{
	/* The three texels of an item are adjacent in their row. */
	const float *t = rs_pack_texel(&packed->triangles, RS_PACK_TRIANGLE_TEXELS, slot, 0);
	for (uint32_t k = 0; k < 3; k++) {
		v[k][0] = t[4 * k];
		v[k][1] = t[4 * k + 1];
		v[k][2] = t[4 * k + 2];
	}
	*out_id = to_index(t[3]);
}

/* One walk for both queries: `any` stops at the first hit. */
static bool traverse(const struct rs_packed *packed, enum rs_triangle_test test,
                     const struct rs_ray *ray, bool any, struct rs_hit *out_hit,
                     struct rs_trace_counters *counters)
{
	if (out_hit) {
		out_hit->t = INFINITY;
		out_hit->u = out_hit->v = 0.0;
		out_hit->slot = RS_NO_SLOT;
		out_hit->triangle = RS_NO_SLOT;
	}
	if (!packed || !ray_usable(ray))
		return false;
	double inv[3];
	for (int a = 0; a < 3; a++)
		inv[a] = 1.0 / ray->dir[a]; /* IEEE: 1/+-0 = +-inf, handled by the slab test */
	struct rs_ray r = *ray;
	struct rs__ray_pre pre;
	rs__ray_prepare(&r, &pre);
	uint64_t boxes = 0, tris = 0;
	bool found = false;
	uint32_t n = packed->node_count;
	uint32_t i = 0;
	while (i < n) {
		const float *t0 = rs_pack_texel(&packed->nodes, RS_PACK_NODE_TEXELS, i, 0);
		const float *t1 = rs_pack_texel(&packed->nodes, RS_PACK_NODE_TEXELS, i, 1);
		uint32_t escape = to_index(t0[3]);
		/* A corrupt escape must not loop forever: never step backwards. */
		escape = escape > i ? escape : i + 1;
		boxes++;
		if (!rs_intersect_box(t0, t1, r.origin, inv, r.tmin, r.tmax)) {
			i = escape;
			continue;
		}
		if (t1[3] != 0.0f) {
			i++;
			continue;
		}
		const float *t2 = rs_pack_texel(&packed->nodes, RS_PACK_NODE_TEXELS, i, 2);
		uint64_t first = to_index(t2[0]);
		uint64_t end = first + to_index(t2[1]);
		end = end < packed->triangle_count ? end : packed->triangle_count;
		for (uint32_t slot = (uint32_t)first; slot < end; slot++) {
			if (slot == r.skip_slot)
				continue;
			double v[3][3], t, u, w;
			uint32_t id;
			load_triangle(packed, slot, v, &id);
			tris++;
			if (!rs__intersect_triangle_pre(test, v[0], v[1], v[2], &pre, &t, &u, &w))
				continue;
			found = true;
			if (out_hit) {
				out_hit->t = t;
				out_hit->u = u;
				out_hit->v = w;
				out_hit->slot = slot;
				out_hit->triangle = id;
			}
			if (any)
				goto done;
			r.tmax = t;
		}
		i = escape;
	}
done:
	if (counters) {
		counters->box_tests += boxes;
		counters->triangle_tests += tris;
	}
	return found;
}

bool rs_trace_closest(const struct rs_packed *packed, enum rs_triangle_test test,
                      const struct rs_ray *ray, struct rs_hit *out_hit,
                      struct rs_trace_counters *counters)
{
	return traverse(packed, test, ray, false, out_hit, counters);
}

bool rs_trace_occluded(const struct rs_packed *packed, enum rs_triangle_test test,
                       const struct rs_ray *ray, struct rs_trace_counters *counters)
{
	return traverse(packed, test, ray, true, NULL, counters);
}

bool rs_trace_closest_brute(const struct rs_packed *packed, enum rs_triangle_test test,
                            const struct rs_ray *ray, struct rs_hit *out_hit)
{
	if (out_hit) {
		out_hit->t = INFINITY;
		out_hit->u = out_hit->v = 0.0;
		out_hit->slot = RS_NO_SLOT;
		out_hit->triangle = RS_NO_SLOT;
	}
	if (!packed || !ray_usable(ray))
		return false;
	struct rs_ray r = *ray;
	struct rs__ray_pre pre;
	rs__ray_prepare(&r, &pre);
	bool found = false;
	for (uint32_t slot = 0; slot < packed->triangle_count; slot++) {
		if (slot == r.skip_slot)
			continue;
		double v[3][3], t, u, w;
		uint32_t id;
		load_triangle(packed, slot, v, &id);
		if (!rs__intersect_triangle_pre(test, v[0], v[1], v[2], &pre, &t, &u, &w))
			continue;
		found = true;
		r.tmax = t;
		if (out_hit) {
			out_hit->t = t;
			out_hit->u = u;
			out_hit->v = w;
			out_hit->slot = slot;
			out_hit->triangle = id;
		}
	}
	return found;
}
