/* rs_bvh: descriptor defaults, input validation, builder dispatch, the shared
 * finalisation pass of the threaded layout, and summary statistics. */
#include "raystream/rs_bvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_internal.h"

#define DEFAULT_SAH_LEAF 4u
#define DEFAULT_LINEAR_LEAF 8u
#define DEFAULT_BINS 16u
#define MAX_LEAF 1024u

void rs_bvh_desc_resolve(const struct rs_bvh_desc *desc, struct rs_bvh_desc *out)
{
	struct rs_bvh_desc d = {0};
	if (desc)
		d = *desc;
	if (d.leaf_size == 0)
		d.leaf_size = d.builder == RS_BVH_LINEAR ? DEFAULT_LINEAR_LEAF : DEFAULT_SAH_LEAF;
	if (d.builder == RS_BVH_PAPER)
		d.leaf_size = 1;
	if (d.sah_bins == 0)
		d.sah_bins = DEFAULT_BINS;
	if (d.traversal_cost == 0.0f)
		d.traversal_cost = 1.0f;
	if (d.threads == 0)
		d.threads = 1;
	*out = d;
}

static const char *const builder_names[] = {"sah", "none", "linear", "paper"};

const char *rs_bvh_builder_name(enum rs_bvh_builder builder)
{
	if ((unsigned)builder < sizeof builder_names / sizeof builder_names[0])
		return builder_names[builder];
	return "unknown";
}

enum rs_status rs_bvh_builder_parse(const char *name, enum rs_bvh_builder *out,
                                    struct rs_error *err)
{
	RS_ASSERT(name && out);
	for (unsigned i = 0; i < sizeof builder_names / sizeof builder_names[0]; i++) {
		if (strcmp(name, builder_names[i]) == 0) {
			*out = (enum rs_bvh_builder)i;
			return RS_OK;
		}
	}
	return rs_error_set(err, RS_ERR_INVALID, "unknown BVH builder '%.64s'", name);
}

static size_t pow2_ceil(size_t n)
{
	size_t p = 1;
	while (p < n)
		p <<= 1;
	return p;
}

size_t rs_bvh_node_bound(const struct rs_bvh_desc *desc, size_t triangle_count)
{
	struct rs_bvh_desc d;
	rs_bvh_desc_resolve(desc, &d);
	if (triangle_count == 0)
		return 0;
	switch (d.builder) {
	case RS_BVH_NONE:
		return 1;
	case RS_BVH_LINEAR:
		return (triangle_count + d.leaf_size - 1) / d.leaf_size;
	case RS_BVH_PAPER:
		return 2 * pow2_ceil(triangle_count) - 1;
	case RS_BVH_SAH:
		return 2 * triangle_count - 1;
	}
	return 0;
}

static enum rs_status validate(const struct rs_bvh_desc *d, const float *positions,
                               size_t vertex_count, const uint32_t *indices, size_t triangle_count,
                               struct rs_error *err)
{
	if ((unsigned)d->builder > RS_BVH_PAPER)
		return rs_error_set(err, RS_ERR_INVALID, "bvh: unknown builder %d",
		                    (int)d->builder);
	if (d->leaf_size > MAX_LEAF && d->builder == RS_BVH_SAH)
		return rs_error_set(err, RS_ERR_INVALID, "bvh: leaf_size %u above %u", d->leaf_size,
		                    MAX_LEAF);
	if (d->sah_bins < 2 || d->sah_bins > RS_BVH_MAX_BINS)
		return rs_error_set(err, RS_ERR_INVALID, "bvh: sah_bins %u outside 2..%u",
		                    d->sah_bins, RS_BVH_MAX_BINS);
	if (d->threads > RS_BVH_MAX_THREADS)
		return rs_error_set(err, RS_ERR_INVALID, "bvh: threads %u above %u", d->threads,
		                    RS_BVH_MAX_THREADS);
	if (!(d->traversal_cost > 0.0f) || !isfinite(d->traversal_cost))
		return rs_error_set(err, RS_ERR_INVALID, "bvh: traversal_cost must be positive");
	if (triangle_count == 0)
		return RS_OK;
	if (triangle_count >= (size_t)1 << 31)
		return rs_error_set(err, RS_ERR_LIMIT, "bvh: %zu triangles exceed 2^31",
		                    triangle_count);
	/* The SAH builder checks each triangle as it reads it (in one pass, on its threads). */
	if (d->builder == RS_BVH_SAH)
		return RS_OK;
	for (size_t t = 0; t < triangle_count; t++) {
		enum rs_status s = rs_bvh__check_triangle(positions, vertex_count, indices, t, err);
		if (s != RS_OK)
			return s;
	}
	return RS_OK;
}

enum rs_status rs_bvh__check_triangle(const float *positions, size_t vertex_count,
                                      const uint32_t *indices, size_t tri, struct rs_error *err)
{
	for (int k = 0; k < 3; k++) {
		uint32_t v = indices[3 * tri + (size_t)k];
		if (v >= vertex_count)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "bvh: triangle %zu uses vertex %u of %zu", tri, v,
			                    vertex_count);
		const float *p = positions + 3 * (size_t)v;
		if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
			return rs_error_set(err, RS_ERR_BAD_DATA, "bvh: vertex %u is not finite",
			                    v);
	}
	return RS_OK;
}

enum rs_status rs_bvh_build(const struct rs_bvh_desc *desc, const float *positions,
                            size_t vertex_count, const uint32_t *indices, size_t triangle_count,
                            struct rs_bvh_node *out_nodes, size_t node_capacity,
                            uint32_t *out_triangle_order, size_t *out_node_count,
                            struct rs_error *err)
{
	RS_ASSERT(out_node_count);
	RS_ASSERT(triangle_count == 0 || (positions && indices && out_nodes && out_triangle_order));
	struct rs_bvh_desc d;
	rs_bvh_desc_resolve(desc, &d);
	*out_node_count = 0;
	enum rs_status s = validate(&d, positions, vertex_count, indices, triangle_count, err);
	if (s != RS_OK)
		return s;
	size_t bound = rs_bvh_node_bound(&d, triangle_count);
	if (node_capacity < bound)
		return rs_error_set(err, RS_ERR_INVALID, "bvh: node capacity %zu below bound %zu",
		                    node_capacity, bound);
	if (triangle_count == 0)
		return RS_OK;
	switch (d.builder) {
	case RS_BVH_NONE:
		return rs_bvh__build_flat((uint32_t)triangle_count, positions, indices,
		                          triangle_count, out_nodes, out_triangle_order,
		                          out_node_count, err);
	case RS_BVH_LINEAR:
		return rs_bvh__build_flat(d.leaf_size, positions, indices, triangle_count,
		                          out_nodes, out_triangle_order, out_node_count, err);
	case RS_BVH_PAPER:
		return rs_bvh__build_paper(positions, indices, triangle_count, out_nodes,
		                           out_triangle_order, out_node_count, err);
	case RS_BVH_SAH:
		return rs_bvh__build_sah(&d, positions, vertex_count, indices, triangle_count,
		                         out_nodes, out_triangle_order, out_node_count, err);
	}
	return rs_error_set(err, RS_ERR_INVALID, "bvh: unknown builder");
}

void rs_bvh__box_empty(float lo[3], float hi[3])
{
	for (int a = 0; a < 3; a++) {
		lo[a] = FLT_MAX;
		hi[a] = -FLT_MAX;
	}
}

void rs_bvh__box_add_triangle(float lo[3], float hi[3], const float *positions,
                              const uint32_t *indices, uint32_t tri)
{
	for (int k = 0; k < 3; k++) {
		const float *p = positions + 3 * (size_t)indices[3 * (size_t)tri + k];
		for (int a = 0; a < 3; a++) {
			lo[a] = p[a] < lo[a] ? p[a] : lo[a];
			hi[a] = p[a] > hi[a] ? p[a] : hi[a];
		}
	}
}

double rs_bvh__box_area(const float lo[3], const float hi[3])
{
	double e[3];
	for (int a = 0; a < 3; a++) {
		if (hi[a] < lo[a])
			return 0.0;
		e[a] = (double)hi[a] - (double)lo[a];
	}
	return 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
}

uint32_t rs_bvh__finalize_up(struct rs_bvh_node *nodes, size_t node_count, const uint32_t *parent)
{
	/* escape doubles as the subtree size while sizes flow up in reverse pre-order (each
	 * parent precedes its children, so one backward sweep is a bottom-up pass). */
	for (size_t i = 0; i < node_count; i++) {
		nodes[i].escape = 1;
		nodes[i].level = 0;
	}
	uint32_t max_level = 0;
	for (size_t i = node_count; i-- > 0;) {
		struct rs_bvh_node *n = &nodes[i];
		if (n->level > max_level)
			max_level = n->level;
		if (parent[i] == RS_BVH_NO_PARENT)
			continue;
		struct rs_bvh_node *p = &nodes[parent[i]];
		p->escape += n->escape;
		if (p->level < n->level + 1)
			p->level = n->level + 1;
		for (int a = 0; a < 3; a++) {
			p->lo[a] = n->lo[a] < p->lo[a] ? n->lo[a] : p->lo[a];
			p->hi[a] = n->hi[a] > p->hi[a] ? n->hi[a] : p->hi[a];
		}
	}
	return max_level;
}

void rs_bvh__finalize_rank(struct rs_bvh_node *nodes, size_t node_count, uint32_t *rank)
{
	for (size_t i = 0; i < node_count; i++) {
		nodes[i].escape += (uint32_t)i;
		nodes[i].order = rank[nodes[i].level]++;
	}
}

int rs_bvh__finalize(struct rs_bvh_node *nodes, size_t node_count, const uint32_t *parent)
{
	uint32_t max_level = rs_bvh__finalize_up(nodes, node_count, parent);
	uint32_t *rank = calloc((size_t)max_level + 1, sizeof *rank);
	if (!rank)
		return 0;
	rs_bvh__finalize_rank(nodes, node_count, rank);
	free(rank);
	return 1;
}

void rs_bvh_stats(const struct rs_bvh_node *nodes, size_t node_count, float traversal_cost,
                  struct rs_bvh_stats *out)
{
	memset(out, 0, sizeof *out);
	if (!nodes || node_count == 0)
		return;
	double ct = traversal_cost > 0.0f ? traversal_cost : 1.0;
	/* Root area: the union of the top-level boxes (a flat list has several). */
	float lo[3], hi[3];
	rs_bvh__box_empty(lo, hi);
	size_t top_count = 0;
	for (size_t i = 0; i<node_count; i = nodes[i].escape> i ? nodes[i].escape : i + 1) {
		top_count++;
		for (int a = 0; a < 3; a++) {
			lo[a] = nodes[i].lo[a] < lo[a] ? nodes[i].lo[a] : lo[a];
			hi[a] = nodes[i].hi[a] > hi[a] ? nodes[i].hi[a] : hi[a];
		}
		if (nodes[i].level + 1 > out->depth)
			out->depth = nodes[i].level + 1;
	}
	double root_area = rs_bvh__box_area(lo, hi);
	/* Expected tests per ray that meets the root box, counted as the traversal counts
	 * them: every top-level box, each child box of a hit interior node, each triangle of
	 * a hit leaf. */
	double cost = ct * (double)top_count;
	size_t tris = 0;
	for (size_t i = 0; i < node_count; i++) {
		const struct rs_bvh_node *n = &nodes[i];
		double p = root_area > 0.0 ? rs_bvh__box_area(n->lo, n->hi) / root_area : 1.0;
		out->nodes++;
		if (n->level == 0) {
			out->leaves++;
			out->empty_leaves += n->count == 0;
			tris += n->count;
			cost += p * n->count;
		} else {
			size_t children = 0;
			for (size_t c = i + 1; c < n->escape && c<node_count; c = nodes[c].escape> c
			                           ? nodes[c].escape
			                           : c + 1)
				children++;
			cost += p * ct * (double)children;
		}
	}
	out->sah_cost = cost;
	size_t full = out->leaves - out->empty_leaves;
	out->mean_leaf_size = full ? (double)tris / (double)full : 0.0;
}
