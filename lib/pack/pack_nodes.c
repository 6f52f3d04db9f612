/* The node texture in its two formats: the paper's three float texels, and the compact
 * single RGBA32UI texel whose bounds sit on a 16-bit grid (one fetch per box, which is what
 * a box test costs most on a software rasteriser and on bandwidth-bound GPUs). Both are
 * decoded by rs_pack_read_node(), which the CPU reference walks. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pack_internal.h"

static void grow_box(float *lo, float *hi, const float *plo, const float *phi)
{
	for (int a = 0; a < 3; a++) {
		lo[a] = plo[a] < lo[a] ? plo[a] : lo[a];
		hi[a] = phi[a] > hi[a] ? phi[a] : hi[a];
	}
}

/* Tight node bounds of the packed vertices, children before parents (pre-order: children
 * follow their parent, the right child at the left child's escape). Boxes start empty
 * (lo = +FLT_MAX, hi = -FLT_MAX), which is what empty leaves keep. */
static void node_bounds(const struct rs_bvh_node *nodes, size_t node_count,
                        const struct rs_packed *packed, float (*box)[6])
{
	for (size_t k = node_count; k-- > 0;) {
		float *lo = box[k], *hi = box[k] + 3;
		lo[0] = lo[1] = lo[2] = FLT_MAX;
		hi[0] = hi[1] = hi[2] = -FLT_MAX;
		const struct rs_bvh_node *n = &nodes[k];
		if (n->level == 0) {
			for (uint32_t s = n->first; s < n->first + n->count; s++)
				for (uint32_t j = 0; j < 3; j++) {
					const float *v = rs_pack_texel(
					    &packed->triangles, RS_PACK_TRIANGLE_TEXELS, s, j);
					grow_box(lo, hi, v, v);
				}
			continue;
		}
		/* a corrupt tree may not read outside its own subtree */
		uint32_t end = n->escape < node_count ? n->escape : (uint32_t)node_count;
		uint32_t child[2] = {(uint32_t)k + 1, k + 1 < end ? nodes[k + 1].escape : end};
		for (int c = 0; c < 2; c++)
			if (child[c] > k && child[c] < end)
				grow_box(lo, hi, box[child[c]], box[child[c]] + 3);
	}
}

/* Node n with bounds box at `item`, escaping to item `escape` (absolute). */
static void write_paper(struct rs_packed *packed, uint32_t item, const struct rs_bvh_node *n,
                        const float box[6], uint32_t escape)
{
	float *t = packed->nodes.texels + (size_t)item * RS_PACK_NODE_TEXELS * 4u;
	float v[12] = {box[0],          box[1],          box[2],          (float)escape,
	               box[3],          box[4],          box[5],          (float)n->level,
	               (float)n->first, (float)n->count, (float)n->order, 0.0f};
	memcpy(t, v, sizeof v);
}

/* Per axis: a power-of-two step s with the bounds' extent under (RS_PACK_GRID_STEPS - 3) s,
 * at least 2^-22 of the largest magnitude (so the origin is a multiple of s below 2^23 s)
 * and at least 2^-100 (no fp32 denormals); origin = floor(lo / s) * s. Then origin + q * s
 * is an exact fp32 value for every q of 16 bits, whatever the rounding mode or fma. */
static void grid(const float (*box)[6], size_t node_count, struct rs_packed *packed)
{
	float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
	for (size_t k = 0; k < node_count; k++)
		grow_box(lo, hi, box[k], box[k] + 3);
	for (int a = 0; a < 3; a++) {
		if (lo[a] > hi[a])
			lo[a] = hi[a] = 0.0f;
		double need = ((double)hi[a] - lo[a]) / (RS_PACK_GRID_STEPS - 3u);
		double mag = fmax(fabs((double)lo[a]), fabs((double)hi[a])) * 0x1p-22;
		need = fmax(fmax(need, mag), 0x1p-100);
		int e;
		frexp(need, &e); /* need < 2^e */
		double step = ldexp(1.0, e);
		packed->node_grid_step[a] = (float)step;
		packed->node_grid_origin[a] = (float)(floor(lo[a] / step) * step);
	}
}

/* Grid index of a bound, rounded outwards (`up` for hi); an empty box's bounds give qlo =
 * max, qhi = 0, which stays empty. Exact in double: the step is a power of two. */
static uint32_t quantise(float v, int a, bool up, const struct rs_packed *p)
{
	double q = ((double)v - p->node_grid_origin[a]) / p->node_grid_step[a];
	q = up ? ceil(q) : floor(q);
	return q < 0.0 ? 0u : q > RS_PACK_GRID_STEPS ? RS_PACK_GRID_STEPS : (uint32_t)q;
}

static void write_compact(struct rs_packed *packed, uint32_t item, const struct rs_bvh_node *n,
                          const float box[6], uint32_t escape)
{
	uint32_t q[6];
	for (int a = 0; a < 3; a++) {
		q[a] = quantise(box[a], a, false, packed);
		q[3 + a] = quantise(box[3 + a], a, true, packed);
	}
	uint32_t *w = packed->nodes.words + (size_t)item * 4u;
	w[0] = q[0] | q[1] << 16;
	w[1] = q[2] | q[3] << 16;
	w[2] = q[4] | q[5] << 16;
	w[3] = n->level == 0 && n->count > 0 ? RS_PACK_LEAF_BIT | n->first : escape;
}

/* A tree every order can be made from: subtrees nest ([k, escape) holds k + 1's subtree
 * and the right child's, which ends where k's does), leaves escape to the next node and
 * the top-level subtrees chain to node_count. */
static bool well_formed(const struct rs_bvh_node *nodes, size_t node_count)
{
	for (size_t k = 0; k < node_count; k++) {
		uint32_t e = nodes[k].escape;
		if (e <= k || e > node_count)
			return false;
		if (nodes[k].level == 0) {
			if (e != k + 1)
				return false;
			continue;
		}
		uint32_t r = k + 1 < node_count ? nodes[k + 1].escape : 0;
		if (k + 1 >= e || r <= k + 1 || r >= e || nodes[r].escape != e)
			return false;
	}
	size_t k = 0;
	while (k < node_count)
		k = nodes[k].escape;
	return k == node_count;
}

/* Pre-order of the tree with, at every interior node, the child whose box centre comes first
 * along axis (ascending, or descending when `down`) visited first; ties keep the builder's
 * order. pos_of[k] = position of node k. The stack holds at most node_count entries. */
static void directional_order(const struct rs_bvh_node *nodes, size_t node_count,
                              const float (*box)[6], int axis, bool down, uint32_t *stack,
                              uint32_t *pos_of)
{
	uint32_t pos = 0;
	for (uint32_t top = 0; top < node_count; top = nodes[top].escape) {
		size_t sp = 0;
		stack[sp++] = top;
		while (sp) {
			uint32_t k = stack[--sp];
			pos_of[k] = pos++;
			if (nodes[k].level == 0)
				continue;
			uint32_t c[2] = {k + 1, nodes[k + 1].escape};
			float m0 = box[c[0]][axis] + box[c[0]][3 + axis];
			float m1 = box[c[1]][axis] + box[c[1]][3 + axis];
			bool swap = down ? m1 > m0 : m1 < m0;
			stack[sp++] =
			    c[swap ? 0 : 1]; /* the second child, popped after the first */
			stack[sp++] = c[swap ? 1 : 0];
		}
	}
}

static enum rs_status write_nodes(const struct rs_bvh_node *nodes, size_t node_count,
                                  const float (*box)[6], struct rs_packed *packed,
                                  struct rs_error *err)
{
	void (*write)(struct rs_packed *, uint32_t, const struct rs_bvh_node *, const float[6],
	              uint32_t) =
	    packed->node_format == RS_PACK_NODES_PAPER ? write_paper : write_compact;
	uint32_t n = (uint32_t)node_count;
	if (packed->node_orders == 1) { /* the builder's own order */
		for (uint32_t k = 0; k < n; k++)
			write(packed, k, &nodes[k], box[k], nodes[k].escape);
		return RS_OK;
	}
	if (!well_formed(nodes, node_count))
		return rs_error_set(
		    err, RS_ERR_BAD_DATA,
		    "pack: the BVH's escapes do not nest, so it cannot be reordered");
	uint32_t *scratch = malloc(2 * (node_count ? node_count : 1) * sizeof *scratch);
	if (!scratch)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for node orders");
	uint32_t *stack = scratch, *pos_of = scratch + node_count;
	for (uint32_t d = 0; d < packed->node_orders; d++) {
		directional_order(nodes, node_count, box, (int)(d / 2), d % 2 == 1, stack, pos_of);
		uint32_t base = d * n;
		for (uint32_t k = 0; k < n; k++)
			write(packed, base + pos_of[k], &nodes[k], box[k],
			      base + pos_of[k] + (nodes[k].escape - k));
	}
	free(scratch);
	return RS_OK;
}

enum rs_status rs__pack_nodes(const struct rs_bvh_node *nodes, size_t node_count,
                              struct rs_packed *packed, struct rs_error *err)
{
	float(*box)[6] = malloc((node_count ? node_count : 1) * sizeof *box);
	if (!box)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for %zu node boxes",
		                    node_count);
	node_bounds(nodes, node_count, packed, box);
	if (packed->node_format == RS_PACK_NODES_COMPACT)
		grid((const float(*)[6])box, node_count, packed);
	enum rs_status s = write_nodes(nodes, node_count, (const float(*)[6])box, packed, err);
	free(box);
	if (s != RS_OK)
		return s;
	/* The last flag of every leaf's last slot: what ends a compact leaf. */
	for (size_t i = 0; i < node_count; i++)
		if (nodes[i].level == 0 && nodes[i].count > 0) {
			uint32_t last = nodes[i].first + nodes[i].count - 1;
			((float *)rs_pack_texel(&packed->triangles, RS_PACK_TRIANGLE_TEXELS, last,
			                        2))[3] = 1.0f;
		}
	return RS_OK;
}

static uint32_t escape_after(uint32_t escape, uint32_t k)
{
	return escape > k ? escape : k + 1u; /* never backwards: a corrupt tree ends */
}

void rs_pack_read_node(const struct rs_packed *p, uint32_t k, struct rs_pack_node *out)
{
	RS_ASSERT(p && out && k < (uint64_t)p->node_count * p->node_orders);
	uint32_t tris = p->triangle_count;
	if (p->node_format == RS_PACK_NODES_PAPER) {
		const float *t = rs_pack_texel(&p->nodes, RS_PACK_NODE_TEXELS, k, 0);
		memcpy(out->lo, t, sizeof out->lo);
		memcpy(out->hi, t + 4, sizeof out->hi);
		out->escape = escape_after(rs_pack_index(t[3]), k);
		out->leaf = t[7] == 0.0f;
		uint32_t first = rs_pack_index(t[8]), count = rs_pack_index(t[9]);
		out->first = first < tris ? first : tris;
		out->count = count < tris - out->first ? count : tris - out->first;
		return;
	}
	const uint32_t *w = p->nodes.words + (size_t)k * 4u;
	uint32_t q[6] = {w[0] & 0xffffu, w[0] >> 16,     w[1] & 0xffffu,
	                 w[1] >> 16,     w[2] & 0xffffu, w[2] >> 16};
	for (int a = 0; a < 3; a++) {
		out->lo[a] = p->node_grid_origin[a] + (float)q[a] * p->node_grid_step[a];
		out->hi[a] = p->node_grid_origin[a] + (float)q[3 + a] * p->node_grid_step[a];
	}
	out->leaf = (w[3] & RS_PACK_LEAF_BIT) != 0;
	out->escape = out->leaf ? k + 1u : escape_after(w[3], k);
	out->first = out->count = 0;
	if (!out->leaf)
		return;
	uint32_t first = w[3] & ~RS_PACK_LEAF_BIT, s = first < tris ? first : tris;
	while (s < tris) {
		const float *t2 = rs_pack_texel(&p->triangles, RS_PACK_TRIANGLE_TEXELS, s++, 2);
		if (t2[3] != 0.0f)
			break;
	}
	out->first = first < tris ? first : tris;
	out->count = s - out->first;
}
