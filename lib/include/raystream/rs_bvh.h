/**
 * @file rs_bvh.h
 * Bounding volume hierarchies over a triangle list, all emitted in one GPU layout: the
 * paper's *threaded* pre-order array. Traversal walks the array forward: test node i; on a
 * hit go to i + 1, on a miss (or after a leaf) jump to escape(i). No stack.
 *
 * Plain functions over caller-owned arrays (size them with rs_bvh_node_bound()).
 */
#ifndef RS_BVH_H
#define RS_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Which builder. Zero (the default) is the best one. */
enum rs_bvh_builder {
	RS_BVH_SAH = 0,    /**< top-down binned SAH */
	RS_BVH_NONE = 1,   /**< one flat list: every ray tests every triangle */
	RS_BVH_LINEAR = 2, /**< boxes of leaf_size (8) triangles in input order, a flat list */
	RS_BVH_PAPER = 3,  /**< complete binary tree bottom-up over input order, padded to 2^k */
};

/** Builder options; zero-initialised means defaults (see rs_bvh_desc_resolve()). */
struct rs_bvh_desc {
	enum rs_bvh_builder builder;
	uint32_t leaf_size;   /**< max triangles per leaf: SAH 0 -> 4, LINEAR 0 -> 8; PAPER is 1 */
	uint32_t sah_bins;    /**< 0 -> 16 */
	float traversal_cost; /**< SAH cost of a box test relative to a triangle test; 0 -> 1 */
	/** SAH builder threads, the caller's included; 0 -> 1. The tree is the same for every
	 *  count (the threads share the work, never the decisions). */
	uint32_t threads;
};

/** Largest rs_bvh_desc.threads. */
#define RS_BVH_MAX_THREADS 256u

/**
 * One node of the threaded pre-order layout.
 * Invariants (checked by rs_bvh_check()):
 *  - node 0 is the root; a node's subtree is the contiguous range [i, escape). The flat
 *    builders (NONE, LINEAR) emit a forest instead: a list of top-level leaves, each one's
 *    escape being the next; the walk is the same;
 *  - escape = index of the first node after i's subtree (node_count for the last subtree);
 *  - level = height above the leaves (leaf: level 0); order = position among the nodes of
 *    the same level, counted left to right;
 *  - leaves (level 0) own triangles [first, first + count) of the triangle order; interior
 *    nodes have count 0; padding leaves of the PAPER builder have count 0 and empty bounds
 *    (lo = +FLT_MAX, hi = -FLT_MAX);
 *  - every node's box contains its children's boxes and its triangles.
 */
struct rs_bvh_node {
	float lo[3];
	float hi[3];
	uint32_t level;
	uint32_t order;
	uint32_t escape;
	uint32_t first;
	uint32_t count;
};

/** Fill in the defaults of `desc` (NULL: all defaults). */
void rs_bvh_desc_resolve(const struct rs_bvh_desc *desc, struct rs_bvh_desc *out);

/** Short builder name ("sah", "none", "linear", "paper"). */
const char *rs_bvh_builder_name(enum rs_bvh_builder builder);
/** Parse a builder name; RS_ERR_INVALID if unknown. */
enum rs_status rs_bvh_builder_parse(const char *name, enum rs_bvh_builder *out,
                                    struct rs_error *err);

/** Worst-case node count for `triangle_count` triangles with this descriptor. */
size_t rs_bvh_node_bound(const struct rs_bvh_desc *desc, size_t triangle_count);

/**
 * Build a BVH.
 * @param positions      xyz per vertex (tightly packed floats), caller-owned
 * @param indices        three vertex indices per triangle, caller-owned
 * @param out_nodes      caller-owned, node_capacity >= rs_bvh_node_bound()
 * @param out_triangle_order caller-owned, triangle_count entries: slot -> input triangle id
 * @param out_node_count nodes written
 * Builder scratch memory is allocated and freed inside the call.
 */
enum rs_status rs_bvh_build(const struct rs_bvh_desc *desc, const float *positions,
                            size_t vertex_count, const uint32_t *indices, size_t triangle_count,
                            struct rs_bvh_node *out_nodes, size_t node_capacity,
                            uint32_t *out_triangle_order, size_t *out_node_count,
                            struct rs_error *err);

/**
 * Refit a built hierarchy to moved vertices: the same topology (escape, level, order, first,
 * count and the triangle order are kept), every box recomputed bottom-up from `positions`
 * (the mesh's new positions, same `indices` as at the build). One pass over the nodes and
 * triangles, no allocation. RS_ERR_BAD_DATA, with the tree unchanged, for a NaN or
 * infinite vertex, an index out of range or a tree whose escapes or leaves are out of
 * range. The refitted boxes may overlap more than a build's would: compare
 * rs_bvh_stats().sah_cost against the cost at the build to decide when to rebuild
 * (docs/bvh.md, "Refit").
 */
enum rs_status rs_bvh_refit(struct rs_bvh_node *nodes, size_t node_count, const float *positions,
                            size_t vertex_count, const uint32_t *indices,
                            const uint32_t *triangle_order, size_t triangle_count,
                            struct rs_error *err);

/** The refitted tree's SAH cost over the cost at its last build past which the renderers
 * rebuild instead (rs_render_desc.rebuild_ratio's default; measured in docs/bvh.md). */
#define RS_BVH_REBUILD_RATIO 1.15

/**
 * Check every invariant listed at struct rs_bvh_node (escape against its definition,
 * containment, level/order, the triangle order being a permutation). RS_OK or
 * RS_ERR_BAD_DATA with the first violation named in err.
 */
enum rs_status rs_bvh_check(const struct rs_bvh_node *nodes, size_t node_count,
                            const float *positions, const uint32_t *indices,
                            const uint32_t *triangle_order, size_t triangle_count,
                            struct rs_error *err);

/** Summary figures of a built hierarchy (for benchmarks and logs). */
struct rs_bvh_stats {
	size_t nodes, leaves, empty_leaves;
	uint32_t depth;  /**< levels on the longest root-to-leaf path */
	double sah_cost; /**< expected cost under the SAH with traversal_cost, tri cost 1 */
	double mean_leaf_size;
};
void rs_bvh_stats(const struct rs_bvh_node *nodes, size_t node_count, float traversal_cost,
                  struct rs_bvh_stats *out);

#ifdef __cplusplus
}
#endif
#endif
