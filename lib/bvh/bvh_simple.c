/* The paper's builders: a flat list of boxes over consecutive input triangles (`none` is
 * one box of all of them, `linear` boxes of leaf_size) and the complete binary tree over
 * input order, padded to a power of two, in pre-order (`paper`). */
#include <stdlib.h>

#include "bvh_internal.h"

enum rs_status rs_bvh__build_flat(uint32_t leaf_size, const float *positions,
                                  const uint32_t *indices, size_t triangle_count,
                                  struct rs_bvh_node *nodes, uint32_t *order, size_t *out_count,
                                  struct rs_error *err)
{
	/* A forest of leaves: every leaf is top-level, so its escape is simply the next
	 * node and a ray tests every box of the list. */
	size_t n = 0;
	for (size_t first = 0; first < triangle_count; first += leaf_size, n++) {
		struct rs_bvh_node *node = &nodes[n];
		size_t count =
		    triangle_count - first < leaf_size ? triangle_count - first : leaf_size;
		rs_bvh__box_empty(node->lo, node->hi);
		for (size_t t = first; t < first + count; t++)
			rs_bvh__box_add_triangle(node->lo, node->hi, positions, indices,
			                         (uint32_t)t);
		node->first = (uint32_t)first;
		node->count = (uint32_t)count;
		node->level = 0;
		node->order = (uint32_t)n;
		node->escape = (uint32_t)n + 1;
	}
	for (size_t t = 0; t < triangle_count; t++)
		order[t] = (uint32_t)t;
	*out_count = n;
	(void)err;
	return RS_OK;
}

/* Pre-order emission of the complete tree over padded leaf range [a, a + size). The
 * bounds, escape, level and order are then filled bottom-up by rs_bvh__finalize(), which
 * is exactly the paper's bottom-up construction re-laid out in pre-order. */
struct paper_task {
	size_t a, size;
	uint32_t parent;
};

enum rs_status rs_bvh__build_paper(const float *positions, const uint32_t *indices,
                                   size_t triangle_count, struct rs_bvh_node *nodes,
                                   uint32_t *order, size_t *out_count, struct rs_error *err)
{
	size_t leaves = 1;
	while (leaves < triangle_count)
		leaves <<= 1;
	size_t node_count = 2 * leaves - 1;
	uint32_t *parent = malloc(node_count * sizeof *parent);
	struct paper_task stack[64];
	if (!parent)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory (%zu nodes)",
		                    node_count);
	size_t top = 0, n = 0;
	stack[top++] = (struct paper_task){0, leaves, RS_BVH_NO_PARENT};
	while (top > 0) {
		struct paper_task task = stack[--top];
		uint32_t k = (uint32_t)n++;
		struct rs_bvh_node *node = &nodes[k];
		parent[k] = task.parent;
		rs_bvh__box_empty(node->lo, node->hi);
		node->first = 0;
		node->count = 0;
		if (task.size == 1) {
			if (task.a < triangle_count) {
				node->first = (uint32_t)task.a;
				node->count = 1;
				rs_bvh__box_add_triangle(node->lo, node->hi, positions, indices,
				                         (uint32_t)task.a);
			}
			continue;
		}
		size_t half = task.size / 2;
		stack[top++] = (struct paper_task){task.a + half, half, k};
		stack[top++] = (struct paper_task){task.a, half, k};
	}
	for (size_t t = 0; t < triangle_count; t++)
		order[t] = (uint32_t)t;
	int ok = rs_bvh__finalize(nodes, node_count, parent);
	free(parent);
	if (!ok)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
	*out_count = node_count;
	return RS_OK;
}
