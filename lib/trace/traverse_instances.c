/* The two-level walk's CPU reference (rs_trace_instances_closest): the stackless threaded walk
 * of the TLAS, and at each instance item the same walk of its mesh's BLAS with the ray in
 * that BLAS's frame, sharing the best hit. Double throughout, reading only the textures and
 * the per-instance transforms (as a kernel would). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "raystream/rs_trace.h"

#include "intersect_internal.h"

struct walk {
	enum rs_triangle_test test;
	bool any, found;
	uint32_t skip; /* scene triangle id */
	double tmax;
	struct rs_instance_hit best;
	uint64_t boxes, tris;
};

static bool ray_usable(const struct rs_ray *ray)
{
	for (int a = 0; a < 3; a++)
		if (!isfinite(ray->origin[a]) || !isfinite(ray->dir[a]))
			return false;
	if (ray->dir[0] == 0.0 && ray->dir[1] == 0.0 && ray->dir[2] == 0.0)
		return false;
	return !isnan(ray->tmin) && !isnan(ray->tmax) && ray->tmin < ray->tmax;
}

static void geometric_normal(const double v[3][3], const double m[3][3], double out[3])
{
	double e1[3], e2[3], n[3];
	for (int a = 0; a < 3; a++) {
		e1[a] = v[1][a] - v[0][a];
		e2[a] = v[2][a] - v[0][a];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	double len = 0.0;
	for (int r = 0; r < 3; r++) {
		out[r] = m[r][0] * n[0] + m[r][1] * n[1] + m[r][2] * n[2];
		len += out[r] * out[r];
	}
	len = sqrt(len);
	for (int r = 0; r < 3; r++)
		out[r] = len > 0.0 ? out[r] / len : 0.0;
}

/* One instance's BLAS as a walk reads it: a decoding view of its texture (its own grid),
 * its item range for the ray's order, its transforms and how local ids become scene ids. */
struct blas {
	struct rs_packed view;
	uint32_t base, count; /* item of order 0, nodes per order */
	uint32_t orders;
	double to_object[3][4];
	double to_world_normal[3][3];
	uint32_t first_triangle;
	const uint32_t *ids; /* local -> scene ids (loose triangles), or NULL: first + local */
};

/* Walk instance i's BLAS with the world ray taken into its frame. Returns true when `any`
 * may stop. */
static bool walk_blas(const struct blas *b, uint32_t i, const struct rs_ray *world, struct walk *w)
{
	const struct rs_packed *p = &b->view;
	const double(*m)[4] = b->to_object;
	struct rs_ray r = {.tmin = world->tmin, .tmax = w->tmax, .skip_slot = RS_NO_SLOT};
	for (int a = 0; a < 3; a++) {
		r.origin[a] = m[a][0] * world->origin[0] + m[a][1] * world->origin[1] +
		              m[a][2] * world->origin[2] + m[a][3];
		r.dir[a] =
		    m[a][0] * world->dir[0] + m[a][1] * world->dir[1] + m[a][2] * world->dir[2];
	}
	if (!ray_usable(&r) || b->count == 0)
		return false;
	double inv[3];
	for (int a = 0; a < 3; a++)
		inv[a] = 1.0 / r.dir[a];
	struct rs__ray_pre pre;
	rs__ray_prepare(&r, &pre);
	pre.edge_slack = RS__INSTANCE_EDGE_SLACK;
	uint32_t k = b->base + rs_pack_node_order_of(b->orders, r.dir) * b->count;
	uint32_t end = k + b->count;
	while (k < end) {
		struct rs_pack_node node;
		rs_pack_read_node(p, k, &node);
		w->boxes++;
		/* One float step outward: the edge slack's twin for boxes (a ray through a corner
		 * shared by instances must reach the triangles that take it; flat boxes are common)
		 */
		for (int a = 0; a < 3; a++) {
			/* at least one float step each way (|x| eps is half a step or more),
			 * without a libm call per bound */
			node.lo[a] -= fabsf(node.lo[a]) * FLT_EPSILON + FLT_MIN;
			node.hi[a] += fabsf(node.hi[a]) * FLT_EPSILON + FLT_MIN;
		}
		if (!rs_intersect_box(node.lo, node.hi, r.origin, inv, r.tmin, r.tmax)) {
			k = node.escape;
			continue;
		}
		if (!node.leaf) {
			k++;
			continue;
		}
		for (uint32_t slot = node.first; slot < node.first + node.count; slot++) {
			const float *t =
			    rs_pack_texel(&p->triangles, RS_PACK_TRIANGLE_TEXELS, slot, 0);
			uint32_t local = rs_pack_index(t[3]);
			uint32_t id = local == UINT32_MAX ? UINT32_MAX
			              : b->ids            ? b->ids[local]
			                                  : b->first_triangle + local;
			if (id == w->skip)
				continue;
			double v[3][3], th, u, vv;
			for (int c = 0; c < 3; c++)
				for (int a = 0; a < 3; a++)
					v[c][a] = t[4 * c + a];
			w->tris++;
			if (!rs__intersect_triangle_pre(w->test, v[0], v[1], v[2], &pre, &th, &u,
			                                &vv))
				continue;
			/* R4: nearer wins, on equal t the lower scene triangle id */
			if (!(th < r.tmax || (w->found && id < w->best.hit.triangle)))
				continue;
			w->found = true;
			w->best.hit = (struct rs_hit){th, u, vv, slot, id, i};
			w->best.instance = i;
			geometric_normal(v, b->to_world_normal, w->best.normal);
			if (w->any)
				return true;
			r.tmax = w->tmax = th;
		}
		k = node.escape;
	}
	return false;
}

/* Instance i of an rs_packed_instances as a BLAS view. */
static void blas_of_instances(const struct rs_packed_instances *pi, uint32_t i, struct blas *b)
{
	const struct rs_packed *p = &pi->meshes[pi->mesh[i]];
	b->view = *p;
	b->base = 0;
	b->count = p->node_count;
	b->orders = p->node_orders;
	memcpy(b->to_object, pi->to_object[i], sizeof b->to_object);
	memcpy(b->to_world_normal, pi->to_world_normal[i], sizeof b->to_world_normal);
	b->first_triangle = pi->first_triangle[i];
	/* the last instance walks the loose triangles, when there are some */
	b->ids = pi->loose_ids && i == pi->instance_count - 1 ? pi->loose_ids : NULL;
}

/* Instance i of a merged packing as a BLAS view: everything from the instance texture, in
 * float as the kernels read it (RS_PACK_INSTANCE_TEXELS). */
static void blas_of_two_level(const struct rs_packed_two_level *p, uint32_t i, struct blas *b)
{
	const float *t = rs_pack_texel(&p->instances, RS_PACK_INSTANCE_TEXELS, i, 0);
	b->view = p->all;
	for (int r = 0; r < 3; r++) {
		for (int c = 0; c < 4; c++)
			b->to_object[r][c] = t[4 * r + c];
		for (int c = 0; c < 3; c++)
			b->to_world_normal[r][c] = t[4 * (6 + r) + c];
		b->view.node_grid_origin[r] = t[4 * 9 + r];
		b->view.node_grid_step[r] = t[4 * 10 + r];
	}
	b->first_triangle = rs_pack_index(t[4 * 6 + 3]);
	b->base = rs_pack_index(t[4 * 9 + 3]);
	b->count = rs_pack_index(t[4 * 10 + 3]);
	b->ids = NULL;
	b->orders = p->tree_orders;
	/* corrupt data never reads outside the node texture */
	uint64_t items = (uint64_t)p->all.node_count;
	if ((uint64_t)b->base + (uint64_t)b->count * p->tree_orders > items)
		b->count = 0;
}

/* The two levels a walk reads: the TLAS (a decoding view, its order-0 item, nodes per
 * order, orders, the world -> TLAS frame offset) and a way to view instance i's BLAS. */
struct levels {
	const struct rs_packed *top;
	uint32_t base, count, orders, instances;
	double offset[3];
	const void *src;
	void (*blas)(const void *src, uint32_t i, struct blas *out);
};

static bool walk(const struct levels *lv, enum rs_triangle_test test, const struct rs_ray *ray,
                 bool any, struct rs_instance_hit *out, struct rs_trace_counters *counters)
{
	struct walk w = {.test = test, .any = any, .skip = ray->skip_slot, .tmax = ray->tmax};
	w.best.hit = (struct rs_hit){INFINITY, 0.0, 0.0, RS_NO_SLOT, RS_NO_SLOT, RS_NO_SLOT};
	w.best.instance = RS_NO_SLOT;
	const struct rs_packed *top = lv->top;
	if (lv->instances > 0 && top->node_format != RS_PACK_NODES_WIDE4 && ray_usable(ray)) {
		double o[3], inv[3];
		for (int a = 0; a < 3; a++) {
			o[a] = ray->origin[a] - lv->offset[a]; /* TLAS frame (R1) */
			inv[a] = 1.0 / ray->dir[a];
		}
		uint32_t k = lv->base + rs_pack_node_order_of(lv->orders, ray->dir) * lv->count;
		uint32_t end = k + lv->count;
		while (k < end) {
			struct rs_pack_node node;
			rs_pack_read_node(top, k, &node);
			w.boxes++;
			if (!rs_intersect_box(node.lo, node.hi, o, inv, ray->tmin, w.tmax)) {
				k = node.escape;
				continue;
			}
			if (!node.leaf) {
				k++;
				continue;
			}
			bool stop = false;
			for (uint32_t s = node.first; !stop && s < node.first + node.count; s++) {
				const float *t =
				    rs_pack_texel(&top->triangles, RS_PACK_TRIANGLE_TEXELS, s, 0);
				uint32_t inst = rs_pack_index(t[3]);
				if (inst < lv->instances) {
					struct blas b;
					lv->blas(lv->src, inst, &b);
					stop = walk_blas(&b, inst, ray, &w);
				}
			}
			if (stop)
				break;
			k = node.escape;
		}
	}
	if (counters) {
		counters->box_tests += w.boxes;
		counters->triangle_tests += w.tris;
	}
	if (out)
		*out = w.best;
	return w.found;
}

static void instances_blas(const void *src, uint32_t i, struct blas *out)
{
	blas_of_instances(src, i, out);
}

static void two_level_blas(const void *src, uint32_t i, struct blas *out)
{
	blas_of_two_level(src, i, out);
}

static struct levels instances_levels(const struct rs_packed_instances *pi)
{
	struct levels lv = {.top = &pi->top,
	                    .count = pi->top.node_count,
	                    .orders = pi->top.node_orders,
	                    .instances = pi->instance_count,
	                    .src = pi,
	                    .blas = instances_blas};
	memcpy(lv.offset, pi->top.origin, sizeof lv.offset);
	return lv;
}

static struct levels two_level_levels(const struct rs_packed_two_level *p)
{
	/* rays arrive in the TLAS frame (p->all.origin) */
	return (struct levels){.top = &p->all,
	                       .base = p->top_node_base,
	                       .count = p->top_node_count,
	                       .orders = p->tree_orders,
	                       .instances = p->instance_count,
	                       .src = p,
	                       .blas = two_level_blas};
}

bool rs_trace_instances_closest(const struct rs_packed_instances *packed,
                                enum rs_triangle_test test, const struct rs_ray *ray,
                                struct rs_instance_hit *out_hit, struct rs_trace_counters *counters)
{
	RS_ASSERT(packed && ray);
	struct levels lv = instances_levels(packed);
	return walk(&lv, test, ray, false, out_hit, counters);
}

bool rs_trace_instances_occluded(const struct rs_packed_instances *packed,
                                 enum rs_triangle_test test, const struct rs_ray *ray,
                                 struct rs_trace_counters *counters)
{
	RS_ASSERT(packed && ray);
	struct levels lv = instances_levels(packed);
	return walk(&lv, test, ray, true, NULL, counters);
}

bool rs_trace_two_level_closest(const struct rs_packed_two_level *packed,
                                enum rs_triangle_test test, const struct rs_ray *ray,
                                struct rs_instance_hit *out_hit, struct rs_trace_counters *counters)
{
	RS_ASSERT(packed && ray);
	struct levels lv = two_level_levels(packed);
	return walk(&lv, test, ray, false, out_hit, counters);
}

bool rs_trace_two_level_occluded(const struct rs_packed_two_level *packed,
                                 enum rs_triangle_test test, const struct rs_ray *ray,
                                 struct rs_trace_counters *counters)
{
	RS_ASSERT(packed && ray);
	struct levels lv = two_level_levels(packed);
	return walk(&lv, test, ray, true, NULL, counters);
}
