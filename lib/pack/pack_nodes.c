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

/* Whether child c1 is visited before c0 in node order d of `orders` (rs_pack.h). Six
 * (directional): the child whose box centre comes first along d's axis, ascending or
 * descending. Eight (octant): on the axis the two centres are farthest apart (the node's
 * split, ties to the lower axis), the one first in the direction of d's sign there (d's
 * bit for that axis set: descending). Ties keep the builder's order. */
static bool visits_second_first(const float (*box)[6], uint32_t c0, uint32_t c1, uint32_t orders,
                                uint32_t d)
{
	int axis = (int)(d / 2);
	bool down = d % 2 == 1;
	if (orders == 8) {
		float best = -1.0f;
		for (int a = 0; a < 3; a++) {
			float gap =
			    fabsf(box[c1][a] + box[c1][3 + a] - box[c0][a] - box[c0][3 + a]);
			if (gap > best) {
				best = gap;
				axis = a;
			}
		}
		down = (d >> axis & 1u) != 0;
	}
	float m0 = box[c0][axis] + box[c0][3 + axis];
	float m1 = box[c1][axis] + box[c1][3 + axis];
	return down ? m1 > m0 : m1 < m0;
}

/* Pre-order d of the tree (visits_second_first() at every interior node); pos_of[k] =
 * position of node k. The stack holds at most node_count entries. */
static void node_order(const struct rs_bvh_node *nodes, size_t node_count, const float (*box)[6],
                       uint32_t orders, uint32_t d, uint32_t *stack, uint32_t *pos_of)
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
			bool swap = visits_second_first(box, c[0], c[1], orders, d);
			stack[sp++] =
			    c[swap ? 0 : 1]; /* the second child, popped after the first */
			stack[sp++] = c[swap ? 1 : 0];
		}
	}
}

/* Wide nodes (RS_PACK_NODES_WIDE4): the binary tree, made one tree (a forest's tops are
 * paired under virtual nodes), collapsed greedily: a wide node starts with its binary
 * node's two children and opens the one of largest surface area until it has four or only
 * leaves (Wald et al. 2008's collapse; Ylitie et al. 2017's SAH collapse is the refinement
 * docs/bvh.md names). Subtrees without triangles are dropped. Nodes are numbered in
 * pre-order, so a child's index is always above its parent's. */
struct binary {
	uint32_t *left, *right; /* UINT32_MAX for a leaf */
	float (*box)[6];
	const struct rs_bvh_node *nodes;
	uint32_t count; /* real nodes; virtual ones follow */
};

static bool box_empty(const float b[6])
{
	return b[0] > b[3] || b[1] > b[4] || b[2] > b[5];
}

static double half_area(const float b[6])
{
	double d[3] = {(double)b[3] - b[0], (double)b[4] - b[1], (double)b[5] - b[2]};
	return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* The compact grid position of a bound (quantise() as integers). */
static int32_t grid_q(float v, int a, bool up, const struct rs_packed *p)
{
	return (int32_t)quantise(v, a, up, p);
}

struct wide_writer {
	const struct binary *bin;
	struct rs_packed *packed;
	uint32_t next;      /* next free wide node */
	uint32_t max_stack; /* entries the walk can need */
};

/* Write the wide node for binary interior node b at index k; returns the stack entries the
 * walk of its subtree can need (docs/bvh.md): children - 1 + max(1, the deepest child's). */
static uint32_t write_wide(struct wide_writer *w, uint32_t b, uint32_t k)
{
	const struct binary *bin = w->bin;
	uint32_t kids[RS_PACK_WIDE_CHILDREN], n = 0;
	uint32_t open[2] = {bin->left[b], bin->right[b]};
	if (open[0] == UINT32_MAX) /* a root that is a leaf: its own only child */
		kids[n++] = b;
	else
		for (int c = 0; c < 2; c++)
			if (!box_empty(bin->box[open[c]]))
				kids[n++] = open[c];
	while (n < RS_PACK_WIDE_CHILDREN) {
		int best = -1;
		double area = -1.0;
		for (uint32_t c = 0; c < n; c++)
			if (bin->left[kids[c]] != UINT32_MAX &&
			    half_area(bin->box[kids[c]]) > area) {
				area = half_area(bin->box[kids[c]]);
				best = (int)c;
			}
		if (best < 0)
			break;
		uint32_t x = kids[best], l = bin->left[x], r = bin->right[x];
		kids[best] = kids[--n];
		if (!box_empty(bin->box[l]))
			kids[n++] = l;
		if (!box_empty(bin->box[r]))
			kids[n++] = r;
	}
	/* The node's own grid: origin at its compact lo, per-axis step 2^e grid steps with
	 * the extent within 255 of them. */
	const struct rs_packed *p = w->packed;
	int32_t o[3], top[3];
	uint32_t e[3];
	for (int a = 0; a < 3; a++) {
		o[a] = INT32_MAX;
		top[a] = 0;
		for (uint32_t c = 0; c < n; c++) {
			int32_t lo = grid_q(bin->box[kids[c]][a], a, false, p);
			int32_t hi = grid_q(bin->box[kids[c]][3 + a], a, true, p);
			o[a] = lo < o[a] ? lo : o[a];
			top[a] = hi > top[a] ? hi : top[a];
		}
		if (n == 0)
			o[a] = 0;
		e[a] = 0;
		while (top[a] - o[a] > (int32_t)(255u << e[a]))
			e[a]++;
	}
	uint32_t word[12] = {0};
	for (uint32_t c = 0; c < RS_PACK_WIDE_CHILDREN; c++)
		for (int a = 0; a < 3; a++) {
			uint32_t qlo = 255, qhi = 0; /* an unused slot: an empty box */
			if (c < n) {
				int32_t lo = grid_q(bin->box[kids[c]][a], a, false, p) - o[a];
				int32_t hi = grid_q(bin->box[kids[c]][3 + a], a, true, p) - o[a];
				qlo = (uint32_t)lo >> e[a];
				qhi = ((uint32_t)hi + (1u << e[a]) - 1u) >> e[a];
			}
			word[a] |= qlo << (8 * c);
			word[3 + a] |= qhi << (8 * c);
		}
	word[6] = (uint32_t)o[0] | (uint32_t)o[1] << 16;
	word[7] = (uint32_t)o[2] | e[0] << 16 | e[1] << 20 | e[2] << 24 | n << 28;
	uint32_t deepest = 0;
	for (uint32_t c = 0; c < n; c++) {
		uint32_t x = kids[c];
		if (bin->left[x] == UINT32_MAX) {
			word[8 + c] = RS_PACK_LEAF_BIT | bin->nodes[x].first;
			continue;
		}
		uint32_t child = w->next++;
		word[8 + c] = child;
		uint32_t need = write_wide(w, x, child);
		deepest = need > deepest ? need : deepest;
	}
	memcpy(w->packed->nodes.words + (size_t)k * RS_PACK_WIDE_NODE_TEXELS * 4u, word,
	       sizeof word);
	return (n ? n - 1u : 0u) + (deepest > 1u ? deepest : 1u);
}

static enum rs_status pack_wide(const struct rs_bvh_node *nodes, size_t node_count,
                                const float (*box)[6], struct rs_packed *packed,
                                struct rs_error *err)
{
	if (node_count == 0)
		return RS_OK;
	if (!well_formed(nodes, node_count))
		return rs_error_set(
		    err, RS_ERR_BAD_DATA,
		    "pack: the BVH's escapes do not nest, so it cannot be made wide");
	size_t cap = 2 * node_count;
	struct binary bin = {malloc(cap * sizeof *bin.left), malloc(cap * sizeof *bin.right),
	                     malloc(cap * sizeof *bin.box), nodes, (uint32_t)node_count};
	uint32_t *tops = malloc(node_count * sizeof *tops);
	enum rs_status s = RS_OK;
	if (!bin.left || !bin.right || !bin.box || !tops) {
		s = rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for wide nodes");
		goto out;
	}
	uint32_t count = (uint32_t)node_count, ntops = 0;
	for (uint32_t k = 0; k < count; k++) {
		memcpy(bin.box[k], box[k], sizeof box[k]);
		bool leaf = nodes[k].level == 0;
		bin.left[k] = leaf ? UINT32_MAX : k + 1;
		bin.right[k] = leaf ? UINT32_MAX : nodes[k + 1].escape;
	}
	for (uint32_t k = 0; k < count; k = nodes[k].escape)
		tops[ntops++] = k;
	/* A forest becomes one tree: neighbours paired level by level (the escape chain's
	 * order, which is the builder's). Virtual nodes are interior nodes past count. */
	while (ntops > 1) {
		uint32_t m = 0;
		for (uint32_t t = 0; t + 1 < ntops; t += 2) {
			uint32_t v = count++;
			bin.left[v] = tops[t];
			bin.right[v] = tops[t + 1];
			for (int a = 0; a < 3; a++) {
				bin.box[v][a] = fminf(bin.box[tops[t]][a], bin.box[tops[t + 1]][a]);
				bin.box[v][3 + a] =
				    fmaxf(bin.box[tops[t]][3 + a], bin.box[tops[t + 1]][3 + a]);
			}
			tops[m++] = v;
		}
		if (ntops % 2)
			tops[m++] = tops[ntops - 1];
		ntops = m;
	}
	struct wide_writer w = {&bin, packed, 1u, 0u};
	if (!box_empty(bin.box[tops[0]]) || bin.left[tops[0]] != UINT32_MAX) {
		uint32_t need = write_wide(&w, tops[0], 0);
		if (need > RS_PACK_WIDE_STACK)
			s = rs_error_set(
			    err, RS_ERR_LIMIT,
			    "pack: this tree's wide walk can need %u stack entries, over "
			    "the kernels' %u; pack compact nodes instead",
			    need, RS_PACK_WIDE_STACK);
	}
out:
	free(bin.left);
	free(bin.right);
	free(bin.box);
	free(tops);
	return s;
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
		node_order(nodes, node_count, box, packed->node_orders, d, stack, pos_of);
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
	if (packed->node_format != RS_PACK_NODES_PAPER)
		grid((const float(*)[6])box, node_count, packed);
	enum rs_status s =
	    packed->node_format == RS_PACK_NODES_WIDE4
	        ? pack_wide(nodes, node_count, (const float(*)[6])box, packed, err)
	        : write_nodes(nodes, node_count, (const float(*)[6])box, packed, err);
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
	RS_ASSERT(p && out && k < (uint64_t)p->node_count * p->node_orders &&
	          p->node_format != RS_PACK_NODES_WIDE4);
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

void rs_pack_read_wide(const struct rs_packed *p, uint32_t k, struct rs_pack_wide *out)
{
	RS_ASSERT(p && out && k < p->node_count && p->node_format == RS_PACK_NODES_WIDE4);
	const uint32_t *w = p->nodes.words + (size_t)k * RS_PACK_WIDE_NODE_TEXELS * 4u;
	uint32_t o[3] = {w[6] & 0xffffu, w[6] >> 16, w[7] & 0xffffu};
	uint32_t n = w[7] >> 28, kept = 0;
	for (uint32_t c = 0; c < n && c < RS_PACK_WIDE_CHILDREN; c++) {
		uint32_t child = w[8 + c];
		bool leaf = (child & RS_PACK_LEAF_BIT) != 0;
		if (leaf ? (child & ~RS_PACK_LEAF_BIT) >= p->triangle_count
		         : child <= k || child >= p->node_count)
			continue; /* corrupt: the kernels drop the slot too */
		for (int a = 0; a < 3; a++) {
			uint32_t e = (w[7] >> (16 + 4 * a)) & 0xfu;
			uint32_t qlo = (w[a] >> (8 * c)) & 0xffu,
			         qhi = (w[3 + a] >> (8 * c)) & 0xffu;
			int32_t lo = (int32_t)(o[a] + (qlo << e)),
			        hi = (int32_t)(o[a] + (qhi << e));
			out->qlo[kept][a] = lo;
			out->qhi[kept][a] = hi;
			out->lo[kept][a] =
			    p->node_grid_origin[a] + (float)lo * p->node_grid_step[a];
			out->hi[kept][a] =
			    p->node_grid_origin[a] + (float)hi * p->node_grid_step[a];
		}
		out->child[kept++] = child;
	}
	out->children = kept;
}
