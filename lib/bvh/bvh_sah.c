/* Top-down binned SAH builder (Wald 2007 style): centroids are binned on all three axes,
 * the best plane is found by one sweep over the bins, and the triangle index range is
 * partitioned in place, so no sorting and O(n log n) work. Nodes are emitted in pre-order
 * from an explicit stack (no recursion, so degenerate inputs cannot overflow the C stack).
 *
 * The cost model matches how the traversal counts hit numbers: a leaf hit costs its
 * triangle count; an interior hit costs one box test per child (traversal_cost each) plus
 * the children's costs weighted by their surface-area hit probability. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_internal.h"

struct tri_box {
	float lo[3], hi[3];
	float c[3]; /* centroid times two (lo + hi) */
};

struct bin {
	float lo[3], hi[3];
	uint32_t count;
};

struct task {
	uint32_t begin, end, parent;
};

struct sah_ctx {
	const struct tri_box *boxes;
	uint32_t *idx;
	struct bin *bins; /* 3 * nbins */
	double *right_cost;
	uint32_t nbins;
	uint32_t leaf_size;
	double ct;
};

static void grow(float lo[3], float hi[3], const float plo[3], const float phi[3])
{
	for (int a = 0; a < 3; a++) {
		lo[a] = plo[a] < lo[a] ? plo[a] : lo[a];
		hi[a] = phi[a] > hi[a] ? phi[a] : hi[a];
	}
}

/* Decide how to split idx[begin, end): returns the split position (begin < mid < end),
 * or 0 to make a leaf. */
static uint32_t split_range(struct sah_ctx *s, uint32_t begin, uint32_t end, float lo[3],
			    float hi[3])
{
	uint32_t n = end - begin;
	float clo[3], chi[3];
	rs_bvh__box_empty(lo, hi);
	rs_bvh__box_empty(clo, chi);
	for (uint32_t i = begin; i < end; i++) {
		const struct tri_box *b = &s->boxes[s->idx[i]];
		grow(lo, hi, b->lo, b->hi);
		grow(clo, chi, b->c, b->c);
	}
	if (n == 1)
		return 0;
	double area = rs_bvh__box_area(lo, hi);
	double leaf_cost = (double)n * area;
	uint32_t nb = s->nbins;
	double k[3];
	for (int a = 0; a < 3; a++) {
		double extent = (double)chi[a] - (double)clo[a];
		k[a] = extent > 0.0 ? (double)nb * (1.0 - 1e-6) / extent : 0.0;
		for (uint32_t j = 0; j < nb; j++) {
			struct bin *bn = &s->bins[a * nb + j];
			rs_bvh__box_empty(bn->lo, bn->hi);
			bn->count = 0;
		}
	}
	for (uint32_t i = begin; i < end; i++) {
		const struct tri_box *b = &s->boxes[s->idx[i]];
		for (int a = 0; a < 3; a++) {
			if (k[a] == 0.0)
				continue;
			uint32_t j = (uint32_t)(((double)b->c[a] - (double)clo[a]) * k[a]);
			j = j < nb ? j : nb - 1;
			struct bin *bn = &s->bins[a * nb + j];
			grow(bn->lo, bn->hi, b->lo, b->hi);
			bn->count++;
		}
	}
	/* Unnormalised costs (times the node area) so flat or point-like nodes (area 0)
	 * still compare. */
	double best = DBL_MAX;
	int best_axis = -1;
	uint32_t best_bin = 0;
	for (int a = 0; a < 3; a++) {
		if (k[a] == 0.0)
			continue;
		struct bin *bins = &s->bins[a * nb];
		float rlo[3], rhi[3];
		rs_bvh__box_empty(rlo, rhi);
		uint32_t rn = 0;
		for (uint32_t j = nb; j-- > 1;) {
			grow(rlo, rhi, bins[j].lo, bins[j].hi);
			rn += bins[j].count;
			s->right_cost[j] = rn ? rs_bvh__box_area(rlo, rhi) * rn : -1.0;
		}
		float llo[3], lhi[3];
		rs_bvh__box_empty(llo, lhi);
		uint32_t ln = 0;
		for (uint32_t j = 1; j < nb; j++) {
			grow(llo, lhi, bins[j - 1].lo, bins[j - 1].hi);
			ln += bins[j - 1].count;
			if (ln == 0 || s->right_cost[j] < 0.0)
				continue;
			double c = 2.0 * s->ct * area + rs_bvh__box_area(llo, lhi) * ln +
				   s->right_cost[j];
			if (c < best) {
				best = c;
				best_axis = a;
				best_bin = j;
			}
		}
	}
	if (best_axis < 0) {
		/* All centroids coincide: only an arbitrary split is possible. */
		return n <= s->leaf_size ? 0 : begin + n / 2;
	}
	if (n <= s->leaf_size && leaf_cost <= best)
		return 0;
	uint32_t i = begin, j = end;
	double ka = k[best_axis];
	double ca = clo[best_axis];
	while (i < j) {
		const struct tri_box *b = &s->boxes[s->idx[i]];
		uint32_t bin = (uint32_t)(((double)b->c[best_axis] - ca) * ka);
		bin = bin < nb ? bin : nb - 1;
		if (bin < best_bin) {
			i++;
		} else {
			uint32_t t = s->idx[i];
			s->idx[i] = s->idx[--j];
			s->idx[j] = t;
		}
	}
	return i;
}

enum rs_status rs_bvh__build_sah(const struct rs_bvh_desc *desc, const float *positions,
				 const uint32_t *indices, size_t triangle_count,
				 struct rs_bvh_node *nodes, uint32_t *order, size_t *out_count,
				 struct rs_error *err)
{
	size_t n = triangle_count;
	size_t cap = 2 * n - 1;
	struct tri_box *boxes = malloc(n * sizeof *boxes);
	struct bin *bins = malloc(3 * (size_t)desc->sah_bins * sizeof *bins);
	double *right_cost = malloc((size_t)desc->sah_bins * sizeof *right_cost);
	uint32_t *parent = malloc(cap * sizeof *parent);
	struct task *stack = malloc((n + 1) * sizeof *stack);
	enum rs_status status = RS_OK;
	if (!boxes || !bins || !right_cost || !parent || !stack) {
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory (%zu triangles)",
				      n);
		goto done;
	}
	for (size_t t = 0; t < n; t++) {
		struct tri_box *b = &boxes[t];
		rs_bvh__box_empty(b->lo, b->hi);
		rs_bvh__box_add_triangle(b->lo, b->hi, positions, indices, (uint32_t)t);
		for (int a = 0; a < 3; a++)
			b->c[a] = b->lo[a] + b->hi[a];
		order[t] = (uint32_t)t;
	}
	struct sah_ctx s = {boxes, order, bins, right_cost, desc->sah_bins, desc->leaf_size,
			    desc->traversal_cost};
	size_t top = 0, count = 0;
	stack[top++] = (struct task){0, (uint32_t)n, RS_BVH_NO_PARENT};
	while (top > 0) {
		struct task t = stack[--top];
		uint32_t k = (uint32_t)count++;
		struct rs_bvh_node *node = &nodes[k];
		parent[k] = t.parent;
		float lo[3], hi[3];
		uint32_t mid = split_range(&s, t.begin, t.end, lo, hi);
		node->first = 0;
		node->count = 0;
		if (mid == 0) {
			memcpy(node->lo, lo, sizeof lo);
			memcpy(node->hi, hi, sizeof hi);
			node->first = t.begin;
			node->count = t.end - t.begin;
			continue;
		}
		rs_bvh__box_empty(node->lo, node->hi);
		/* LIFO: push the second child first so the first child follows its parent. */
		stack[top++] = (struct task){mid, t.end, k};
		stack[top++] = (struct task){t.begin, mid, k};
	}
	if (!rs_bvh__finalize(nodes, count, parent)) {
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
		goto done;
	}
	*out_count = count;
done:
	free(boxes);
	free(bins);
	free(right_cost);
	free(parent);
	free(stack);
	return status;
}
