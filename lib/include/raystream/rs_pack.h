/**
 * @file rs_pack.h
 * The scene and its BVH packed into textures, exactly as the GLES kernels read them and as
 * the CPU reference tracer traverses them. Integers in float textures are stored as floats
 * (exact below 2^24). Items are laid out `row_items` per texture row (a packing parameter,
 * struct rs_pack_desc, chosen so a row fits the device's texture size limit); item k's
 * texel j sits at x = (k % row_items) * texels_per_item + j, y = k / row_items. A texture
 * with fewer items than row_items is one row of exactly its items, so every texture is
 * `width / texels_per_item` items wide, without padding at row ends.
 *
 * nodes, three formats (rs_pack_desc.nodes); the first two are the paper's threaded pre-order
 * array with escape indices (a leaf's escape is always the next node, k + 1):
 *   RS_PACK_NODES_COMPACT (default), 1 RGBA32UI texel per node, bounds on a 16-bit grid:
 *                                          x = qlo.x | qlo.y << 16, y = qlo.z | qhi.x << 16,
 *                                          z = qhi.y | qhi.z << 16,
 *                                          w = leaf ? RS_PACK_LEAF_BIT | first : escape
 *     bound = node_grid_origin + q * node_grid_step per axis, exact in fp32 (the step is a
 *     power of two, see rs_packed); lo rounded down and hi up, so a compact box holds the
 *     tight one. A leaf's triangles run from `first` to the slot whose last flag is set.
 *     An empty leaf is stored as an interior node whose escape is k + 1.
 *   RS_PACK_NODES_PAPER, 3 RGBA32F texels per node: t0 = (lo.xyz, escape)
 *                                          t1 = (hi.xyz, level)       level 0 = leaf
 *                                          t2 = (first, count, order, 0)
 *   RS_PACK_NODES_WIDE4, not threaded: a 4-wide tree collapsed from the binary one, walked
 *     with a short stack (docs/bvh.md "Wide nodes"). 3 RGBA32UI texels per node, holding its
 *     up to four children's boxes, child c's byte at bits 8c of each word:
 *                                          t0 = (qlo.x, qlo.y, qlo.z, qhi.x)
 *                                          t1 = (qhi.y, qhi.z, o.x | o.y << 16,
 *                                                o.z | e.x << 16 | e.y << 20 | e.z << 24
 *                                                    | children << 28)
 *                                          t2 = (child 0, 1, 2, 3)
 *     child bound on the compact grid: Q = o + (q << e), bound = node_grid_origin + Q *
 *     node_grid_step (Q < 2^18, exact in fp32 as compact bounds are); lo rounded down, hi
 *     up, so a child's box holds its compact box. Children fill slots 0 .. children - 1; a
 *     child word is RS_PACK_LEAF_BIT | first slot for a leaf (ended by the last flag), else
 *     the child node's index (always above its parent's). Node 0 is the root; node_count
 *     items are reserved (the binary tree's count), the tree uses the first ones.
 * triangles (3 texels, BVH slot order):   t0 = (v0.xyz, scene triangle id)
 *                                          t1 = (v1.xyz, material id)
 *                                          t2 = (v2.xyz, last)  last = 1 on a leaf's last slot
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

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Texels per texture side that OpenGL ES 3.0 guarantees (GL_MAX_TEXTURE_SIZE's minimum):
 * the default limit, so a scene packed with defaults loads on every GLES 3.0 device. */
#define RS_PACK_DEFAULT_MAX_TEXTURE_SIZE 2048u
/** Widest item: the texels per row must hold one item of every kind. */
#define RS_PACK_MAX_ITEM_TEXELS 3u
#define RS_PACK_NODE_TEXELS 3u
#define RS_PACK_COMPACT_NODE_TEXELS 1u
/** Compact node word w: set for a leaf, whose low bits are its first triangle slot. */
#define RS_PACK_LEAF_BIT 0x80000000u
/** Compact node bounds: grid positions per axis (16 bits). */
#define RS_PACK_GRID_STEPS 65535u
/** Wide nodes: texels a node, children a node, and the walk's stack entries. Packing
 * refuses a tree whose walk could ever need more entries (RS_ERR_LIMIT), so the kernels'
 * fixed stack never overflows (docs/bvh.md "Wide nodes"). */
#define RS_PACK_WIDE_NODE_TEXELS 3u
#define RS_PACK_WIDE_CHILDREN 4u
#define RS_PACK_WIDE_STACK 48u
#define RS_PACK_TRIANGLE_TEXELS 3u
#define RS_PACK_NORMAL_TEXELS 3u
#define RS_PACK_MATERIAL_TEXELS 3u
/** Largest item count whose indices are exact in a float. */
#define RS_PACK_MAX_ITEMS (1u << 24)

/** Texel formats of a packed texture. */
enum rs_texel_format {
	RS_TEXEL_RGBA32F = 0,  /**< four floats a texel: `texels` */
	RS_TEXEL_RGBA32UI = 1, /**< four 32-bit unsigned integers a texel: `words` */
};

/** Node formats (rs_pack_desc.nodes): two threaded pre-order layouts and a wide one. */
enum rs_pack_nodes {
	/** One RGBA32UI texel a node: one texture fetch per box instead of two or three. */
	RS_PACK_NODES_COMPACT = 0,
	/** The paper's three RGBA32F texels a node, exact float bounds. */
	RS_PACK_NODES_PAPER = 1,
	/** 4-wide nodes of quantised child boxes, 3 RGBA32UI texels testing four boxes, walked
	 * with a stack in the ray's octant order (one node order). Exact, and 20-25 % slower
	 * than compact on llvmpipe (docs/benchmarks.md), so not the default. */
	RS_PACK_NODES_WIDE4 = 2,
};

/** How many pre-orders of the tree the node texture holds (rs_pack_desc.orders). */
enum rs_pack_orders {
	/** Six (the default): one per major direction (+x, -x, +y, -y, +z, -z), each visiting at
	 * every node first the child whose box centre comes first along that direction; a ray
	 * walks the one of its own major direction (rs_pack_node_order), so it meets near boxes
	 * first (closest hits prune more). Six times the node texture; where six do not fit the
	 * texture size limit (or 2^24 items), one order is packed instead (rs_packed.node_orders
	 * says which). */
	RS_PACK_ORDERS_DIRECTIONAL = 0,
	/** One: the builder's order, as the paper. */
	RS_PACK_ORDERS_SINGLE = 1,
	/** Eight: one per octant of the ray's direction (the signs of x, y, z), each visiting at
	 * every node first the child whose box centre comes first, along the axis the two
	 * centres are farthest apart (the node's split), in the direction of the octant's sign
	 * there: three-mesh-bvh's per-node child order, made stackless by keeping eight copies
	 * (rs_pack_node_order_of). Eight times the node texture; one order where eight do not
	 * fit, as directional. */
	RS_PACK_ORDERS_OCTANT = 2,
};

/** A texture image: width * height * 4 values, row-major, caller-owned. */
struct rs_texture {
	union {
		float *texels;   /**< RS_TEXEL_RGBA32F */
		uint32_t *words; /**< RS_TEXEL_RGBA32UI (the same storage) */
	};
	uint32_t width;
	uint32_t height;
	enum rs_texel_format format;
};

/** Packing options; zero-initialised means defaults. */
struct rs_pack_desc {
	/** Largest texture side in texels, as the device reports it (GL_MAX_TEXTURE_SIZE);
	 * 0 -> RS_PACK_DEFAULT_MAX_TEXTURE_SIZE (2048). Rows and row width stay within it. */
	uint32_t max_texture_size;
	/** Items per texture row; 0 -> the largest power of two that fits (max_texture_size / 3
	 * rounded down: 512 at 2048), so kernels address items by mask and shift. */
	uint32_t row_items;
	/** Node format; 0 -> RS_PACK_NODES_COMPACT. Wide nodes pack one order (orders is
	 * ignored). */
	enum rs_pack_nodes nodes;
	/** Node orders; 0 -> RS_PACK_ORDERS_DIRECTIONAL. */
	enum rs_pack_orders orders;
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
	uint32_t row_items;        /**< items per row of every texture (the kernels' row width) */
	uint32_t max_texture_size; /**< the limit the layout was made for (resolved) */
	double origin[3]; /**< world position of the packed frame's origin (set by packing) */
	enum rs_pack_nodes node_format; /**< the nodes texture's format (resolved) */
	/** Pre-orders in the node texture (1, 6 or 8): order d holds items [d * node_count,
	 * (d + 1) * node_count), escapes are absolute items, a ray starts at its order's first. */
	uint32_t node_orders;
	/** Compact nodes: bound = grid_origin + q * grid_step (packed frame). The step is a power
	 * of two and the origin a multiple of it below 2^23 steps, so every bound is exact in
	 * fp32 however a GPU rounds (set by packing; 0 for paper nodes). */
	float node_grid_origin[3];
	float node_grid_step[3];
};

/** One node as both threaded formats decode it (bounds in the packed frame). */
struct rs_pack_node {
	float lo[3];
	float hi[3];
	uint32_t escape; /**< next node when the box is missed (a leaf's: k + 1) */
	bool leaf;
	uint32_t first; /**< leaf: first triangle slot */
	uint32_t count; /**< leaf: triangle slots (compact: up to the slot with the last flag) */
};

/** One wide node as it decodes (RS_PACK_NODES_WIDE4; bounds in the packed frame). */
struct rs_pack_wide {
	uint32_t children; /**< valid slots, 0..4 */
	float lo[RS_PACK_WIDE_CHILDREN][3];
	float hi[RS_PACK_WIDE_CHILDREN][3];
	/** Child bounds on the compact grid (node_grid_origin + q * node_grid_step): integers
	 * the walk orders children by, exactly as the kernels do. */
	int32_t qlo[RS_PACK_WIDE_CHILDREN][3];
	int32_t qhi[RS_PACK_WIDE_CHILDREN][3];
	uint32_t child[RS_PACK_WIDE_CHILDREN]; /**< RS_PACK_LEAF_BIT | first slot, or a node */
};

/**
 * Two-level packing of a scene's instances (rs_scene_add_instance, docs/bvh.md "Instances"):
 * one bottom-level tree (BLAS) per prototype mesh, built and packed once in the prototype's
 * own space (origin: its centre), and a top-level tree (TLAS) over the instances' world boxes.
 * The TLAS is packed as an ordinary rs_packed whose "triangles" are degenerate: item i holds
 * instance i's box as (lo, hi, (lo + hi) / 2), widened so that rounding to float never
 * shrinks it, with the instance id in t0.w; a TLAS leaf's items are instances, not triangles.
 * to_object[i] maps world to the BLAS frame of instance i's mesh (world -> object, times the
 * mesh's mesh_scale, minus its packed origin), to_world_normal[i] the inverse transpose
 * (object -> world normals; scaled by a power of two as well when its largest entry is outside
 * [2^-10, 2^10], since only its direction counts). A prototype's BLAS is packed from its positions
 * times mesh_scale, a power of two that brings a half extent outside [2^-10, 2^10] into [1, 2) (1
 * otherwise, and for the loose triangles), so the fp32 walk in its frame neither overflows nor
 * flushes (R7) whatever units the prototype was modelled in. Triangles of the scene outside every
 * instance (rs_scene_add_mesh) go into one more BLAS, meshes[mesh_count - 1] when `loose_ids` is
 * set, walked through one more identity instance (the last); loose_ids maps its local triangle ids
 * to scene ids. Threaded node formats only (compact or paper); wide4 is refused.
 */
struct rs_packed_instances {
	struct rs_packed top;     /**< TLAS over instance boxes (its triangles are boxes) */
	struct rs_packed *meshes; /**< BLAS per prototype mesh, mesh_count of them */
	uint32_t mesh_count;
	uint32_t instance_count;
	double (*to_object)[3][4];       /**< per instance: world -> mesh's packed frame */
	double (*to_world_normal)[3][3]; /**< per instance: inverse transpose of the 3x3 part */
	uint32_t *mesh;                  /**< per instance: its prototype */
	uint32_t *first_triangle;        /**< per instance: scene id of its first triangle */
	uint32_t *loose_ids; /**< the loose BLAS's local -> scene triangle ids, or NULL */
	double build_ms;     /**< BLAS + TLAS builds (without packing) */
	/** The TLAS's own build and pack, of rs_pack_instances() or the last
	 * rs_pack_instances_update(). */
	double top_build_ms, top_pack_ms;
	/** Per mesh: its object-space box (of the BLAS's vertices), what the TLAS's instance
	 * boxes are made from (mesh_count of them). */
	struct rs_bounds *mesh_bounds;
	/** Per mesh: the power of two its BLAS frame is scaled by (see above). */
	double *mesh_scale;
	struct rs_pack_desc pack; /**< the pack options as given (updates repack the TLAS so) */
};

/**
 * Build and pack a scene's instances in two levels (see struct rs_packed_instances) with the
 * given builder (NULL: defaults) and pack options (NULL: defaults). RS_ERR_INVALID when the
 * scene has no instances or `pack` asks for wide4 nodes; errors of the builder and packer
 * otherwise. Free with rs_pack_instances_free().
 */
enum rs_status rs_pack_instances(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                 const struct rs_pack_desc *pack, struct rs_packed_instances *out,
                                 struct rs_error *err);
void rs_pack_instances_free(struct rs_packed_instances *packed);

/** Texels an instance in rs_packed_two_level.instances (RGBA32F), as the kernels read them:
 *   t0..t2  to_object rows (x, y, z, w): the TLAS frame -> the BLAS's packed frame
 *   t3..t5  to_world rows: the BLAS's packed frame -> the TLAS frame (shading)
 *   t6..t8  to_world_normal rows (x, y, z); t6.w = first scene triangle id,
 *           t7.w = material (-1: the triangle's own), t8.w = 1 when mirrored (det < 0)
 *   t9      (BLAS grid origin xyz, BLAS node base: item of its order 0)
 *   t10     (BLAS grid step xyz, BLAS node count per order)
 *   t11     (BLAS triangle count, BLAS first slot, 0, 0)
 * Rows hold instance_row_items instances (a power of two).
 * A hit texel of the kernels names a scene triangle id; shading finds its instance by a
 * binary search of t6.w over the prototypes' instances (ascending, the loose instance last)
 * and its slot through the normal texture's spare channel: for a BLAS with first slot b,
 * normal texel 0 of item b + local id holds w = the slot of that triangle, and for the
 * loose BLAS normal texel 1 of item b + local holds w = its scene id (ascending). */
#define RS_PACK_INSTANCE_TEXELS 12u

/**
 * A two-level packing merged into one set of textures (docs/bvh.md "Instances on the GPU"):
 * what the GLES kernels sample and the CPU reference walks for an instanced scene.
 * all.nodes holds every BLAS (each with its tree_orders orders, escapes made absolute in
 * the merged texture) and then, from top_node_base, the TLAS, with room for
 * top_node_capacity items so that a new TLAS over the same instances fits in place.
 * all.triangles / all.normals hold every BLAS's slots (leaf first slots made absolute,
 * t0.w the prototype-local triangle id, or for the loose BLAS the scene id) and from
 * top_slot_base the TLAS's instance boxes (t0.w = instance id).
 * all.materials is the scene's. all.node_count counts node items (all trees, all orders,
 * node_orders 1 for the texture); all.triangle_count counts slots; all.origin is the TLAS
 * frame's (the frame rays are traced in); all's grid is the TLAS's.
 * A per-frame transform update touches only the rows from top_node_base's / top_slot_base's
 * on and the instance texture (top_bytes).
 */
struct rs_packed_two_level {
	struct rs_packed all;
	struct rs_texture instances; /**< RGBA32F, RS_PACK_INSTANCE_TEXELS per instance */
	uint32_t instance_count;
	uint32_t instance_row_items; /**< instances per row of `instances` */
	uint32_t tree_orders;        /**< node orders of every tree (1 or 6) */
	uint32_t top_node_base;      /**< item of the TLAS's order 0 */
	uint32_t top_node_count;     /**< TLAS nodes per order */
	uint32_t top_node_capacity;  /**< items reserved from top_node_base */
	uint32_t top_slot_base;      /**< slot of the TLAS's first instance box */
	uint32_t scene_triangles;    /**< the scene's triangle count */
	bool loose;                  /**< the last instance walks the scene's loose triangles */
	/** Bytes of the textures' TLAS rows and of the instance texture (what a transform
	 * update sends). */
	size_t top_bytes;
};

/**
 * Merge a two-level packing of `scene` (from rs_pack_instances() with the same scene) into
 * one set of textures (struct rs_packed_two_level), laid out for `pack`'s texture size
 * limit (NULL: defaults; its row width must be the one `packed` was made with).
 * RS_ERR_LIMIT when the merged textures exceed the texture size limit or 2^24 items, or
 * the trees' node orders differ (pack with RS_PACK_ORDERS_SINGLE then).
 * Free with rs_pack_two_level_free().
 */
enum rs_status rs_pack_two_level(const struct rs_scene *scene,
                                 const struct rs_packed_instances *packed,
                                 struct rs_packed_two_level *out, struct rs_error *err);
/**
 * After rs_pack_instances_update() of `packed` (same scene, new transforms): rewrite `out`'s
 * TLAS items, its frame (all.origin, the TLAS grid) and the instance texture in place, the
 * BLASes untouched, so `out` equals a fresh rs_pack_two_level(). RS_ERR_INVALID (nothing
 * changed) when `packed` is not the layout's instances or its tree does not fit the
 * reserved items.
 */
enum rs_status rs_pack_two_level_update(const struct rs_scene *scene,
                                        const struct rs_packed_instances *packed,
                                        struct rs_packed_two_level *out, struct rs_error *err);
void rs_pack_two_level_free(struct rs_packed_two_level *packed);
/** Bytes of a merged two-level packing: its four textures and the instance texture. */
size_t rs_pack_two_level_bytes(const struct rs_packed_two_level *packed);

/**
 * Per-frame instance transforms (rs_scene_set_instance_transform): rebuild and repack only the
 * TLAS of `packed` (made by rs_pack_instances() of a scene with the same prototypes,
 * instances' meshes and triangle ranges, and loose triangles) from `scene`'s current
 * transforms with `bvh` (NULL: defaults) and the pack options `packed` was made with, and
 * recompute to_object and to_world_normal. The BLASes, their origins and mesh_bounds are not
 * touched. The result equals rs_pack_instances() of `scene` (the same TLAS and transforms,
 * so the same hits). The TLAS's node count and texture sizes follow the new tree, so a GPU
 * re-uploads the whole `top` (its
 * four textures, reallocating them when a size changed) and the instance transforms (six
 * RGBA32F texels an instance), never a BLAS. RS_ERR_INVALID (one line, `packed`
 * unchanged) for another scene's instances; on any failure `packed` is unchanged.
 */
enum rs_status rs_pack_instances_update(struct rs_packed_instances *packed,
                                        const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                        struct rs_error *err);

/** Bytes of a packed scene's four textures (width * height * 16 each). */
size_t rs_pack_bytes(const struct rs_packed *packed);
/** Bytes of a two-level packing: the TLAS's and every BLAS's textures, plus the instance
 * transforms as a GPU would hold them (six RGBA32F texels an instance). */
size_t rs_pack_instances_bytes(const struct rs_packed_instances *packed);

/** Texture size for `items` items of `texels_per_item` texels each, `row_items` (> 0) per row:
 * min(items, row_items) items wide (at least 1), as many rows as needed (at least 1). */
void rs_pack_texture_size(size_t items, uint32_t texels_per_item, uint32_t row_items,
                          uint32_t *out_width, uint32_t *out_height);

/**
 * Size the four textures for a scene and BVH: fills widths/heights, counts and the resolved
 * row_items and max_texture_size of *out and sets texel pointers to NULL. `desc` NULL means
 * defaults. RS_ERR_LIMIT when a count reaches RS_PACK_MAX_ITEMS or a texture would need more
 * rows than max_texture_size (the message names the limit); RS_ERR_INVALID when
 * max_texture_size cannot hold one item (< 3) or row_items * 3 exceeds it.
 */
enum rs_status rs_pack_layout(const struct rs_pack_desc *desc, size_t node_count,
                              size_t triangle_count, size_t material_count, struct rs_packed *out,
                              struct rs_error *err);

/**
 * Check that `packed` (not NULL) is laid out as rs_pack_layout() makes it for its counts and
 * row_items and has every texel buffer: the condition for reading it through
 * rs_pack_texel(). RS_ERR_INVALID naming the first texture that is not.
 */
enum rs_status rs_pack_check(const struct rs_packed *packed, struct rs_error *err);

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

/**
 * Decode node k (< node_count) of a packed BVH in either threaded format (not wide4: see
 * rs_pack_read_wide), as the kernels read it.
 * Corrupt data never reads outside the textures: an escape is at least k + 1 and a leaf's
 * slots end at triangle_count.
 */
void rs_pack_read_node(const struct rs_packed *packed, uint32_t k, struct rs_pack_node *out);

/** Decode wide node k (< node_count) of a RS_PACK_NODES_WIDE4 texture, as the kernels read
 * it. Corrupt data never reads outside the textures: a child node index that is not above k
 * and below node_count, or a leaf's first slot at or past triangle_count, drops the slot
 * (the kernels drop the same). */
void rs_pack_read_wide(const struct rs_packed *packed, uint32_t k, struct rs_pack_wide *out);

/** The node order a ray with direction d walks when packed->node_orders is 6: the major axis
 * (largest |d|, ties to the lower axis) times two, plus one when that component is negative.
 * The kernels choose the same way in fp32. */
static inline uint32_t rs_pack_node_order(const double d[3])
{
	double ax = d[0] < 0 ? -d[0] : d[0], ay = d[1] < 0 ? -d[1] : d[1];
	double az = d[2] < 0 ? -d[2] : d[2];
	int axis = ay > ax ? 1 : 0;
	if (az > (axis ? ay : ax))
		axis = 2;
	return 2u * (uint32_t)axis + (d[axis] < 0.0 ? 1u : 0u);
}

/** The node order a ray with direction d walks in a texture of `orders` pre-orders: 0 for
 * one, rs_pack_node_order() for six, and for eight (RS_PACK_ORDERS_OCTANT) the octant
 * (d[0] < 0) + 2 (d[1] < 0) + 4 (d[2] < 0). The kernels choose the same way in fp32. */
static inline uint32_t rs_pack_node_order_of(uint32_t orders, const double d[3])
{
	if (orders == 8)
		return (d[0] < 0.0 ? 1u : 0u) | (d[1] < 0.0 ? 2u : 0u) | (d[2] < 0.0 ? 4u : 0u);
	return orders > 1 ? rs_pack_node_order(d) : 0u;
}

/** An index stored in a float texel (exact below 2^24); NaN, negative or huge values (corrupt
 * data) give UINT32_MAX, which every reader treats as out of range. */
static inline uint32_t rs_pack_index(float f)
{
	return f >= 0.0f && f < 4294967040.0f ? (uint32_t)f : UINT32_MAX;
}

/** Where texel j of item k sits in a texture laid out `row_items` per row (what a kernel
 * passes to texelFetch). */
static inline void rs_pack_texel_xy(uint32_t row_items, uint32_t texels_per_item, uint32_t item,
                                    uint32_t j, uint32_t *out_x, uint32_t *out_y)
{
	*out_x = (item % row_items) * texels_per_item + j;
	*out_y = item / row_items;
}

/**
 * Texel j of item k of a texture made by rs_pack_layout() (4 floats). Rows hold exactly
 * width / texels_per_item items with no padding, so the texel at (x, y) of
 * rs_pack_texel_xy() is the (k * texels_per_item + j)-th of the image for every row width:
 * the CPU walks the very layout the kernels sample without a division per fetch.
 * tests/test_pack.c checks the identity at several row widths.
 */
static inline const float *rs_pack_texel(const struct rs_texture *tex, uint32_t texels_per_item,
                                         uint32_t item, uint32_t j)
{
	return tex->texels + ((size_t)item * texels_per_item + j) * 4u;
}

#ifdef __cplusplus
}
#endif
#endif
