/**
 * @file rs_pack.h
 * The scene and its BVH packed into RGBA32F textures, exactly as the GLES kernels read
 * them and as the CPU reference tracer traverses them. Integers are stored as floats
 * (exact below 2^24). Items are laid out RS_PACK_ROW_ITEMS per texture row; item k's
 * texel j sits at x = (k % RS_PACK_ROW_ITEMS) * texels_per_item + j, y = k / RS_PACK_ROW_ITEMS.
 *
 * nodes (3 texels per node, pre-order):   t0 = (lo.xyz, escape)
 *                                          t1 = (hi.xyz, level)       level 0 = leaf
 *                                          t2 = (first, count, order, 0)
 * triangles (3 texels, BVH slot order):   t0 = (v0.xyz, scene triangle id)
 *                                          t1 = (v1.xyz, material id)
 *                                          t2 = (v2.xyz, 0)
 * normals (3 texels, BVH slot order):     (n0.xyz, 0), (n1.xyz, 0), (n2.xyz, 0)
 * materials (3 texels per material):      t0 = (diffuse.rgb, specular)
 *                                          t1 = (shininess, reflectance, transmittance, ior)
 *                                          t2 = (flags, 0, 0, 0)
 * Material defaults (shininess 0 -> 1, ior 0 -> 1) are resolved when packing.
 *
 * Positions (vertices and node bounds) are stored relative to `origin`, the centre of the
 * scene's bounds: world = origin + stored. The centre is subtracted in double before
 * rounding, so a scene far from the world origin packs as it would at the origin. Backends
 * move the camera, lights and environment into this frame (docs/tracer.md R1).
 */
#ifndef RS_PACK_H
#define RS_PACK_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RS_PACK_ROW_ITEMS 1024u
#define RS_PACK_NODE_TEXELS 3u
#define RS_PACK_TRIANGLE_TEXELS 3u
#define RS_PACK_NORMAL_TEXELS 3u
#define RS_PACK_MATERIAL_TEXELS 3u
/** Largest item count whose indices are exact in a float. */
#define RS_PACK_MAX_ITEMS (1u << 24)

/** An RGBA32F texture image: width * height * 4 floats, row-major, caller-owned. */
struct rs_texture {
	float *texels;
	uint32_t width;
	uint32_t height;
};

/** Everything the kernels read; caller-owned storage. */
struct rs_packed {
	struct rs_texture nodes;
	struct rs_texture triangles;
	struct rs_texture normals;
	struct rs_texture materials;
	uint32_t node_count;
	uint32_t triangle_count;
	uint32_t material_count;
	double origin[3]; /**< world position of the packed frame's origin (set by packing) */
};

/** Texture size for `items` items of `texels_per_item` texels each. */
void rs_pack_texture_size(size_t items, uint32_t texels_per_item, uint32_t *out_width,
                          uint32_t *out_height);

/**
 * Size the four textures for a scene and BVH: fills widths/heights and counts of *out and
 * sets texel pointers to NULL. RS_ERR_LIMIT when a count reaches RS_PACK_MAX_ITEMS.
 */
enum rs_status rs_pack_layout(size_t node_count, size_t triangle_count, size_t material_count,
                              struct rs_packed *out, struct rs_error *err);

/**
 * Pack. `packed` must come from rs_pack_layout() with the same counts and have texel
 * buffers of width * height * 4 floats attached by the caller. Unused texels are zeroed.
 * Sets packed->origin; node bounds are recomputed (tight) from the packed vertices, so only
 * the BVH's topology and triangle order are used, not its float bounds.
 */
enum rs_status rs_pack_scene(const struct rs_scene *scene, const struct rs_bvh_node *nodes,
                             size_t node_count, const uint32_t *triangle_order,
                             struct rs_packed *packed, struct rs_error *err);

/** Convenience: allocate the texel buffers of a laid-out rs_packed (free with rs_pack_free). */
enum rs_status rs_pack_alloc(struct rs_packed *packed, struct rs_error *err);
/** Free buffers allocated by rs_pack_alloc() and zero the struct. */
void rs_pack_free(struct rs_packed *packed);

/** Texel j of item k of a packed texture (4 floats). */
static inline const float *rs_pack_texel(const struct rs_texture *tex, uint32_t texels_per_item,
                                         uint32_t item, uint32_t j)
{
	uint32_t x = (item % RS_PACK_ROW_ITEMS) * texels_per_item + j;
	uint32_t y = item / RS_PACK_ROW_ITEMS;
	return tex->texels + ((size_t)y * tex->width + x) * 4u;
}

#ifdef __cplusplus
}
#endif
#endif
