/* rs_pack_two_level: a two-level packing (rs_pack_instances) merged into one set of textures
 * with per-tree base offsets, plus the instance texture: the layout the GLES kernels sample
 * and the CPU reference walks for an instanced scene (docs/bvh.md "Instances on the GPU").
 * Escapes and leaf first slots are made absolute while copying, so a walk needs only a
 * tree's first item and its node count; the TLAS comes last so a transform update sends
 * the rows from its first on and nothing else of the BLASes. */
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_pack.h"

/* Copy `items` nodes of tree `src` to item `base` of `dst`, escapes + base, leaf first slots
 * + slot_base. */
static void copy_nodes(const struct rs_packed *src, uint32_t base, uint32_t slot_base,
                       struct rs_packed *dst)
{
	uint32_t items = src->node_count * src->node_orders;
	if (src->node_format == RS_PACK_NODES_PAPER) {
		for (uint32_t k = 0; k < items; k++) {
			const float *s = rs_pack_texel(&src->nodes, RS_PACK_NODE_TEXELS, k, 0);
			float *d =
			    (float *)rs_pack_texel(&dst->nodes, RS_PACK_NODE_TEXELS, base + k, 0);
			memcpy(d, s, RS_PACK_NODE_TEXELS * 16u);
			d[3] += (float)base;
			if (d[7] == 0.0f) /* a leaf: level 0 */
				d[8] += (float)slot_base;
		}
		return;
	}
	for (uint32_t k = 0; k < items; k++) {
		const uint32_t *s = src->nodes.words + (size_t)k * 4u;
		uint32_t *d = dst->nodes.words + ((size_t)base + k) * 4u;
		memcpy(d, s, 16u);
		d[3] = s[3] & RS_PACK_LEAF_BIT
		           ? RS_PACK_LEAF_BIT | ((s[3] & ~RS_PACK_LEAF_BIT) + slot_base)
		           : s[3] + base;
	}
}

/* Copy tree `src`'s slots (triangle and normal texels) to slot `base` of `dst`; ids !=
 * NULL replaces t0.w by ids[local id]. The normals' spare channel gets the local id -> slot
 * map (and the loose BLAS's local id -> scene id) that shading decodes a hit through. */
static void copy_slots(const struct rs_packed *src, uint32_t base, const uint32_t *ids, bool map,
                       struct rs_packed *dst)
{
	size_t bytes = (size_t)src->triangle_count * RS_PACK_TRIANGLE_TEXELS * 16u;
	float *t = (float *)rs_pack_texel(&dst->triangles, RS_PACK_TRIANGLE_TEXELS, base, 0);
	memcpy(t, src->triangles.texels, bytes);
	memcpy((float *)rs_pack_texel(&dst->normals, RS_PACK_NORMAL_TEXELS, base, 0),
	       src->normals.texels, bytes);
	for (uint32_t s = 0; s < src->triangle_count; s++) {
		float *w = t + (size_t)s * RS_PACK_TRIANGLE_TEXELS * 4u + 3u;
		uint32_t local = rs_pack_index(*w);
		if (!map || local >= src->triangle_count)
			continue;
		float *n =
		    (float *)rs_pack_texel(&dst->normals, RS_PACK_NORMAL_TEXELS, base + local, 0);
		n[3] = (float)(base + s);
		if (ids) {
			n[4 + 3] = (float)ids[local];
			*w = (float)ids[local];
		}
	}
}

static void set4(float *t, double a, double b, double c, double d)
{
	t[0] = (float)a;
	t[1] = (float)b;
	t[2] = (float)c;
	t[3] = (float)d;
}

/* Instance i's texels (RS_PACK_INSTANCE_TEXELS in rs_pack.h). */
static void write_instance(const struct rs_scene *scene, const struct rs_packed_instances *pi,
                           const uint32_t *node_base, const uint32_t *slot_base, uint32_t i,
                           struct rs_packed_two_level *out)
{
	const double *o_top = pi->top.origin;
	uint32_t mesh = pi->mesh[i];
	const struct rs_packed *blas = &pi->meshes[mesh];
	bool loose = pi->loose_ids && i == pi->instance_count - 1;
	double a[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
	double material = -1.0;
	if (!loose) {
		const struct rs_scene_instance *si = &rs_scene_instances(scene)[i];
		memcpy(a, si->transform, sizeof a);
		material = si->material;
	}
	uint32_t row = out->instance_row_items;
	float *t = out->instances.texels + ((size_t)(i % row) * RS_PACK_INSTANCE_TEXELS +
	                                    (size_t)(i / row) * out->instances.width) *
	                                       4u;
	for (int r = 0; r < 3; r++) {
		const double *m = pi->to_object[i][r];
		/* world = TLAS frame + o_top */
		double w = m[3] + m[0] * o_top[0] + m[1] * o_top[1] + m[2] * o_top[2];
		set4(t + 4 * r, m[0], m[1], m[2], w);
		/* TLAS frame = A (BLAS frame + mesh origin) / mesh scale + b - o_top */
		const double *o = blas->origin;
		double s = pi->mesh_scale[mesh];
		double b =
		    a[r][3] + (a[r][0] * o[0] + a[r][1] * o[1] + a[r][2] * o[2]) / s - o_top[r];
		set4(t + 4 * (3 + r), a[r][0] / s, a[r][1] / s, a[r][2] / s, b);
	}
	double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
	             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
	             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
	double w6[3] = {loose ? 0.0 : pi->first_triangle[i], material, det < 0.0 ? 1.0 : 0.0};
	for (int r = 0; r < 3; r++) {
		const double *n = pi->to_world_normal[i][r];
		set4(t + 4 * (6 + r), n[0], n[1], n[2], w6[r]);
	}
	const float *go = blas->node_grid_origin, *gs = blas->node_grid_step;
	set4(t + 4 * 9, go[0], go[1], go[2], node_base[mesh]);
	set4(t + 4 * 10, gs[0], gs[1], gs[2], blas->node_count);
	set4(t + 4 * 11, blas->triangle_count, slot_base[mesh], 0.0, 0.0);
}

/* The TLAS (nodes, instance boxes), the frame it sets and every instance's texels; what a
 * transform update rewrites. */
static void write_top(const struct rs_scene *scene, const struct rs_packed_instances *pi,
                      const uint32_t *node_base, const uint32_t *slot_base,
                      struct rs_packed_two_level *out)
{
	const struct rs_packed *top = &pi->top;
	/* a smaller tree than the last leaves no stale nodes behind it */
	size_t texels = out->all.node_format == RS_PACK_NODES_PAPER ? RS_PACK_NODE_TEXELS
	                                                            : RS_PACK_COMPACT_NODE_TEXELS;
	memset(out->all.nodes.words + (size_t)out->top_node_base * texels * 4u, 0,
	       (size_t)out->top_node_capacity * texels * 16u);
	copy_nodes(top, out->top_node_base, out->top_slot_base, &out->all);
	copy_slots(top, out->top_slot_base, NULL, false, &out->all);
	out->top_node_count = top->node_count;
	memcpy(out->all.origin, top->origin, sizeof top->origin);
	memcpy(out->all.node_grid_origin, top->node_grid_origin, sizeof top->node_grid_origin);
	memcpy(out->all.node_grid_step, top->node_grid_step, sizeof top->node_grid_step);
	for (uint32_t i = 0; i < pi->instance_count; i++)
		write_instance(scene, pi, node_base, slot_base, i, out);
}

/* Where each BLAS starts in the merged node and slot items. */
static void bases(const struct rs_packed_instances *pi, uint32_t orders, uint32_t *node_base,
                  uint32_t *slot_base, uint64_t *out_nodes, uint64_t *out_slots)
{
	uint64_t nodes = 0, slots = 0;
	for (uint32_t k = 0; k < pi->mesh_count; k++) {
		node_base[k] = (uint32_t)(nodes < RS_PACK_MAX_ITEMS ? nodes : RS_PACK_MAX_ITEMS);
		slot_base[k] = (uint32_t)(slots < RS_PACK_MAX_ITEMS ? slots : RS_PACK_MAX_ITEMS);
		nodes += (uint64_t)pi->meshes[k].node_count * orders;
		slots += pi->meshes[k].triangle_count;
	}
	*out_nodes = nodes;
	*out_slots = slots;
}

static enum rs_status check_trees(const struct rs_packed_instances *pi, struct rs_error *err)
{
	const struct rs_packed *top = &pi->top;
	for (uint32_t k = 0; k < pi->mesh_count; k++) {
		const struct rs_packed *m = &pi->meshes[k];
		if (m->node_orders != top->node_orders)
			return rs_error_set(
			    err, RS_ERR_LIMIT,
			    "pack: mesh %u has %u node orders, the instances' tree %u; "
			    "pack them with one order (RS_PACK_ORDERS_SINGLE)",
			    k, m->node_orders, top->node_orders);
		RS_ASSERT(m->row_items == top->row_items && m->node_format == top->node_format);
	}
	return RS_OK;
}

enum rs_status rs_pack_two_level(const struct rs_scene *scene, const struct rs_packed_instances *pi,
                                 struct rs_packed_two_level *out, struct rs_error *err)
{
	RS_ASSERT(scene && pi && out);
	memset(out, 0, sizeof *out);
	const struct rs_packed *top = &pi->top;
	enum rs_status st = check_trees(pi, err);
	if (st != RS_OK)
		return st;
	uint32_t orders = top->node_orders, row = top->row_items, n = pi->instance_count;
	uint32_t *node_base = malloc((pi->mesh_count + 1) * sizeof *node_base);
	uint32_t *slot_base = malloc((pi->mesh_count + 1) * sizeof *slot_base);
	if (!node_base || !slot_base) {
		free(node_base);
		free(slot_base);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instances");
	}
	uint64_t nodes, slots;
	bases(pi, orders, node_base, slot_base, &nodes, &slots);
	/* The TLAS after the BLASes, with room for any binary tree over n items (2n - 1). Not
	 * padded to a row start: at GL's usual 16384-texel limit a row of triangles is 192 KiB,
	 * more than Cow17i's whole BLAS; an update sends the rows from the TLAS's first. */
	uint64_t top_nodes =
	    (uint64_t)(2u * n - 1u > top->node_count ? 2u * n - 1u : top->node_count);
	uint64_t top_node_base = nodes, top_slot_base = slots;
	uint64_t node_items = top_node_base + top_nodes * orders, slot_items = top_slot_base + n;
	if (node_items >= RS_PACK_MAX_ITEMS || slot_items >= RS_PACK_MAX_ITEMS)
		st = rs_error_set(err, RS_ERR_LIMIT,
		                  "pack: %llu node items and %llu slots merged, over 2^24",
		                  (unsigned long long)node_items, (unsigned long long)slot_items);
	struct rs_pack_desc d = {.max_texture_size = top->max_texture_size,
	                         .row_items = row,
	                         .nodes = top->node_format,
	                         .orders = RS_PACK_ORDERS_SINGLE};
	if (st == RS_OK)
		st =
		    rs_pack_layout(&d, node_items, slot_items, top->material_count, &out->all, err);
	if (st == RS_OK)
		st = rs_pack_alloc(&out->all, err);
	/* instances: the widest power-of-two row the size limit takes */
	uint32_t irow = 1;
	while (irow * 2u * RS_PACK_INSTANCE_TEXELS <= top->max_texture_size)
		irow *= 2u;
	out->instance_row_items = irow;
	rs_pack_texture_size(n, RS_PACK_INSTANCE_TEXELS, irow, &out->instances.width,
	                     &out->instances.height);
	out->instances.format = RS_TEXEL_RGBA32F;
	if (st == RS_OK && out->instances.height > top->max_texture_size)
		st = rs_error_set(err, RS_ERR_LIMIT,
		                  "pack: %u instances need %u texture rows, over the texture size "
		                  "limit of %u texels",
		                  n, out->instances.height, top->max_texture_size);
	if (st == RS_OK) {
		out->instances.texels = calloc(
		    (size_t)out->instances.width * out->instances.height * 4u, sizeof(float));
		if (!out->instances.texels)
			st = rs_error_set(err, RS_ERR_NO_MEMORY,
			                  "pack: out of memory for instances");
	}
	if (st == RS_OK) {
		out->instance_count = n;
		out->tree_orders = orders;
		out->top_node_base = (uint32_t)top_node_base;
		out->top_node_count = top->node_count;
		out->top_node_capacity = (uint32_t)(top_nodes * orders);
		out->top_slot_base = (uint32_t)top_slot_base;
		out->scene_triangles = (uint32_t)rs_scene_triangle_count(scene);
		out->loose = pi->loose_ids != NULL;
		for (uint32_t k = 0; k < pi->mesh_count; k++) {
			bool loose = pi->loose_ids && k == pi->mesh_count - 1;
			copy_nodes(&pi->meshes[k], node_base[k], slot_base[k], &out->all);
			copy_slots(&pi->meshes[k], slot_base[k], loose ? pi->loose_ids : NULL, true,
			           &out->all);
		}
		write_top(scene, pi, node_base, slot_base, out);
		memcpy(out->all.materials.texels, top->materials.texels,
		       (size_t)top->materials.width * top->materials.height * 16u);
		memcpy(out->all.origin, top->origin, sizeof top->origin);
		memcpy(out->all.node_grid_origin, top->node_grid_origin,
		       sizeof top->node_grid_origin);
		memcpy(out->all.node_grid_step, top->node_grid_step, sizeof top->node_grid_step);
		for (uint32_t i = 0; i < n; i++)
			write_instance(scene, pi, node_base, slot_base, i, out);
		/* the TLAS's items (reserved nodes, instance boxes) and the instances */
		size_t per = out->all.node_format == RS_PACK_NODES_PAPER
		                 ? RS_PACK_NODE_TEXELS
		                 : RS_PACK_COMPACT_NODE_TEXELS;
		out->top_bytes =
		    ((size_t)out->top_node_capacity * per + (size_t)n * RS_PACK_TRIANGLE_TEXELS +
		     (size_t)out->instances.width * out->instances.height) *
		    16u;
	}
	free(node_base);
	free(slot_base);
	if (st != RS_OK)
		rs_pack_two_level_free(out);
	return st;
}

enum rs_status rs_pack_two_level_update(const struct rs_scene *scene,
                                        const struct rs_packed_instances *pi,
                                        struct rs_packed_two_level *out, struct rs_error *err)
{
	RS_ASSERT(scene && pi && out);
	const struct rs_packed *top = &pi->top;
	if (pi->instance_count != out->instance_count || top->node_orders != out->tree_orders ||
	    top->row_items != out->all.row_items || top->node_format != out->all.node_format ||
	    (uint64_t)top->node_count * top->node_orders > out->top_node_capacity ||
	    top->triangle_count != pi->instance_count)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pack: the instances' new tree does not fit the merged layout "
		                    "(another scene's instances?)");
	uint32_t *node_base = malloc((pi->mesh_count + 1) * sizeof *node_base);
	uint32_t *slot_base = malloc((pi->mesh_count + 1) * sizeof *slot_base);
	enum rs_status st = RS_OK;
	if (!node_base || !slot_base)
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instances");
	uint64_t nodes, slots;
	if (st == RS_OK) {
		bases(pi, top->node_orders, node_base, slot_base, &nodes, &slots);
		if (nodes != out->top_node_base || slots != out->top_slot_base)
			st =
			    rs_error_set(err, RS_ERR_INVALID,
			                 "pack: the instances' meshes are not the merged layout's");
	}
	if (st == RS_OK)
		write_top(scene, pi, node_base, slot_base, out);
	free(node_base);
	free(slot_base);
	return st;
}

void rs_pack_two_level_free(struct rs_packed_two_level *packed)
{
	if (!packed)
		return;
	rs_pack_free(&packed->all);
	free(packed->instances.texels);
	memset(packed, 0, sizeof *packed);
}

size_t rs_pack_two_level_bytes(const struct rs_packed_two_level *packed)
{
	return rs_pack_bytes(&packed->all) +
	       (size_t)packed->instances.width * packed->instances.height * 16u;
}
