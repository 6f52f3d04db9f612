/* Refit: a tree whose triangles moved keeps its topology (escapes, levels, leaves and the
 * triangle order) and gets its boxes recomputed bottom-up. Far cheaper than a build (one
 * pass over the nodes, no sorting), but the boxes of a tree built for other positions may
 * overlap more: the caller compares the SAH cost against the cost at the last build and
 * rebuilds past a ratio (docs/bvh.md, "Refit"). */
#include <stdbool.h>

#include "bvh_internal.h"

/* Everything the bottom-up pass reads is in range, checked before any box is written (a
 * refused refit leaves the tree as it was). */
static enum rs_status check_tree(const struct rs_bvh_node *nodes, size_t node_count,
                                 const float *positions, size_t vertex_count,
                                 const uint32_t *indices, const uint32_t *triangle_order,
                                 size_t triangle_count, struct rs_error *err)
{
	for (size_t k = 0; k < node_count; k++) {
		const struct rs_bvh_node *n = &nodes[k];
		if (n->escape <= k || n->escape > node_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh refit: node %zu escapes to %u (not in %zu..%zu)",
			                    k, n->escape, k + 1, node_count);
		if (n->level == 0 && (size_t)n->first + n->count > triangle_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh refit: leaf %zu holds slots past %zu triangles", k,
			                    triangle_count);
	}
	for (size_t s = 0; s < triangle_count; s++) {
		if (triangle_order[s] >= triangle_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh refit: slot %zu names triangle %u of %zu", s,
			                    triangle_order[s], triangle_count);
		enum rs_status st = rs_bvh__check_triangle(positions, vertex_count, indices,
		                                           triangle_order[s], err);
		if (st != RS_OK)
			return st;
	}
	return RS_OK;
}

enum rs_status rs_bvh_refit(struct rs_bvh_node *nodes, size_t node_count, const float *positions,
                            size_t vertex_count, const uint32_t *indices,
                            const uint32_t *triangle_order, size_t triangle_count,
                            struct rs_error *err)
{
	RS_ASSERT((nodes || !node_count) && (positions || !vertex_count) &&
	          (indices || !triangle_count) && (triangle_order || !triangle_count));
	enum rs_status st = check_tree(nodes, node_count, positions, vertex_count, indices,
	                               triangle_order, triangle_count, err);
	if (st != RS_OK)
		return st;
	/* Pre-order: every child sits after its parent, so a backward sweep sees children
	 * first. The children of k are k + 1 and then each one's escape, up to k's escape. */
	for (size_t k = node_count; k-- > 0;) {
		struct rs_bvh_node *n = &nodes[k];
		rs_bvh__box_empty(n->lo, n->hi);
		if (n->level == 0) {
			for (uint32_t s = n->first; s < n->first + n->count; s++)
				rs_bvh__box_add_triangle(n->lo, n->hi, positions, indices,
				                         triangle_order[s]);
			continue;
		}
		for (uint32_t c = (uint32_t)k + 1; c < n->escape; c = nodes[c].escape)
			for (int a = 0; a < 3; a++) {
				n->lo[a] = nodes[c].lo[a] < n->lo[a] ? nodes[c].lo[a] : n->lo[a];
				n->hi[a] = nodes[c].hi[a] > n->hi[a] ? nodes[c].hi[a] : n->hi[a];
			}
	}
	return RS_OK;
}
