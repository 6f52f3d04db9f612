/* rs_bvh_check: verifies every invariant of the threaded layout from the node array alone,
 * so tests and the tools can validate any builder (and any packed file read back). */
#include <stdlib.h>

#include "raystream/rs_bvh.h"

static int box_empty(const struct rs_bvh_node *n)
{
	return n->lo[0] > n->hi[0] || n->lo[1] > n->hi[1] || n->lo[2] > n->hi[2];
}

static int box_contains(const struct rs_bvh_node *outer, const float lo[3], const float hi[3])
{
	for (int a = 0; a < 3; a++)
		if (lo[a] < outer->lo[a] || hi[a] > outer->hi[a])
			return 0;
	return 1;
}

/* Structure: walks the children chain of every interior node; sizes, levels and nesting
 * must agree with the escapes. */
static enum rs_status check_structure(const struct rs_bvh_node *nodes, size_t node_count,
                                      struct rs_error *err)
{
	size_t top = 0;
	while (top < node_count) {
		uint32_t e = nodes[top].escape;
		if (e <= top || e > node_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: top-level node %zu escape %u out of range", top,
			                    e);
		top = e;
	}
	for (size_t i = 0; i < node_count; i++) {
		const struct rs_bvh_node *n = &nodes[i];
		if (n->escape <= i || n->escape > node_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: node %zu escape %u out of range", i, n->escape);
		if (n->level == 0) {
			if (n->escape != i + 1)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "bvh: leaf %zu escape %u, expected %zu", i,
				                    n->escape, i + 1);
			if (n->count == 0 && !box_empty(n))
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "bvh: empty leaf %zu has non-empty bounds", i);
			continue;
		}
		if (n->count != 0)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: interior node %zu has %u triangles", i, n->count);
		if (n->escape == i + 1)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: interior node %zu has no children", i);
		uint32_t max_child = 0;
		size_t c = i + 1;
		while (c < n->escape) {
			const struct rs_bvh_node *ch = &nodes[c];
			if (ch->escape > n->escape)
				return rs_error_set(
				    err, RS_ERR_BAD_DATA,
				    "bvh: child %zu of node %zu escapes past its parent", c, i);
			if (!box_empty(ch) && !box_contains(n, ch->lo, ch->hi))
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "bvh: node %zu box does not contain child %zu",
				                    i, c);
			if (ch->level >= n->level)
				return rs_error_set(
				    err, RS_ERR_BAD_DATA,
				    "bvh: child %zu level %u not below parent %zu level %u", c,
				    ch->level, i, n->level);
			max_child = ch->level > max_child ? ch->level : max_child;
			c = ch->escape;
		}
		if (max_child + 1 != n->level)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: node %zu level %u, expected %u", i, n->level,
			                    max_child + 1);
	}
	return RS_OK;
}

static enum rs_status check_order(const struct rs_bvh_node *nodes, size_t node_count,
                                  struct rs_error *err)
{
	uint32_t max_level = 0;
	for (size_t i = 0; i < node_count; i++)
		max_level = nodes[i].level > max_level ? nodes[i].level : max_level;
	uint32_t *rank = calloc((size_t)max_level + 1, sizeof *rank);
	if (!rank)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
	enum rs_status s = RS_OK;
	for (size_t i = 0; i < node_count && s == RS_OK; i++) {
		uint32_t want = rank[nodes[i].level]++;
		if (nodes[i].order != want)
			s = rs_error_set(err, RS_ERR_BAD_DATA,
			                 "bvh: node %zu order %u, expected %u", i, nodes[i].order,
			                 want);
	}
	free(rank);
	return s;
}

static enum rs_status check_triangles(const struct rs_bvh_node *nodes, size_t node_count,
                                      const float *positions, const uint32_t *indices,
                                      const uint32_t *triangle_order, size_t triangle_count,
                                      struct rs_error *err)
{
	unsigned char *seen = calloc(triangle_count ? triangle_count : 1, 1);
	unsigned char *covered = calloc(triangle_count ? triangle_count : 1, 1);
	enum rs_status s = RS_OK;
	if (!seen || !covered) {
		s = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
		goto done;
	}
	for (size_t t = 0; t < triangle_count; t++) {
		uint32_t id = triangle_order[t];
		if (id >= triangle_count || seen[id]) {
			s = rs_error_set(err, RS_ERR_BAD_DATA,
			                 "bvh: triangle order is not a permutation at slot %zu", t);
			goto done;
		}
		seen[id] = 1;
	}
	for (size_t i = 0; i < node_count; i++) {
		const struct rs_bvh_node *n = &nodes[i];
		if (n->level != 0)
			continue;
		if ((size_t)n->first + n->count > triangle_count) {
			s = rs_error_set(err, RS_ERR_BAD_DATA,
			                 "bvh: leaf %zu range past the triangles", i);
			goto done;
		}
		for (uint32_t t = n->first; t < n->first + n->count; t++) {
			if (covered[t]) {
				s = rs_error_set(err, RS_ERR_BAD_DATA, "bvh: slot %u in two leaves",
				                 t);
				goto done;
			}
			covered[t] = 1;
			const uint32_t *tri = indices + 3 * (size_t)triangle_order[t];
			for (int k = 0; k < 3; k++) {
				const float *p = positions + 3 * (size_t)tri[k];
				if (!box_contains(n, p, p)) {
					s = rs_error_set(
					    err, RS_ERR_BAD_DATA,
					    "bvh: leaf %zu box does not contain slot %u", i, t);
					goto done;
				}
			}
		}
	}
	for (size_t t = 0; t < triangle_count; t++) {
		if (!covered[t]) {
			s = rs_error_set(err, RS_ERR_BAD_DATA, "bvh: slot %zu in no leaf", t);
			goto done;
		}
	}
done:
	free(seen);
	free(covered);
	return s;
}

enum rs_status rs_bvh_check(const struct rs_bvh_node *nodes, size_t node_count,
                            const float *positions, const uint32_t *indices,
                            const uint32_t *triangle_order, size_t triangle_count,
                            struct rs_error *err)
{
	if ((node_count == 0) != (triangle_count == 0))
		return rs_error_set(err, RS_ERR_BAD_DATA, "bvh: %zu nodes for %zu triangles",
		                    node_count, triangle_count);
	RS_ASSERT(triangle_count == 0 || (nodes && positions && indices && triangle_order));
	enum rs_status s = check_structure(nodes, node_count, err);
	if (s == RS_OK)
		s = check_order(nodes, node_count, err);
	if (s == RS_OK)
		s = check_triangles(nodes, node_count, positions, indices, triangle_order,
		                    triangle_count, err);
	return s;
}
