/* Stackless traversal of the packed threaded BVH, reading only the textures (as the GLES
 * kernel does, through rs_pack_read_node in either node format), and brute force for checking it.
 * Counting follows the paper: every box tested is one test, every triangle tested is one test; a
 * skipped slot (skip_slot) is not tested and not counted. */
#include <math.h>

#include "raystream/rs_trace.h"

#include "intersect_internal.h"

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
	*out_id = rs_pack_index(t[3]);
}

/* The closest-hit rule (docs/tracer.md R4): nearer wins; on exactly equal t the lower scene
 * triangle id wins, so the answer does not depend on the order the BVH visits triangles.
 * The triangle tests accept t == r->tmax: the caller's tmax before a hit (kept exclusive
 * here), the best t after. */
static bool better(bool found, double t, uint32_t id, const struct rs_ray *r, uint32_t best_id)
{
	return t < r->tmax || (found && id < best_id);
}

static void record(struct rs_hit *out_hit, double t, double u, double v, uint32_t slot, uint32_t id)
{
	if (out_hit) {
		out_hit->t = t;
		out_hit->u = u;
		out_hit->v = v;
		out_hit->slot = slot;
		out_hit->triangle = id;
	}
}

static void clear(struct rs_hit *out_hit)
{
	record(out_hit, INFINITY, 0.0, 0.0, RS_NO_SLOT, RS_NO_SLOT);
}

/* Tests a leaf's triangles from `first` to the slot with the last flag: the closest-hit
 * rule, r->tmax shrinks to the best t. Returns true when `any` may stop. */
static bool test_leaf(const struct rs_packed *packed, enum rs_triangle_test test,
                      const struct rs__ray_pre *pre, struct rs_ray *r, bool any, uint32_t first,
                      bool *found, uint32_t *best_id, struct rs_hit *out_hit, uint64_t *tris)
{
	for (uint32_t slot = first; slot < packed->triangle_count; slot++) {
		const float *t2 =
		    rs_pack_texel(&packed->triangles, RS_PACK_TRIANGLE_TEXELS, slot, 2);
		bool last = t2[3] != 0.0f;
		if (slot != r->skip_slot) {
			double v[3][3], t, u, w;
			uint32_t id;
			load_triangle(packed, slot, v, &id);
			(*tris)++;
			if (rs__intersect_triangle_pre(test, v[0], v[1], v[2], pre, &t, &u, &w) &&
			    better(*found, t, id, r, *best_id)) {
				*found = true;
				*best_id = id;
				record(out_hit, t, u, w, slot, id);
				if (any)
					return true;
				r->tmax = t;
			}
		}
		if (last)
			break;
	}
	return false;
}

/* The wide walk (RS_PACK_NODES_WIDE4, docs/bvh.md "Wide nodes"), as the kernel's: a stack of
 * child words; at an interior node every child box is tested (one box test each) and the
 * children hit are pushed farthest first in the ray's octant order, the integer key
 * sum_a sign(d_a) (qlo_a + qhi_a) with ties to the lower slot popped first, so the order
 * is the same in double and fp32. Packing guarantees RS_PACK_WIDE_STACK entries suffice. */
static bool traverse_wide(const struct rs_packed *packed, enum rs_triangle_test test,
                          struct rs_ray *r, const struct rs__ray_pre *pre, const double inv[3],
                          bool any, struct rs_hit *out_hit, uint64_t *boxes, uint64_t *tris)
{
	bool found = false;
	uint32_t best_id = RS_NO_SLOT, stack[RS_PACK_WIDE_STACK], sp = 0, entry = 0;
	if (packed->node_count == 0)
		return false;
	int32_t sign[3];
	for (int a = 0; a < 3; a++)
		sign[a] = r->dir[a] < 0.0 ? -1 : 1;
	for (;;) {
		if (entry & RS_PACK_LEAF_BIT) {
			if (test_leaf(packed, test, pre, r, any, entry & ~RS_PACK_LEAF_BIT, &found,
			              &best_id, out_hit, tris))
				return true;
		} else {
			struct rs_pack_wide node;
			rs_pack_read_wide(packed, entry, &node);
			int32_t key[RS_PACK_WIDE_CHILDREN];
			bool hit[RS_PACK_WIDE_CHILDREN];
			for (uint32_t c = 0; c < node.children; c++) {
				(*boxes)++;
				hit[c] = rs_intersect_box(node.lo[c], node.hi[c], r->origin, inv,
				                          r->tmin, r->tmax);
				key[c] = 0;
				for (int a = 0; a < 3; a++)
					key[c] += sign[a] * (node.qlo[c][a] + node.qhi[c][a]);
			}
			/* push farthest first: c goes below every d that comes before it */
			for (uint32_t c = 0; c < node.children; c++) {
				if (!hit[c])
					continue;
				uint32_t below = 0;
				for (uint32_t d = 0; d < node.children; d++)
					if (hit[d] &&
					    (key[d] > key[c] || (key[d] == key[c] && d > c)))
						below++;
				if (sp + below < RS_PACK_WIDE_STACK)
					stack[sp + below] = node.child[c];
			}
			for (uint32_t c = 0; c < node.children; c++)
				sp += hit[c] && sp < RS_PACK_WIDE_STACK ? 1u : 0u;
		}
		if (sp == 0)
			return found;
		entry = stack[--sp];
	}
}

/* One walk for both queries: `any` stops at the first hit. The ray is in the packed frame. */
static bool traverse(const struct rs_packed *packed, enum rs_triangle_test test,
                     const struct rs_ray *ray, bool any, struct rs_hit *out_hit,
                     struct rs_trace_counters *counters)
{
	clear(out_hit);
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
	uint32_t best_id = RS_NO_SLOT;
	if (packed->node_format == RS_PACK_NODES_WIDE4) {
		found = traverse_wide(packed, test, &r, &pre, inv, any, out_hit, &boxes, &tris);
		goto done;
	}
	/* the node order of the ray's direction (rs_pack.h), whose escapes are absolute */
	uint32_t i = rs_pack_node_order_of(packed->node_orders, ray->dir) * packed->node_count;
	uint32_t n = i + packed->node_count;
	while (i < n) {
		struct rs_pack_node node;
		rs_pack_read_node(packed, i, &node);
		boxes++;
		if (!rs_intersect_box(node.lo, node.hi, r.origin, inv, r.tmin, r.tmax)) {
			i = node.escape;
			continue;
		}
		if (!node.leaf) {
			i++;
			continue;
		}
		for (uint32_t slot = node.first; slot < node.first + node.count; slot++) {
			if (slot == r.skip_slot)
				continue;
			double v[3][3], t, u, w;
			uint32_t id;
			load_triangle(packed, slot, v, &id);
			tris++;
			if (!rs__intersect_triangle_pre(test, v[0], v[1], v[2], &pre, &t, &u, &w) ||
			    !better(found, t, id, &r, best_id))
				continue;
			found = true;
			best_id = id;
			record(out_hit, t, u, w, slot, id);
			if (any)
				goto done;
			r.tmax = t;
		}
		i = node.escape;
	}
done:
	if (counters) {
		counters->box_tests += boxes;
		counters->triangle_tests += tris;
	}
	return found;
}

bool rs__trace_closest_local(const struct rs_packed *packed, enum rs_triangle_test test,
                             const struct rs_ray *ray, struct rs_hit *out_hit,
                             struct rs_trace_counters *counters)
{
	return traverse(packed, test, ray, false, out_hit, counters);
}

bool rs__trace_occluded_local(const struct rs_packed *packed, enum rs_triangle_test test,
                              const struct rs_ray *ray, struct rs_trace_counters *counters)
{
	return traverse(packed, test, ray, true, NULL, counters);
}

/* World ray -> packed frame (docs/tracer.md R1); a non-finite ray stays non-finite. */
static void to_packed_frame(const struct rs_packed *packed, const struct rs_ray *ray,
                            struct rs_ray *out)
{
	*out = *ray;
	if (packed)
		for (int a = 0; a < 3; a++)
			out->origin[a] = ray->origin[a] - packed->origin[a];
}

bool rs_trace_closest(const struct rs_packed *packed, enum rs_triangle_test test,
                      const struct rs_ray *ray, struct rs_hit *out_hit,
                      struct rs_trace_counters *counters)
{
	struct rs_ray r;
	to_packed_frame(packed, ray, &r);
	return traverse(packed, test, &r, false, out_hit, counters);
}

bool rs_trace_occluded(const struct rs_packed *packed, enum rs_triangle_test test,
                       const struct rs_ray *ray, struct rs_trace_counters *counters)
{
	struct rs_ray r;
	to_packed_frame(packed, ray, &r);
	return traverse(packed, test, &r, true, NULL, counters);
}

bool rs_trace_closest_brute(const struct rs_packed *packed, enum rs_triangle_test test,
                            const struct rs_ray *ray, struct rs_hit *out_hit)
{
	clear(out_hit);
	if (!packed || !ray_usable(ray))
		return false;
	struct rs_ray r;
	to_packed_frame(packed, ray, &r);
	struct rs__ray_pre pre;
	rs__ray_prepare(&r, &pre);
	bool found = false;
	uint32_t best_id = RS_NO_SLOT;
	for (uint32_t slot = 0; slot < packed->triangle_count; slot++) {
		if (slot == r.skip_slot)
			continue;
		double v[3][3], t, u, w;
		uint32_t id;
		load_triangle(packed, slot, v, &id);
		if (!rs__intersect_triangle_pre(test, v[0], v[1], v[2], &pre, &t, &u, &w) ||
		    !better(found, t, id, &r, best_id))
			continue;
		found = true;
		best_id = id;
		r.tmax = t;
		record(out_hit, t, u, w, slot, id);
	}
	return found;
}
