/* Top-down binned SAH builder (Wald 2007 style): centroids are binned on all three axes,
 * the best plane is found by one sweep over the bins, and the triangle records are
 * partitioned in place, so no sorting and O(n log n) work. Records (box, centroid, id) are
 * moved rather than indexed so every pass reads memory in order; a node's bounds come
 * from its parent's bins, its centroid bounds from the parent's partition pass, so each
 * node costs one binning pass and one partition pass. Nodes are emitted in pre-order from
 * an explicit stack (no recursion: degenerate inputs cannot overflow the C stack).
 *
 * The cost model matches how the traversal counts hit numbers: a leaf hit costs its
 * triangle count; an interior hit costs one box test per child (traversal_cost each) plus
 * the children's costs weighted by their surface-area hit probability. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_internal.h"

struct item {
	float lo[3], hi[3];
	float c[3]; /* centroid */
	uint32_t id;
};

struct bin {
	float lo[3], hi[3];
	uint32_t count;
};

struct task {
	uint32_t begin, end, parent;
	float lo[3], hi[3];   /* bounds of the items */
	float clo[3], chi[3]; /* bounds of their centroids */
};

struct sah_ctx {
	struct item *items;
	struct bin *bins;  /* 3 * nbins */
	struct bin *right; /* nbins: suffix unions of the best axis candidates */
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

/* Surface area (inlined copy of rs_bvh__box_area for the sweep; boxes here are never
 * empty). */
static inline double box_area(const float lo[3], const float hi[3])
{
	double x = (double)hi[0] - lo[0], y = (double)hi[1] - lo[1], z = (double)hi[2] - lo[2];
	return 2.0 * (x * y + y * z + z * x);
}

static uint32_t bin_of(float c, float clo, float k, uint32_t nb)
{
	/* NaN (inf * 0 for coordinates near FLT_MAX) and out-of-range go to an end bin,
	 * never through an undefined float-to-integer conversion. */
	float f = (c - clo) * k;
	return f >= 0.0f && f < (float)nb ? (uint32_t)f : f >= (float)nb ? nb - 1 : 0;
}

/* A "large" triangle spans at least half the node on some axis. */
static int is_large(const struct item *it, const float inv_ext[3])
{
	for (int a = 0; a < 3; a++)
		if ((it->hi[a] - it->lo[a]) * inv_ext[a] >= 0.5f)
			return 1;
	return 0;
}

static void inverse_extent(const struct task *t, float inv_ext[3])
{
	for (int a = 0; a < 3; a++) {
		float e = t->hi[a] - t->lo[a];
		inv_ext[a] = e > 0.0f ? 1.0f / e : 0.0f;
	}
}

/* What find_split() chose for a node. */
enum split_kind {
	SPLIT_LEAF,   /* no split: a leaf is cheaper (or required) */
	SPLIT_PLANE,  /* centroid plane: items in bins below `bin` on `axis` go left */
	SPLIT_MEDIAN, /* all centroids coincide: halves of the list, bounds from the items */
	SPLIT_SIZE,   /* the large triangles (left) against the rest (right) */
};

struct split {
	enum split_kind kind;
	int axis;     /* SPLIT_PLANE only */
	uint32_t bin; /* SPLIT_PLANE only */
	float llo[3], lhi[3], rlo[3], rhi[3];
	double cost; /* unnormalised (times the node area), DBL_MAX when none priced yet */
};

static void take(struct split *out, enum split_kind kind, int axis, uint32_t bin, double cost,
                 const float llo[3], const float lhi[3], const float rlo[3], const float rhi[3])
{
	out->kind = kind;
	out->axis = axis;
	out->bin = bin;
	out->cost = cost;
	memcpy(out->llo, llo, sizeof out->llo);
	memcpy(out->lhi, lhi, sizeof out->lhi);
	memcpy(out->rlo, rlo, sizeof out->rlo);
	memcpy(out->rhi, rhi, sizeof out->rhi);
}

/* Bin scale per axis (0 for an axis whose centroids coincide); empties the bins. Returns
 * how many axes can be split. */
static int prepare_bins(struct sah_ctx *s, const struct task *t, float k[3])
{
	uint32_t nb = s->nbins;
	int axes = 0;
	for (int a = 0; a < 3; a++) {
		float extent = t->chi[a] - t->clo[a];
		double kk = extent > 0.0f ? (double)nb * (1.0 - 1e-6) / extent : 0.0;
		/* A tiny extent could make k overflow to inf and (c - clo) * k NaN. */
		k[a] = kk > 0.0 && kk < 1e30 ? (float)kk : 0.0f;
		axes += k[a] != 0.0f;
		for (uint32_t j = 0; j < nb; j++) {
			struct bin *bn = &s->bins[a * nb + j];
			rs_bvh__box_empty(bn->lo, bn->hi);
			bn->count = 0;
		}
	}
	return axes;
}

static void fill_bins(struct sah_ctx *s, const struct task *t, const float k[3])
{
	uint32_t nb = s->nbins;
	for (uint32_t i = t->begin; i < t->end; i++) {
		const struct item *it = &s->items[i];
		for (int a = 0; a < 3; a++) {
			/* k = 0 (a flat axis) puts everything in bin 0; the sweep skips it. */
			struct bin *bn = &s->bins[a * nb + bin_of(it->c[a], t->clo[a], k[a], nb)];
			grow(bn->lo, bn->hi, it->lo, it->hi);
			bn->count++;
		}
	}
}

/* Price every plane between non-empty bins of axis a; keep the cheapest in *out. */
static void sweep_axis(struct sah_ctx *s, int a, double area, struct split *out)
{
	struct bin *bins = &s->bins[a * s->nbins];
	uint32_t ne[RS_BVH_MAX_BINS], m = 0;
	for (uint32_t j = 0; j < s->nbins; j++)
		if (bins[j].count)
			ne[m++] = j;
	float rlo[3], rhi[3];
	rs_bvh__box_empty(rlo, rhi);
	uint32_t rn = 0;
	double right_cost[RS_BVH_MAX_BINS];
	for (uint32_t i = m; i-- > 1;) {
		const struct bin *bn = &bins[ne[i]];
		grow(rlo, rhi, bn->lo, bn->hi);
		rn += bn->count;
		right_cost[i] = box_area(rlo, rhi) * rn;
		memcpy(s->right[i].lo, rlo, sizeof rlo);
		memcpy(s->right[i].hi, rhi, sizeof rhi);
	}
	float llo[3], lhi[3];
	rs_bvh__box_empty(llo, lhi);
	uint32_t ln = 0;
	for (uint32_t i = 1; i < m; i++) {
		const struct bin *bn = &bins[ne[i - 1]];
		grow(llo, lhi, bn->lo, bn->hi);
		ln += bn->count;
		double c = 2.0 * s->ct * area + box_area(llo, lhi) * ln + right_cost[i];
		if (c < out->cost)
			take(out, SPLIT_PLANE, a, ne[i], c, llo, lhi, s->right[i].lo,
			     s->right[i].hi);
	}
}

/* Size split: the few large triangles (floor, walls) against the rest. Centroid planes
 * leave such triangles in children whose boxes then overlap everything; one more pass
 * prices putting them aside. Only when they are at most a quarter of the node: a node
 * made mostly of large triangles is a room, whose rays start inside it, where the SAH's
 * outside-ray model misleads (measured on Box, docs/bvh.md). */
static void price_size_split(struct sah_ctx *s, const struct task *t, double area,
                             struct split *out)
{
	uint32_t n = t->end - t->begin, large = 0;
	float inv_ext[3];
	inverse_extent(t, inv_ext);
	float blo[3], bhi[3], slo[3], shi[3];
	rs_bvh__box_empty(blo, bhi);
	rs_bvh__box_empty(slo, shi);
	for (uint32_t i = t->begin; i < t->end; i++) {
		const struct item *it = &s->items[i];
		if (is_large(it, inv_ext)) {
			grow(blo, bhi, it->lo, it->hi);
			large++;
		} else {
			grow(slo, shi, it->lo, it->hi);
		}
	}
	if (large == 0 || large == n || (size_t)large * 4 > n)
		return;
	double cost =
	    2.0 * s->ct * area + box_area(blo, bhi) * large + box_area(slo, shi) * (n - large);
	if (cost < out->cost)
		take(out, SPLIT_SIZE, -1, 0, cost, blo, bhi, slo, shi);
}

/* Best split of task t, or SPLIT_LEAF when making a leaf is better (or required). */
static void find_split(struct sah_ctx *s, const struct task *t, float k[3], struct split *out)
{
	uint32_t n = t->end - t->begin;
	memset(out, 0, sizeof *out);
	out->kind = SPLIT_LEAF;
	out->cost = DBL_MAX;
	if (n == 1)
		return;
	if (prepare_bins(s, t, k) == 0) {
		/* All centroids coincide: no plane separates them; split the list in halves if
		 * the leaf would be too big. */
		if (n > s->leaf_size)
			out->kind = SPLIT_MEDIAN;
		return;
	}
	fill_bins(s, t, k);
	/* Unnormalised costs (times the node area) so flat or point-like nodes (area 0)
	 * still compare. */
	double area = rs_bvh__box_area(t->lo, t->hi);
	for (int a = 0; a < 3; a++)
		if (k[a] != 0.0f)
			sweep_axis(s, a, area, out);
	price_size_split(s, t, area, out);
	if (n <= s->leaf_size && (double)n * area <= out->cost)
		out->kind = SPLIT_LEAF;
}

/* Partition t's items by the split; fills the two child tasks (bounds and centroid
 * bounds) in list order. */
static void partition(struct sah_ctx *s, const struct task *t, const float k[3],
                      const struct split *sp, struct task *left, struct task *right)
{
	*left = (struct task){.begin = t->begin};
	*right = (struct task){.end = t->end};
	rs_bvh__box_empty(left->clo, left->chi);
	rs_bvh__box_empty(right->clo, right->chi);
	uint32_t i = t->begin, j = t->end;
	if (sp->kind == SPLIT_MEDIAN) {
		i = t->begin + (t->end - t->begin) / 2;
	} else if (sp->kind == SPLIT_SIZE) {
		float inv_ext[3];
		inverse_extent(t, inv_ext);
		while (i < j) {
			struct item *it = &s->items[i];
			if (is_large(it, inv_ext)) {
				i++;
			} else {
				struct item tmp = *it;
				*it = s->items[--j];
				s->items[j] = tmp;
			}
		}
	} else {
		int a = sp->axis;
		while (i < j) {
			struct item *it = &s->items[i];
			if (bin_of(it->c[a], t->clo[a], k[a], s->nbins) < sp->bin) {
				i++;
			} else {
				struct item tmp = *it;
				*it = s->items[--j];
				s->items[j] = tmp;
			}
		}
	}
	left->end = right->begin = i;
	rs_bvh__box_empty(left->lo, left->hi);
	rs_bvh__box_empty(right->lo, right->hi);
	for (uint32_t m = t->begin; m < t->end; m++) {
		const struct item *it = &s->items[m];
		struct task *side = m < i ? left : right;
		grow(side->clo, side->chi, it->c, it->c);
		if (sp->kind == SPLIT_MEDIAN)
			grow(side->lo, side->hi, it->lo, it->hi);
	}
	if (sp->kind != SPLIT_MEDIAN) {
		memcpy(left->lo, sp->llo, sizeof left->lo);
		memcpy(left->hi, sp->lhi, sizeof left->hi);
		memcpy(right->lo, sp->rlo, sizeof right->lo);
		memcpy(right->hi, sp->rhi, sizeof right->hi);
	}
}

/* Which child comes first in the pre-order (the walk meets it first: for closest hit its
 * hits shrink tmax before the sibling's box is tested, for any hit it may end the walk):
 * the one with the smaller surface area. Of the orders measured (docs/bvh.md: lower side
 * of the plane, larger area, more or fewer triangles, smaller area) it gave the lowest hit
 * numbers on Box, Cow9 and Cow17. */
static int second_first(const struct task *l, const struct task *r)
{
	return rs_bvh__box_area(r->lo, r->hi) < rs_bvh__box_area(l->lo, l->hi);
}

enum rs_status rs_bvh__build_sah(const struct rs_bvh_desc *desc, const float *positions,
                                 const uint32_t *indices, size_t triangle_count,
                                 struct rs_bvh_node *nodes, uint32_t *order, size_t *out_count,
                                 struct rs_error *err)
{
	size_t n = triangle_count;
	size_t cap = 2 * n - 1;
	struct item *items = malloc(n * sizeof *items);
	struct bin *bins = malloc(4 * (size_t)desc->sah_bins * sizeof *bins);
	uint32_t *parent = malloc(cap * sizeof *parent);
	struct task *stack = malloc((n + 1) * sizeof *stack);
	enum rs_status status = RS_OK;
	if (!items || !bins || !parent || !stack) {
		status =
		    rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory (%zu triangles)", n);
		goto done;
	}
	struct task root = {0, (uint32_t)n, RS_BVH_NO_PARENT, {0}, {0}, {0}, {0}};
	rs_bvh__box_empty(root.lo, root.hi);
	rs_bvh__box_empty(root.clo, root.chi);
	for (size_t t = 0; t < n; t++) {
		struct item *it = &items[t];
		rs_bvh__box_empty(it->lo, it->hi);
		rs_bvh__box_add_triangle(it->lo, it->hi, positions, indices, (uint32_t)t);
		for (int a = 0; a < 3; a++)
			it->c[a] = 0.5f * it->lo[a] + 0.5f * it->hi[a]; /* no overflow */
		it->id = (uint32_t)t;
		grow(root.lo, root.hi, it->lo, it->hi);
		grow(root.clo, root.chi, it->c, it->c);
	}
	struct sah_ctx s = {items,
	                    bins,
	                    bins + 3 * (size_t)desc->sah_bins,
	                    desc->sah_bins,
	                    desc->leaf_size,
	                    desc->traversal_cost};
	size_t top = 0, count = 0;
	stack[top++] = root;
	while (top > 0) {
		struct task t = stack[--top];
		uint32_t k = (uint32_t)count++;
		struct rs_bvh_node *node = &nodes[k];
		parent[k] = t.parent;
		float kk[3];
		struct split sp;
		find_split(&s, &t, kk, &sp);
		node->first = 0;
		node->count = 0;
		if (sp.kind == SPLIT_LEAF) {
			memcpy(node->lo, t.lo, sizeof t.lo);
			memcpy(node->hi, t.hi, sizeof t.hi);
			node->first = t.begin;
			node->count = t.end - t.begin;
			continue;
		}
		rs_bvh__box_empty(node->lo, node->hi);
		struct task l, r;
		partition(&s, &t, kk, &sp, &l, &r);
		l.parent = r.parent = k;
		/* LIFO: push the second child first so the first child follows its parent. */
		if (second_first(&l, &r)) {
			stack[top++] = l;
			stack[top++] = r;
		} else {
			stack[top++] = r;
			stack[top++] = l;
		}
	}
	if (!rs_bvh__finalize(nodes, count, parent)) {
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
		goto done;
	}
	/* Leaves own contiguous record ranges; when the right child is emitted first the
	 * ranges are no longer increasing in pre-order, which the layout allows. */
	for (size_t t = 0; t < n; t++)
		order[t] = items[t].id;
	*out_count = count;
done:
	free(items);
	free(bins);
	free(parent);
	free(stack);
	return status;
}
