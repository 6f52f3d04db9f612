/* rs_pack: the scene and its BVH as texture images, the exact bytes the GLES kernels sample
 * and the CPU reference tracer walks. Integers in float textures are stored as floats,
 * which is why every count must stay below 2^24. The node texture is in pack_nodes.c. */
#include "raystream/rs_pack.h"

#include <stdlib.h>
#include <string.h>

#include "pack_internal.h"

void rs_pack_texture_size(size_t items, uint32_t texels_per_item, uint32_t row_items,
                          uint32_t *out_width, uint32_t *out_height)
{
	RS_ASSERT(row_items > 0 && out_width && out_height);
	/* Never 0 x 0: an empty list still gets one (zeroed) row so a texture can exist. */
	size_t per_row = items < row_items ? (items ? items : 1) : row_items;
	size_t rows = items ? (items + row_items - 1) / row_items : 1;
	*out_width = (uint32_t)(per_row * texels_per_item);
	*out_height = (uint32_t)rows;
}

static const char *const texture_names[4] = {"node", "triangle", "normal", "material"};

/* Texels per item of texture i (0: nodes, in their format). */
static uint32_t texture_texels(int i, enum rs_pack_nodes nodes)
{
	static const uint32_t texels[4] = {RS_PACK_NODE_TEXELS, RS_PACK_TRIANGLE_TEXELS,
	                                   RS_PACK_NORMAL_TEXELS, RS_PACK_MATERIAL_TEXELS};
	if (i == 0 && nodes == RS_PACK_NODES_WIDE4)
		return RS_PACK_WIDE_NODE_TEXELS;
	return i == 0 && nodes == RS_PACK_NODES_COMPACT ? RS_PACK_COMPACT_NODE_TEXELS : texels[i];
}

/* The default row: the most items a row holds, rounded down to a power of two, so that
 * kernels address an item with a mask and a shift instead of an integer division. */
static uint32_t widest_power_of_two(uint32_t max_side)
{
	uint32_t fit = max_side / RS_PACK_MAX_ITEM_TEXELS, p = 1;
	while (p <= fit / 2)
		p *= 2;
	return p;
}

enum rs_status rs_pack_layout(const struct rs_pack_desc *desc, size_t node_count,
                              size_t triangle_count, size_t material_count, struct rs_packed *out,
                              struct rs_error *err)
{
	RS_ASSERT(out);
	memset(out, 0, sizeof *out);
	uint32_t max_side = desc && desc->max_texture_size ? desc->max_texture_size
	                                                   : RS_PACK_DEFAULT_MAX_TEXTURE_SIZE;
	if (max_side < RS_PACK_MAX_ITEM_TEXELS)
		return rs_error_set(
		    err, RS_ERR_INVALID,
		    "pack: a texture size limit of %u texels cannot hold one %u-texel "
		    "item",
		    max_side, RS_PACK_MAX_ITEM_TEXELS);
	uint32_t row_items =
	    desc && desc->row_items ? desc->row_items : widest_power_of_two(max_side);
	enum rs_pack_nodes nodes = desc ? desc->nodes : RS_PACK_NODES_COMPACT;
	if (nodes != RS_PACK_NODES_COMPACT && nodes != RS_PACK_NODES_PAPER &&
	    nodes != RS_PACK_NODES_WIDE4)
		return rs_error_set(err, RS_ERR_INVALID, "pack: unknown node format %d",
		                    (int)nodes);
	enum rs_pack_orders orders = desc ? desc->orders : RS_PACK_ORDERS_DIRECTIONAL;
	if (orders != RS_PACK_ORDERS_DIRECTIONAL && orders != RS_PACK_ORDERS_SINGLE &&
	    orders != RS_PACK_ORDERS_OCTANT)
		return rs_error_set(err, RS_ERR_INVALID, "pack: unknown node orders %d",
		                    (int)orders);
	if ((uint64_t)row_items * RS_PACK_MAX_ITEM_TEXELS > max_side)
		return rs_error_set(
		    err, RS_ERR_INVALID,
		    "pack: %u items per row need %llu texels, over the texture size "
		    "limit of %u",
		    row_items, (unsigned long long)row_items * RS_PACK_MAX_ITEM_TEXELS, max_side);
	if (node_count >= RS_PACK_MAX_ITEMS || triangle_count >= RS_PACK_MAX_ITEMS ||
	    material_count >= RS_PACK_MAX_ITEMS)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "pack: %zu nodes, %zu triangles, %zu materials: each must stay "
		                    "below 2^24 to index exactly through floats",
		                    node_count, triangle_count, material_count);
	/* Six (or eight) orders where they fit the limits, else the one (ordered copies are a
	 * speed-up, never a reason to refuse a scene). */
	/* Wide nodes are ordered per ray at each node (octant order), never copied. */
	uint32_t copies = orders == RS_PACK_ORDERS_OCTANT ? 8u : 6u;
	uint32_t node_orders =
	             orders == RS_PACK_ORDERS_SINGLE || nodes == RS_PACK_NODES_WIDE4 ? 1u : copies,
	         w, h;
	rs_pack_texture_size(node_count * copies, texture_texels(0, nodes), row_items, &w, &h);
	if (node_count * copies >= RS_PACK_MAX_ITEMS || h > max_side)
		node_orders = 1u;
	struct rs_texture *tex[4] = {&out->nodes, &out->triangles, &out->normals, &out->materials};
	size_t items[4] = {node_count * node_orders, triangle_count, triangle_count,
	                   material_count};
	for (int i = 0; i < 4; i++) {
		rs_pack_texture_size(items[i], texture_texels(i, nodes), row_items, &tex[i]->width,
		                     &tex[i]->height);
		if (tex[i]->height > max_side) {
			enum rs_status s = rs_error_set(
			    err, RS_ERR_LIMIT,
			    "pack: %zu %ss need %u texture rows of %u, over the texture size limit "
			    "of %u texels (GL_MAX_TEXTURE_SIZE)",
			    items[i], texture_names[i], tex[i]->height, row_items, max_side);
			memset(out, 0, sizeof *out);
			return s;
		}
	}
	out->node_count = (uint32_t)node_count;
	out->triangle_count = (uint32_t)triangle_count;
	out->material_count = (uint32_t)material_count;
	out->row_items = row_items;
	out->max_texture_size = max_side;
	out->node_format = nodes;
	out->node_orders = node_orders;
	out->nodes.format = nodes == RS_PACK_NODES_PAPER ? RS_TEXEL_RGBA32F : RS_TEXEL_RGBA32UI;
	return RS_OK;
}

enum rs_status rs_pack_check(const struct rs_packed *packed, struct rs_error *err)
{
	RS_ASSERT(packed);
	if (packed->row_items == 0)
		return rs_error_set(err, RS_ERR_INVALID, "pack: not laid out (row width 0)");
	const struct rs_texture *tex[4] = {&packed->nodes, &packed->triangles, &packed->normals,
	                                   &packed->materials};
	size_t items[4] = {(size_t)packed->node_count * packed->node_orders, packed->triangle_count,
	                   packed->triangle_count, packed->material_count};
	for (int i = 0; i < 4; i++) {
		uint32_t w, h;
		rs_pack_texture_size(items[i], texture_texels(i, packed->node_format),
		                     packed->row_items, &w, &h);
		enum rs_texel_format f = i == 0 && packed->node_format != RS_PACK_NODES_PAPER
		                             ? RS_TEXEL_RGBA32UI
		                             : RS_TEXEL_RGBA32F;
		if (!tex[i]->texels || tex[i]->width != w || tex[i]->height != h ||
		    tex[i]->format != f)
			return rs_error_set(err, RS_ERR_INVALID,
			                    "pack: %s texture missing or not %ux%u as laid out for "
			                    "%u items per row",
			                    texture_names[i], w, h, packed->row_items);
	}
	return RS_OK;
}

static size_t texture_floats(const struct rs_texture *t)
{
	return (size_t)t->width * t->height * 4u;
}

enum rs_status rs_pack_alloc(struct rs_packed *packed, struct rs_error *err)
{
	RS_ASSERT(packed);
	struct rs_texture *tex[4] = {&packed->nodes, &packed->triangles, &packed->normals,
	                             &packed->materials};
	for (int i = 0; i < 4; i++) {
		tex[i]->texels = calloc(texture_floats(tex[i]), sizeof(float));
		if (!tex[i]->texels) {
			for (int j = 0; j < i; j++) {
				free(tex[j]->texels);
				tex[j]->texels = NULL;
			}
			return rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory");
		}
	}
	return RS_OK;
}

void rs_pack_free(struct rs_packed *packed)
{
	if (!packed)
		return;
	free(packed->nodes.texels);
	free(packed->triangles.texels);
	free(packed->normals.texels);
	free(packed->materials.texels);
	memset(packed, 0, sizeof *packed);
}

static float *texel(struct rs_texture *tex, uint32_t texels_per_item, uint32_t item, uint32_t j)
{
	return (float *)rs_pack_texel(tex, texels_per_item, item, j);
}

static void set4(float *t, float a, float b, float c, float d)
{
	t[0] = a;
	t[1] = b;
	t[2] = c;
	t[3] = d;
}

static enum rs_status check_packed(const struct rs_scene *scene, const struct rs_bvh_node *nodes,
                                   size_t node_count, const uint32_t *triangle_order,
                                   const struct rs_packed *p, struct rs_error *err)
{
	size_t tris = rs_scene_triangle_count(scene);
	if (p->node_count != node_count || p->triangle_count != tris ||
	    p->material_count != rs_scene_material_count(scene))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pack: layout counts do not match the scene and BVH");
	enum rs_status s = rs_pack_check(p, err);
	if (s != RS_OK)
		return s;
	if (node_count && !nodes)
		return rs_error_set(err, RS_ERR_INVALID, "pack: no nodes");
	if (tris && !triangle_order)
		return rs_error_set(err, RS_ERR_INVALID, "pack: no triangle order");
	for (size_t t = 0; t < tris; t++)
		if (triangle_order[t] >= tris)
			return rs_error_set(
			    err, RS_ERR_BAD_DATA,
			    "pack: triangle order slot %zu names triangle %u of %zu", t,
			    triangle_order[t], tris);
	for (size_t i = 0; i < node_count; i++) {
		if (nodes[i].escape > node_count || (size_t)nodes[i].first + nodes[i].count > tris)
			return rs_error_set(err, RS_ERR_BAD_DATA, "pack: node %zu out of range", i);
		/* compact and wide nodes store no escape for a leaf: it must be the next node */
		if (p->node_format != RS_PACK_NODES_PAPER && nodes[i].level == 0 &&
		    nodes[i].escape != i + 1)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "pack: leaf %zu escapes to %u, not to the next node", i,
			                    nodes[i].escape);
	}
	return RS_OK;
}

/* Vertices relative to the centre (docs/tracer.md R1): subtracted in double, then rounded. */
static void pack_triangles(const struct rs_scene *scene, const uint32_t *triangle_order,
                           struct rs_packed *packed)
{
	const double *pos = rs_scene_positions_f64(scene);
	const float *nrm = rs_scene_normals(scene);
	const uint32_t *idx = rs_scene_indices(scene);
	const uint32_t *mat = rs_scene_triangle_materials(scene);
	const double *o = packed->origin;
	for (uint32_t slot = 0; slot < packed->triangle_count; slot++) {
		uint32_t tri = triangle_order[slot];
		const uint32_t *v = idx + 3 * (size_t)tri;
		for (uint32_t k = 0; k < 3; k++) {
			const double *p = pos + 3 * (size_t)v[k];
			const float *nn = nrm + 3 * (size_t)v[k];
			float w = k == 0 ? (float)tri : k == 1 ? (float)mat[tri] : 0.0f;
			set4(texel(&packed->triangles, RS_PACK_TRIANGLE_TEXELS, slot, k),
			     (float)(p[0] - o[0]), (float)(p[1] - o[1]), (float)(p[2] - o[2]), w);
			set4(texel(&packed->normals, RS_PACK_NORMAL_TEXELS, slot, k), nn[0], nn[1],
			     nn[2], 0.0f);
		}
	}
}

enum rs_status rs_pack_scene(const struct rs_scene *scene, const struct rs_bvh_node *nodes,
                             size_t node_count, const uint32_t *triangle_order,
                             struct rs_packed *packed, struct rs_error *err)
{
	RS_ASSERT(scene && packed);
	enum rs_status s = check_packed(scene, nodes, node_count, triangle_order, packed, err);
	if (s != RS_OK)
		return s;
	struct rs_texture *tex[4] = {&packed->nodes, &packed->triangles, &packed->normals,
	                             &packed->materials};
	for (int i = 0; i < 4; i++)
		memset(tex[i]->texels, 0, texture_floats(tex[i]) * sizeof(float));

	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	for (int a = 0; a < 3; a++)
		packed->origin[a] = b.hi[a] >= b.lo[a] ? 0.5 * (b.lo[a] + b.hi[a]) : 0.0;
	pack_triangles(scene, triangle_order, packed);
	s = rs__pack_nodes(nodes, node_count, packed, err);
	if (s != RS_OK)
		return s;

	const struct rs_material *m = rs_scene_materials(scene);
	for (uint32_t i = 0; i < packed->material_count; i++) {
		float shininess = m[i].shininess == 0.0f ? 1.0f : m[i].shininess;
		float ior = m[i].ior == 0.0f ? 1.0f : m[i].ior;
		set4(texel(&packed->materials, RS_PACK_MATERIAL_TEXELS, i, 0), m[i].diffuse[0],
		     m[i].diffuse[1], m[i].diffuse[2], m[i].specular);
		set4(texel(&packed->materials, RS_PACK_MATERIAL_TEXELS, i, 1), shininess,
		     m[i].reflectance, m[i].transmittance, ior);
		set4(texel(&packed->materials, RS_PACK_MATERIAL_TEXELS, i, 2), (float)m[i].flags,
		     0.0f, 0.0f, 0.0f);
	}
	return RS_OK;
}
