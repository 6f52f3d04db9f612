/* Top-down binned SAH (Wald 2007 style), one node at a time: centroids are binned on all
 * three axes, the best plane is found by one sweep over the bins, and the records are
 * partitioned in place, so no sorting and O(n log n) work. Each node costs one binning pass
 * (which also gathers the two sides of the size split) and one partition pass (which also
 * gathers the children's centroid bounds); a node's bounds come from its parent's bins.
 * Nodes are emitted in pre-order from an explicit stack (no recursion: degenerate inputs
 * cannot overflow the C stack).
 *
 * The cost model matches how the traversal counts hit numbers: a leaf hit costs its
 * triangle count; an interior hit costs one box test per child (traversal_cost each) plus
 * the children's costs weighted by their surface-area hit probability.
 *
 * Every decision depends on the node's set of records only (bins are unions and counts),
 * never on how the work was split: big nodes bin in chunks on several threads and small
 * ones bin sparsely, with the same planes, boxes and costs to the bit, so the tree is the
 * same whatever the thread count (and the same as the one-thread builder's before the
 * threads came, docs/bvh.md). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_sah.h"
#include "bvh_v4.h"

#ifdef RS_BVH_WIDE
#include <immintrin.h>
/* AVX code, chosen at run time (s->wide). Each such function ends with vzeroupper: the SSE
 * code that follows ran at a third of its speed with the upper halves of the registers
 * dirty (measured: the whole build took 2.9x as long), and GCC left it out before a tail
 * call. */
#define WIDE_FN __attribute__((target("avx")))
#endif

/* Nodes of at most this many records bin sparsely: only the bins their records fall in are
 * cleared, filled and swept (split_small()). */
#define SMALL_NODE 12u
/* Nodes of at least this many records bin and partition in chunks of CHUNK on the pool
 * (two chunks and up: the nodes just above the subtrees, n / (4 threads) records, would
 * otherwise be binned and partitioned by one thread while the others wait). */
#define PAR_BIN_MIN 8192u
#define CHUNK 4096u

static inline struct rs_bvh__item *task_items(const struct rs_bvh__sah *s,
                                              const struct rs_bvh__task *t)
{
	return t->buf ? s->tmp : s->items;
}

static inline void grow(float lo[4], float hi[4], const float plo[4], const float phi[4])
{
	rs_v4_grow(lo, hi, plo, phi);
}

static inline void box_empty4(float lo[4], float hi[4])
{
	rs_v4_store(lo, rs_v4_set(FLT_MAX, FLT_MAX, FLT_MAX, 0.0f));
	rs_v4_store(hi, rs_v4_set(-FLT_MAX, -FLT_MAX, -FLT_MAX, 0.0f));
}

/* Surface area (inlined copy of rs_bvh__box_area for the sweeps; boxes here are never
 * empty). */
static inline double box_area(const float lo[4], const float hi[4])
{
#ifdef RS_BVH_SSE
	/* The same operations two lanes at a time: exact conversions, then x y + y z + z x
	 * summed in the same order. */
	__m128 l = _mm_loadu_ps(lo), h = _mm_loadu_ps(hi);
	__m128d xy = _mm_sub_pd(_mm_cvtps_pd(h), _mm_cvtps_pd(l));
	__m128d zw =
	    _mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(h, h)), _mm_cvtps_pd(_mm_movehl_ps(l, l)));
	__m128d p = _mm_mul_pd(xy, _mm_shuffle_pd(xy, zw, 1));
	double x = _mm_cvtsd_f64(xy), z = _mm_cvtsd_f64(zw);
	return 2.0 * (_mm_cvtsd_f64(p) + _mm_cvtsd_f64(_mm_unpackhi_pd(p, p)) + z * x);
#else
	double x = (double)hi[0] - lo[0], y = (double)hi[1] - lo[1], z = (double)hi[2] - lo[2];
	return 2.0 * (x * y + y * z + z * x);
#endif
}

/* What find_split() chose for a node. */
enum split_kind {
	SPLIT_LEAF,   /* no split: a leaf is cheaper (or required) */
	SPLIT_PLANE,  /* centroid plane: records in bins below `bin` on `axis` go left */
	SPLIT_MEDIAN, /* all centroids coincide: halves of the list, bounds from the records */
	SPLIT_SIZE,   /* the large triangles (left) against the rest (right) */
};

struct split {
	enum split_kind kind;
	int axis;     /* SPLIT_PLANE only */
	uint32_t bin; /* SPLIT_PLANE only */
	float llo[4], lhi[4], rlo[4], rhi[4];
	double cost; /* unnormalised (times the node area), DBL_MAX when none priced yet */
};

/* The node's split parameters: bin scale per axis (0 for an axis whose centroids
 * coincide) and inverse extent (size split). */
struct node_scale {
	float k[4], inv_ext[4]; /* lane 3: 0 */
	rs_v4 clo, kv, top, inv, half;
	int axes; /* axes that can be split */
};

/* A record's bin on every axis (lane 3 meaningless). */
static inline void item_bins(const struct rs_bvh__item *it, const struct node_scale *sc,
                             int32_t out[4])
{
	rs_v4_bins(rs_v4_centroid(rs_v4_load(it->lo), rs_v4_load(it->hi)), sc->clo, sc->kv, sc->top,
	           out);
}

/* A "large" triangle spans at least half the node on some axis. */
static inline int spans_half(rs_v4 lo, rs_v4 hi, const struct node_scale *sc)
{
	return (rs_v4_ge_mask(rs_v4_mul(rs_v4_sub(hi, lo), sc->inv), sc->half) & 7) != 0;
}

static inline int is_large(const struct rs_bvh__item *it, const struct node_scale *sc)
{
	return spans_half(rs_v4_load(it->lo), rs_v4_load(it->hi), sc);
}

static void take(struct split *out, enum split_kind kind, int axis, uint32_t bin, double cost,
                 const float llo[4], const float lhi[4], const float rlo[4], const float rhi[4])
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

static void node_scale(uint32_t nb, const struct rs_bvh__task *t, struct node_scale *sc)
{
#ifdef RS_BVH_SSE
	/* The loop below, lane by lane (the same divisions and conversions; a lane that fails a
	 * test, and lane 3, masked to +0). */
	const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)), zero = _mm_setzero_ps();
	__m128 extent = _mm_sub_ps(_mm_loadu_ps(t->chi), _mm_loadu_ps(t->clo));
	const __m128d num = _mm_set1_pd((double)nb * (1.0 - 1e-6)), lim = _mm_set1_pd(1e30);
	__m128d k01 = _mm_div_pd(num, _mm_cvtps_pd(extent));
	__m128d k23 = _mm_div_pd(num, _mm_cvtps_pd(_mm_movehl_ps(extent, extent)));
	k01 = _mm_and_pd(k01,
	                 _mm_and_pd(_mm_cmpgt_pd(k01, _mm_setzero_pd()), _mm_cmplt_pd(k01, lim)));
	k23 = _mm_and_pd(k23,
	                 _mm_and_pd(_mm_cmpgt_pd(k23, _mm_setzero_pd()), _mm_cmplt_pd(k23, lim)));
	__m128 k = _mm_movelh_ps(_mm_cvtpd_ps(k01), _mm_cvtpd_ps(k23));
	k = _mm_and_ps(k, _mm_and_ps(xyz, _mm_cmpgt_ps(extent, zero)));
	__m128 e = _mm_sub_ps(_mm_loadu_ps(t->hi), _mm_loadu_ps(t->lo));
	__m128 inv =
	    _mm_and_ps(_mm_div_ps(_mm_set1_ps(1.0f), e), _mm_and_ps(xyz, _mm_cmpgt_ps(e, zero)));
	_mm_storeu_ps(sc->k, k);
	_mm_storeu_ps(sc->inv_ext, inv);
	int nonzero = _mm_movemask_ps(_mm_cmpneq_ps(k, zero));
	sc->axes = (nonzero & 1) + (nonzero >> 1 & 1) + (nonzero >> 2 & 1);
#else
	sc->axes = 0;
	sc->k[3] = sc->inv_ext[3] = 0.0f;
	for (int a = 0; a < 3; a++) {
		float extent = t->chi[a] - t->clo[a];
		double kk = extent > 0.0f ? (double)nb * (1.0 - 1e-6) / extent : 0.0;
		/* A tiny extent could make k overflow to inf and (c - clo) * k NaN. */
		sc->k[a] = kk > 0.0 && kk < 1e30 ? (float)kk : 0.0f;
		sc->axes += sc->k[a] != 0.0f;
		float e = t->hi[a] - t->lo[a];
		sc->inv_ext[a] = e > 0.0f ? 1.0f / e : 0.0f;
	}
#endif
	float top = (float)(nb - 1);
	sc->clo = rs_v4_set(t->clo[0], t->clo[1], t->clo[2], 0.0f);
	sc->kv = rs_v4_load(sc->k);
	sc->top = rs_v4_set(top, top, top, top);
	sc->inv = rs_v4_load(sc->inv_ext);
	sc->half = rs_v4_set(0.5f, 0.5f, 0.5f, 0.5f);
}

static void binning_clear(struct rs_bvh__binning *b, uint32_t nb)
{
	for (uint32_t j = 0; j < 3 * nb; j++) {
		box_empty4(b->bins[j].lo, b->bins[j].hi);
		b->counts[j] = 0;
	}
	box_empty4(b->blo, b->bhi);
	box_empty4(b->slo, b->shi);
	b->large = 0;
}

/* The size split's two sides as one pass gathers them: large (spanning half the node) and
 * the rest, kept in registers (stores to the bins could alias memory). */
struct sides {
	rs_v4 blo, bhi, slo, shi;
	uint32_t large;
};

static inline void sides_add(struct sides *d, rs_v4 lo, rs_v4 hi, const struct node_scale *sc)
{
	if (spans_half(lo, hi, sc)) {
		d->blo = rs_v4_min(d->blo, lo);
		d->bhi = rs_v4_max(d->bhi, hi);
		d->large++;
	} else {
		d->slo = rs_v4_min(d->slo, lo);
		d->shi = rs_v4_max(d->shi, hi);
	}
}

static inline void sides_store(const struct sides *d, struct rs_bvh__binning *b)
{
	rs_v4_store(b->blo, d->blo);
	rs_v4_store(b->bhi, d->bhi);
	rs_v4_store(b->slo, d->slo);
	rs_v4_store(b->shi, d->shi);
	b->large = d->large;
}

/* Nodes of at least this many records bin into two sets of bins, even records into one and
 * odd ones into the other, merged at the end (bin_range()). 128 since the records go in
 * pairs (measured on Cow17, one thread: 2-5 % faster than 64, 32 slower, 256 not told
 * apart). */
#define TWO_SETS_MIN 128u

/* One record into the bins of all three axes (a flat axis, k = 0, fills bin 0, which the
 * sweep skips). */
static inline __attribute__((always_inline)) void bin_one(struct rs_bvh__bin *bins,
                                                          uint32_t *counts, rs_v4 lo, rs_v4 hi,
                                                          const struct node_scale *sc, uint32_t nb)
{
	int32_t bin[4];
	rs_v4_bins(rs_v4_centroid(lo, hi), sc->clo, sc->kv, sc->top, bin);
	for (uint32_t a = 0; a < 3; a++) {
		uint32_t j = a * nb + (uint32_t)bin[a];
		rs_v4_store(bins[j].lo, rs_v4_min(rs_v4_load(bins[j].lo), lo));
		rs_v4_store(bins[j].hi, rs_v4_max(rs_v4_load(bins[j].hi), hi));
		counts[j]++;
	}
}

#ifdef RS_BVH_WIDE
WIDE_FN static inline __attribute__((always_inline)) void
bin_one_wide(struct rs_bvh__bin *bins, uint32_t *counts, rs_v4 lo, rs_v4 hi,
             const struct node_scale *sc, uint32_t nb)
{
	int32_t bin[4];
	rs_v4_bins(rs_v4_centroid(lo, hi), sc->clo, sc->kv, sc->top, bin);
	__m256 r = _mm256_set_m128(hi, lo);
	for (uint32_t a = 0; a < 3; a++) {
		uint32_t j = a * nb + (uint32_t)bin[a];
		__m256 o = _mm256_loadu_ps(bins[j].lo);
		_mm256_storeu_ps(bins[j].lo,
		                 _mm256_blend_ps(_mm256_min_ps(o, r), _mm256_max_ps(o, r), 0xf0));
		counts[j]++;
	}
}
#endif
typedef void (*bin_one_fn)(struct rs_bvh__bin *, uint32_t *, rs_v4, rs_v4,
                           const struct node_scale *, uint32_t);

/* One pass over records [begin, end): the bins of all three axes and both sides of the
 * size split. Neighbouring records (the partition keeps them near each other in space)
 * often fall in the same bin, and each update of a bin waits for the previous one's store:
 * with two sets of bins, alternate records update independent bins. Min, max and counts
 * merge exactly, so the bins are the same bits either way. */
static inline __attribute__((always_inline)) void
bin_range_body(const struct rs_bvh__item *items, uint32_t begin, uint32_t end,
               const struct node_scale *scale, uint32_t nb, struct rs_bvh__binning *b,
               bin_one_fn one)
{
	/* A copy the bins' stores cannot alias, so its vectors stay in registers. */
	const struct node_scale copy = *scale, *sc = &copy;
	binning_clear(b, nb);
	struct rs_bvh__bin *bins = b->bins;
	uint32_t *counts = b->counts;
	struct rs_bvh__bin bins2[3 * RS_BVH_MAX_BINS];
	uint32_t counts2[3 * RS_BVH_MAX_BINS];
	int two = end - begin >= TWO_SETS_MIN;
	if (two) {
		for (uint32_t j = 0; j < 3 * nb; j++) {
			box_empty4(bins2[j].lo, bins2[j].hi);
			counts2[j] = 0;
		}
	}
	struct sides d = {rs_v4_load(b->blo), rs_v4_load(b->bhi), rs_v4_load(b->slo),
	                  rs_v4_load(b->shi), 0};
	uint32_t i = begin;
	/* Pairs: the first record of each into one set, the second into the other. */
	for (; two && i + 1 < end; i += 2) {
		rs_v4 lo = rs_v4_load(items[i].lo), hi = rs_v4_load(items[i].hi);
		rs_v4 lo2 = rs_v4_load(items[i + 1].lo), hi2 = rs_v4_load(items[i + 1].hi);
		one(bins, counts, lo, hi, sc, nb);
		one(bins2, counts2, lo2, hi2, sc, nb);
		sides_add(&d, lo, hi, sc);
		sides_add(&d, lo2, hi2, sc);
	}
	for (; i < end; i++) {
		rs_v4 lo = rs_v4_load(items[i].lo), hi = rs_v4_load(items[i].hi);
		one(bins, counts, lo, hi, sc, nb);
		sides_add(&d, lo, hi, sc);
	}
	if (two) {
		for (uint32_t j = 0; j < 3 * nb; j++) {
			grow(bins[j].lo, bins[j].hi, bins2[j].lo, bins2[j].hi);
			counts[j] += counts2[j];
		}
	}
	sides_store(&d, b);
}

static void bin_range_narrow(const struct rs_bvh__item *items, uint32_t begin, uint32_t end,
                             const struct node_scale *sc, uint32_t nb, struct rs_bvh__binning *b)
{
	bin_range_body(items, begin, end, sc, nb, b, bin_one);
}

#ifdef RS_BVH_WIDE
WIDE_FN static void bin_range_wide(const struct rs_bvh__item *items, uint32_t begin, uint32_t end,
                                   const struct node_scale *sc, uint32_t nb,
                                   struct rs_bvh__binning *b)
{
	bin_range_body(items, begin, end, sc, nb, b, bin_one_wide);
	_mm256_zeroupper();
}
#endif

static void bin_range(const struct rs_bvh__sah *s, const struct rs_bvh__item *items, uint32_t begin,
                      uint32_t end, const struct node_scale *sc, struct rs_bvh__binning *b)
{
#ifdef RS_BVH_WIDE
	if (s->wide) {
		bin_range_wide(items, begin, end, sc, s->nbins, b);
		return;
	}
#endif
	bin_range_narrow(items, begin, end, sc, s->nbins, b);
}

struct chunk_job {
	const struct rs_bvh__sah *s;
	const struct rs_bvh__task *t;
	const struct node_scale *sc;
	uint32_t chunks;
};

static uint32_t chunk_edge(const struct rs_bvh__task *t, uint32_t c, uint32_t chunks)
{
	return t->begin + (uint32_t)((uint64_t)(t->end - t->begin) * c / chunks);
}

static void bin_chunk(void *ctx, uint32_t c, uint32_t worker)
{
	(void)worker;
	const struct chunk_job *j = ctx;
	bin_range(j->s, task_items(j->s, j->t), chunk_edge(j->t, c, j->chunks),
	          chunk_edge(j->t, c + 1, j->chunks), j->sc, &j->s->chunk_bins[c]);
}

/* o's bins into b's (min, max and counts: exact in any grouping). */
static void merge_bins(struct rs_bvh__binning *b, const struct rs_bvh__binning *o, uint32_t nb)
{
	for (uint32_t j = 0; j < 3 * nb; j++) {
		grow(b->bins[j].lo, b->bins[j].hi, o->bins[j].lo, o->bins[j].hi);
		b->counts[j] += o->counts[j];
	}
	grow(b->blo, b->bhi, o->blo, o->bhi);
	grow(b->slo, b->shi, o->slo, o->shi);
	b->large += o->large;
}

/* Bin a node, in chunks on the pool when it is big; min, max and counts merge exactly, so
 * the bins are the same however the records were chunked. */
static const struct rs_bvh__binning *bin_node(const struct rs_bvh__sah *s,
                                              struct rs_bvh__scratch *w,
                                              const struct rs_bvh__task *t,
                                              const struct node_scale *sc)
{
	uint32_t n = t->end - t->begin, nb = s->nbins;
	uint32_t chunks = s->pool && n >= PAR_BIN_MIN ? n / CHUNK : 1;
	chunks = chunks < s->max_chunks ? chunks : s->max_chunks;
	if (chunks < 2) {
		bin_range(s, task_items(s, t), t->begin, t->end, sc, &w->binning);
		return &w->binning;
	}
	struct chunk_job job = {s, t, sc, chunks};
	rs_bvh__pool_run(s->pool, chunks, bin_chunk, &job);
	struct rs_bvh__binning *b = &s->chunk_bins[0];
	for (uint32_t c = 1; c < chunks; c++) {
		merge_bins(b, &s->chunk_bins[c], nb);
	}
	return b;
}

/* One plane's boxes, left of it (boxes of bins ne[0..i)) and right of it (ne[i..m)). */
struct plane_boxes {
	_Alignas(16) float llo[4], lhi[4], rlo[4], rhi[4];
};

/* cost[i] = split + area(left i) ln[i] + area(right i) rn[i] for planes [from, to), with
 * box_area()'s operations in its order, so the same bits as a plane priced alone. */
static void plane_costs_narrow(const struct plane_boxes *pb, const uint32_t *ln, const uint32_t *rn,
                               uint32_t from, uint32_t to, double split, double *cost)
{
	for (uint32_t i = from; i < to; i++) {
		double right = box_area(pb[i].rlo, pb[i].rhi) * rn[i];
		cost[i] = split + box_area(pb[i].llo, pb[i].lhi) * ln[i] + right;
	}
}

#ifdef RS_BVH_WIDE
/* Areas of four boxes (lo at offset 0, hi at offset 4 floats of each, stride floats apart),
 * four lanes of double at a time: the conversions, differences, products and sums of
 * box_area(), in its order (x y + y z + z x, then times 2), transposed so that lane k is
 * box k. */
WIDE_FN static inline __m256d areas4(const float *box, size_t stride)
{
	__m256d d[4];
	for (int k = 0; k < 4; k++) {
		const float *b = box + (size_t)k * stride;
		d[k] = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(b + 4)),
		                     _mm256_cvtps_pd(_mm_load_ps(b)));
	}
	__m256d xz01 = _mm256_unpacklo_pd(d[0], d[1]), yw01 = _mm256_unpackhi_pd(d[0], d[1]);
	__m256d xz23 = _mm256_unpacklo_pd(d[2], d[3]), yw23 = _mm256_unpackhi_pd(d[2], d[3]);
	__m256d x = _mm256_permute2f128_pd(xz01, xz23, 0x20);
	__m256d z = _mm256_permute2f128_pd(xz01, xz23, 0x31);
	__m256d y = _mm256_permute2f128_pd(yw01, yw23, 0x20);
	__m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, y), _mm256_mul_pd(y, z)),
	                            _mm256_mul_pd(z, x));
	return _mm256_mul_pd(_mm256_set1_pd(2.0), sum);
}

/* plane_costs_narrow(), four planes at a time (counts below 2^31: a record is 32 bytes). */
WIDE_FN static void plane_costs_wide(const struct plane_boxes *pb, const uint32_t *ln,
                                     const uint32_t *rn, uint32_t from, uint32_t to, double split,
                                     double *cost)
{
	const size_t stride = sizeof *pb / sizeof(float);
	__m256d sp = _mm256_set1_pd(split);
	uint32_t i = from;
	for (; i + 4 <= to; i += 4) {
		__m256d lc =
		    _mm256_cvtepi32_pd(_mm_loadu_si128((const __m128i *)(const void *)(ln + i)));
		__m256d rc =
		    _mm256_cvtepi32_pd(_mm_loadu_si128((const __m128i *)(const void *)(rn + i)));
		__m256d right = _mm256_mul_pd(areas4(pb[i].rlo, stride), rc);
		__m256d left = _mm256_mul_pd(areas4(pb[i].llo, stride), lc);
		_mm256_storeu_pd(cost + i, _mm256_add_pd(_mm256_add_pd(sp, left), right));
	}
	_mm256_zeroupper();
	plane_costs_narrow(pb, ln, rn, i, to, split, cost);
}
#endif

/* Price every plane between the non-empty bins ne[0..m) of axis a (ascending); keep the
 * cheapest in *out (the first of equal costs, as planes are compared in order). One scan
 * grows the left boxes upwards and the right ones downwards, in the order a plane priced
 * alone would grow them, so the boxes are the same bits; then the costs, four planes at a
 * time where the CPU has AVX (the same operations, so the same bits: s->wide decides
 * nothing about the tree). */
static void sweep_bins(const struct rs_bvh__sah *s, const struct rs_bvh__binning *b, int a,
                       const uint32_t *ne, uint32_t m, double area, struct split *out)
{
	if (m < 2)
		return;
	const struct rs_bvh__bin *bins = &b->bins[a * s->nbins];
	const uint32_t *counts = &b->counts[a * s->nbins];
	struct plane_boxes pb[RS_BVH_MAX_BINS];
	uint32_t ln[RS_BVH_MAX_BINS], rn[RS_BVH_MAX_BINS];
	double cost[RS_BVH_MAX_BINS];
	float lo[4], hi[4];
	box_empty4(lo, hi);
	rs_v4 llo = rs_v4_load(lo), lhi = rs_v4_load(hi), rlo = llo, rhi = lhi;
	uint32_t lsum = 0, rsum = 0;
	for (uint32_t i = 1; i < m; i++) {
		const struct rs_bvh__bin *l = &bins[ne[i - 1]], *r = &bins[ne[m - i]];
		llo = rs_v4_min(llo, rs_v4_load(l->lo));
		lhi = rs_v4_max(lhi, rs_v4_load(l->hi));
		rlo = rs_v4_min(rlo, rs_v4_load(r->lo));
		rhi = rs_v4_max(rhi, rs_v4_load(r->hi));
		lsum += counts[ne[i - 1]];
		rsum += counts[ne[m - i]];
		rs_v4_store(pb[i].llo, llo);
		rs_v4_store(pb[i].lhi, lhi);
		rs_v4_store(pb[m - i].rlo, rlo);
		rs_v4_store(pb[m - i].rhi, rhi);
		ln[i] = lsum;
		rn[m - i] = rsum;
	}
	double split = 2.0 * s->ct * area;
#ifdef RS_BVH_WIDE
	if (s->wide)
		plane_costs_wide(pb, ln, rn, 1, m, split, cost);
	else
#endif
		plane_costs_narrow(pb, ln, rn, 1, m, split, cost);
	uint32_t best = 0;
	double best_cost = out->cost;
	for (uint32_t i = 1; i < m; i++) {
		if (cost[i] < best_cost) {
			best_cost = cost[i];
			best = i;
		}
	}
	if (best != 0)
		take(out, SPLIT_PLANE, a, ne[best], best_cost, pb[best].llo, pb[best].lhi,
		     pb[best].rlo, pb[best].rhi);
}

/* All bins of axis a were filled: sweep the non-empty ones. */
static void sweep_axis(const struct rs_bvh__sah *s, const struct rs_bvh__binning *b, int a,
                       double area, struct split *out)
{
	const uint32_t *counts = &b->counts[a * s->nbins];
	uint32_t ne[RS_BVH_MAX_BINS], m = 0;
	for (uint32_t j = 0; j < s->nbins; j++) {
		ne[m] = j;
		m += counts[j] != 0;
	}
	sweep_bins(s, b, a, ne, m, area, out);
}

enum { BIN_WORDS = RS_BVH_MAX_BINS / 64 };

/* A small node: only the bins its few records fall in are cleared, filled and swept
 * (sparse binning; the same bins, so the same planes and costs as sweep_axis()), and the
 * size split's two sides are gathered on the way. */
static void split_small(const struct rs_bvh__sah *s, struct rs_bvh__scratch *w,
                        const struct rs_bvh__task *t, const struct node_scale *scale, double area,
                        struct split *out)
{
	const struct rs_bvh__item *items = task_items(s, t) + t->begin;
	uint32_t n = t->end - t->begin, nb = s->nbins, words = (nb + 63) / 64;
	int32_t bins[SMALL_NODE][4];
	uint64_t used[3][BIN_WORDS] = {{0}};
	struct rs_bvh__binning *b = &w->binning;
	/* The scale in registers too (stores could alias it). */
	const struct node_scale copy = *scale, *sc = &copy;
	float elo[4], ehi[4];
	box_empty4(elo, ehi);
	struct sides d = {rs_v4_load(elo), rs_v4_load(ehi), rs_v4_load(elo), rs_v4_load(ehi), 0};
	for (uint32_t i = 0; i < n; i++) {
		item_bins(&items[i], sc, bins[i]);
		for (int a = 0; a < 3; a++)
			used[a][bins[i][a] >> 6] |= 1ull << (bins[i][a] & 63);
		sides_add(&d, rs_v4_load(items[i].lo), rs_v4_load(items[i].hi), sc);
	}
	sides_store(&d, b);
	uint32_t ne[3][SMALL_NODE], m[3] = {0, 0, 0};
	for (int a = 0; a < 3; a++) {
		for (uint32_t wd = 0; wd < words; wd++) {
			for (uint64_t bits = used[a][wd]; bits; bits &= bits - 1) {
				uint32_t j = 64 * wd + (uint32_t)__builtin_ctzll(bits);
				box_empty4(b->bins[a * nb + j].lo, b->bins[a * nb + j].hi);
				b->counts[a * nb + j] = 0;
				ne[a][m[a]++] = j;
			}
		}
	}
	for (uint32_t i = 0; i < n; i++) {
		for (uint32_t a = 0; a < 3; a++) {
			uint32_t j = a * nb + (uint32_t)bins[i][a];
			grow(b->bins[j].lo, b->bins[j].hi, items[i].lo, items[i].hi);
			b->counts[j]++;
		}
	}
	for (int a = 0; a < 3; a++)
		if (sc->k[a] != 0.0f)
			sweep_bins(s, b, a, ne[a], m[a], area, out);
}

/* Size split: the few large triangles (floor, walls) against the rest. Centroid planes
 * leave such triangles in children whose boxes then overlap everything, so each node
 * prices putting them aside. Only when they are at most a quarter of the node: a node
 * made mostly of large triangles is a room, whose rays start inside it, where the SAH's
 * outside-ray model misleads (measured on Box, docs/bvh.md). */
static void price_size_split(const struct rs_bvh__sah *s, const struct rs_bvh__binning *b,
                             uint32_t n, double area, struct split *out)
{
	uint32_t large = b->large;
	if (large == 0 || large == n || (size_t)large * 4 > n)
		return;
	double cost = 2.0 * s->ct * area + box_area(b->blo, b->bhi) * large +
	              box_area(b->slo, b->shi) * (n - large);
	if (cost < out->cost)
		take(out, SPLIT_SIZE, -1, 0, cost, b->blo, b->bhi, b->slo, b->shi);
}

/* Whether no split can beat the leaf, so the search may be skipped: a child's box holds
 * each of its triangles' boxes, so a split costs at least 2 ct area + the sum of the
 * triangles' box areas (with a margin far above the rounding of either sum). Decides about
 * half the nodes of at most leaf_size triangles on the Cow scenes. */
static int leaf_is_cheapest(const struct rs_bvh__sah *s, const struct rs_bvh__task *t, double area)
{
	const struct rs_bvh__item *items = task_items(s, t);
	double bound = 2.0 * s->ct * area;
	for (uint32_t i = t->begin; i < t->end; i++)
		bound += box_area(items[i].lo, items[i].hi);
	return (double)(t->end - t->begin) * area <= bound * (1.0 - 1e-9);
}

/* Task t's bins if they were made while its parent's records were moved (the slot is
 * freed: only the thread that builds the upper nodes partitions in chunks). */
static const struct rs_bvh__binning *prebinned(const struct rs_bvh__sah *s,
                                               const struct rs_bvh__task *t)
{
	for (uint32_t i = 0; i < s->prebins; i++) {
		struct rs_bvh__prebin *p = &s->prebin[i];
		if (p->used && p->begin == t->begin && p->end == t->end) {
			p->used = 0;
			return &p->b;
		}
	}
	return NULL;
}

/* Best split of task t, or SPLIT_LEAF when making a leaf is better (or required). */
static void find_split(const struct rs_bvh__sah *s, struct rs_bvh__scratch *w,
                       const struct rs_bvh__task *t, struct node_scale *sc, struct split *out)
{
	uint32_t n = t->end - t->begin;
	out->kind = SPLIT_LEAF;
	out->cost = DBL_MAX;
	/* Every split costs at least 2 ct area, so a leaf of n <= 2 ct triangles (n * area)
	 * is never dearer: no need to price one. */
	if (n == 1 || (n <= s->leaf_size && (double)n <= 2.0 * s->ct))
		return;
	/* Unnormalised costs (times the node area) so flat or point-like nodes (area 0)
	 * still compare. */
	double area = rs_bvh__box_area(t->lo, t->hi);
	if (n <= s->leaf_size && leaf_is_cheapest(s, t, area))
		return;
	node_scale(s->nbins, t, sc);
	if (sc->axes == 0) {
		/* All centroids coincide: no plane separates them; split the list in halves if
		 * the leaf would be too big. */
		if (n > s->leaf_size)
			out->kind = SPLIT_MEDIAN;
		return;
	}
	if (n <= SMALL_NODE) {
		split_small(s, w, t, sc, area, out);
		price_size_split(s, &w->binning, n, area, out);
	} else {
		const struct rs_bvh__binning *b = prebinned(s, t);
		if (!b)
			b = bin_node(s, w, t, sc);
		for (int a = 0; a < 3; a++)
			if (sc->k[a] != 0.0f)
				sweep_axis(s, b, a, area, out);
		price_size_split(s, b, n, area, out);
	}
	if (n <= s->leaf_size && (double)n * area <= out->cost)
		out->kind = SPLIT_LEAF;
}

/* Records [begin, end) of src by the split: left ones to dst ascending from *l, right ones
 * descending from *r (the next goes to dst[*r - 1]), so the children's records are the
 * left ones in list order and then the right ones in reverse list order. Counts and
 * centroid bounds go to *p. Every record is written to both ends and one end advances (no
 * branch to mispredict), so both ends must stay inside [begin, end): *l = begin and
 * *r = end. */
static void part_range_narrow(const struct rs_bvh__item *src, struct rs_bvh__item *dst,
                              uint32_t begin, uint32_t end, uint32_t *l, uint32_t *r,
                              const struct node_scale *sc, const struct split *sp,
                              struct rs_bvh__part *p)
{
	const rs_v4 pad[2] = {rs_v4_set(0.0f, 0.0f, 0.0f, 0.0f),
	                      rs_v4_set(INFINITY, INFINITY, INFINITY, INFINITY)};
	float lo[4], hi[4];
	box_empty4(lo, hi);
	rs_v4 lclo = rs_v4_load(lo), lchi = rs_v4_load(hi), rclo = lclo, rchi = lchi;
	uint32_t li = *l, ri = *r, left = 0;
	int a = sp->axis, size = sp->kind == SPLIT_SIZE;
	/* bin < B exactly when the clamped (c - clo) k < B (B >= 1 an integer, truncation
	 * and clamping to [0, top] keep the order; NaN goes to bin 0 and compares false), so
	 * the plane test needs neither the clamp nor the conversion. */
	float fb = (float)sp->bin;
	rs_v4 plane = rs_v4_set(fb, fb, fb, fb);
	for (uint32_t i = begin; i < end; i++) {
		const struct rs_bvh__item *it = &src[i];
		rs_v4 c = rs_v4_centroid(rs_v4_load(it->lo), rs_v4_load(it->hi));
		int go_left;
		if (size) {
			go_left = is_large(it, sc);
		} else {
			rs_v4 f = rs_v4_mul(rs_v4_sub(c, sc->clo), sc->kv);
			go_left = !((rs_v4_ge_mask(f, plane) >> a) & 1);
		}
		left += (uint32_t)go_left;
		/* Without a branch: c + 0 = c (a zero's sign aside), and c + inf = inf,
		 * c - inf = -inf leave the other side's bounds as they are. */
		lclo = rs_v4_min(lclo, rs_v4_add(c, pad[!go_left]));
		lchi = rs_v4_max(lchi, rs_v4_sub(c, pad[!go_left]));
		rclo = rs_v4_min(rclo, rs_v4_add(c, pad[go_left]));
		rchi = rs_v4_max(rchi, rs_v4_sub(c, pad[go_left]));
		dst[li] = *it;
		dst[ri - 1] = *it;
		li += (uint32_t)go_left;
		ri -= (uint32_t)!go_left;
	}
	*l = li;
	*r = ri;
	p->left = left;
	p->right = (end - begin) - left;
	rs_v4_store(p->lclo, lclo);
	rs_v4_store(p->lchi, lchi);
	rs_v4_store(p->rclo, rclo);
	rs_v4_store(p->rchi, rchi);
}

#ifdef RS_BVH_WIDE
/* part_range_narrow() of a plane split with AVX: the record moved in one register, and the
 * side's lanes picked by a blend instead of the padding's add (c + 0 towards the lower
 * bounds, c itself towards the upper ones, +-inf on the other side: the values the padding
 * gives, so the same bits). */
WIDE_FN static void part_plane_wide(const struct rs_bvh__item *src, struct rs_bvh__item *dst,
                                    uint32_t begin, uint32_t end, uint32_t *l, uint32_t *r,
                                    const struct node_scale *sc, const struct split *sp,
                                    struct rs_bvh__part *p)
{
	const __m128 half = _mm_set1_ps(0.5f), zero = _mm_setzero_ps();
	const __m128 inf = _mm_set1_ps(INFINITY), ninf = _mm_set1_ps(-INFINITY);
	const __m128 clo = sc->clo, k = sc->kv, plane = _mm_set1_ps((float)sp->bin);
	const __m128i axis = _mm_set1_epi32(sp->axis);
	__m128 lclo = _mm_setr_ps(FLT_MAX, FLT_MAX, FLT_MAX, 0.0f);
	__m128 lchi = _mm_setr_ps(-FLT_MAX, -FLT_MAX, -FLT_MAX, 0.0f), rclo = lclo, rchi = lchi;
	uint32_t li = *l, ri = *r;
	for (uint32_t i = begin; i < end; i++) {
		const struct rs_bvh__item *it = &src[i];
		__m256 rec = _mm256_loadu_ps(it->lo);
		__m128 c = _mm_add_ps(_mm_mul_ps(half, _mm_loadu_ps(it->lo)),
		                      _mm_mul_ps(half, _mm_loadu_ps(it->hi)));
		__m128 f = _mm_mul_ps(_mm_sub_ps(c, clo), k);
		__m128 right = _mm_permutevar_ps(_mm_cmpge_ps(f, plane), axis);
		uint32_t go_right = (uint32_t)_mm_movemask_ps(right) & 1u;
		__m128 c0 = _mm_add_ps(c, zero);
		lclo = _mm_min_ps(lclo, _mm_blendv_ps(c0, inf, right));
		lchi = _mm_max_ps(lchi, _mm_blendv_ps(c, ninf, right));
		rclo = _mm_min_ps(rclo, _mm_blendv_ps(inf, c0, right));
		rchi = _mm_max_ps(rchi, _mm_blendv_ps(ninf, c, right));
		_mm256_storeu_ps(dst[li].lo, rec);
		_mm256_storeu_ps(dst[ri - 1].lo, rec);
		li += go_right ^ 1u;
		ri -= go_right;
	}
	p->left = li - *l;
	p->right = (end - begin) - p->left;
	*l = li;
	*r = ri;
	_mm_storeu_ps(p->lclo, lclo);
	_mm_storeu_ps(p->lchi, lchi);
	_mm_storeu_ps(p->rclo, rclo);
	_mm_storeu_ps(p->rchi, rchi);
	_mm256_zeroupper();
}
#endif

static void part_range(const struct rs_bvh__sah *s, const struct rs_bvh__item *src,
                       struct rs_bvh__item *dst, uint32_t begin, uint32_t end, uint32_t *l,
                       uint32_t *r, const struct node_scale *sc, const struct split *sp,
                       struct rs_bvh__part *p)
{
#ifdef RS_BVH_WIDE
	if (s->wide && sp->kind == SPLIT_PLANE) {
		part_plane_wide(src, dst, begin, end, l, r, sc, sp, p);
		return;
	}
#endif
	part_range_narrow(src, dst, begin, end, l, r, sc, sp, p);
}

struct part_job {
	const struct rs_bvh__sah *s;
	const struct rs_bvh__task *t;
	const struct node_scale *sc;
	const struct split *sp;
	uint32_t chunks;
	/* Whether the left and right child are binned as their records are moved. */
	int bin_child[2];
	struct node_scale child_sc[2];
};

/* Chunk c partitioned within its own range of the other buffer: its left records at the
 * bottom, its right ones at the top, in the order the whole node's pass would give them. */
static void part_chunk(void *ctx, uint32_t c, uint32_t worker)
{
	(void)worker;
	const struct part_job *j = ctx;
	const struct rs_bvh__sah *s = j->s;
	uint32_t begin = chunk_edge(j->t, c, j->chunks), end = chunk_edge(j->t, c + 1, j->chunks);
	uint32_t l = begin, r = end;
	part_range(s, task_items(j->s, j->t), j->t->buf ? s->items : s->tmp, begin, end, &l, &r,
	           j->sc, j->sp, &s->chunk_part[c]);
}

/* Chunk c's two blocks copied back into the node's own buffer, where the whole node's pass
 * would have put them: its left ones after the left ones of the chunks before it, its right
 * ones below their right ones. */
static void move_chunk(void *ctx, uint32_t c, uint32_t worker)
{
	(void)worker;
	const struct part_job *j = ctx;
	const struct rs_bvh__sah *s = j->s;
	const struct rs_bvh__task *t = j->t;
	uint32_t l = t->begin, r = t->end;
	for (uint32_t k = 0; k < c; k++) {
		l += s->chunk_part[k].left;
		r -= s->chunk_part[k].right;
	}
	const struct rs_bvh__part *p = &s->chunk_part[c];
	const struct rs_bvh__item *from = t->buf ? s->items : s->tmp;
	struct rs_bvh__item *to = task_items(s, t);
	uint32_t end = chunk_edge(t, c + 1, j->chunks);
	memcpy(to + l, from + chunk_edge(t, c, j->chunks), p->left * sizeof *to);
	memcpy(to + r - p->right, from + end - p->right, p->right * sizeof *to);
	if (j->bin_child[0])
		bin_range(s, to, l, l + p->left, &j->child_sc[0], &s->child_bins[2 * c]);
	if (j->bin_child[1])
		bin_range(s, to, r - p->right, r, &j->child_sc[1], &s->child_bins[2 * c + 1]);
}

/* Child k's chunk bins merged in chunk order into a free prebin slot. */
static void keep_child_bins(const struct rs_bvh__sah *s, const struct rs_bvh__task *child,
                            uint32_t k, uint32_t chunks, struct rs_bvh__prebin *slot)
{
	uint32_t nb = s->nbins;
	struct rs_bvh__binning *b = &s->child_bins[k];
	for (uint32_t c = 1; c < chunks; c++) {
		merge_bins(b, &s->child_bins[2 * c + k], nb);
	}
	memcpy(slot->b.bins, b->bins, 3 * (size_t)nb * sizeof *b->bins);
	memcpy(slot->b.counts, b->counts, 3 * (size_t)nb * sizeof *b->counts);
	memcpy(slot->b.blo, b->blo, sizeof b->blo);
	memcpy(slot->b.bhi, b->bhi, sizeof b->bhi);
	memcpy(slot->b.slo, b->slo, sizeof b->slo);
	memcpy(slot->b.shi, b->shi, sizeof b->shi);
	slot->b.large = b->large;
	slot->begin = child->begin;
	slot->end = child->end;
	slot->used = 1;
}

static struct rs_bvh__prebin *free_slot(const struct rs_bvh__sah *s,
                                        const struct rs_bvh__prebin * not )
{
	for (uint32_t i = 0; i < s->prebins; i++)
		if (!s->prebin[i].used && &s->prebin[i] != not )
			return &s->prebin[i];
	return NULL;
}

/* The children's ranges and bounds from the partition's counts and the split. */
static void child_tasks(const struct rs_bvh__task *t, const struct split *sp,
                        const struct rs_bvh__part *p, struct rs_bvh__task *left,
                        struct rs_bvh__task *right)
{
	left->end = right->begin = t->begin + p->left;
	memcpy(left->clo, p->lclo, sizeof left->clo);
	memcpy(left->chi, p->lchi, sizeof left->chi);
	memcpy(right->clo, p->rclo, sizeof right->clo);
	memcpy(right->chi, p->rchi, sizeof right->chi);
	memcpy(left->lo, sp->llo, sizeof left->lo);
	memcpy(left->hi, sp->lhi, sizeof left->hi);
	memcpy(right->lo, sp->rlo, sizeof right->lo);
	memcpy(right->hi, sp->rhi, sizeof right->hi);
}

/* Partition t's records by the split into the other buffer; big nodes in chunks on the pool,
 * each partitioned within its own range of the other buffer, then the chunks' blocks copied
 * back to their places in t's own buffer (the records land in the same places either way,
 * only the buffer differs). Fills the two child tasks, whose centroid bounds are gathered on
 * the way. */
static void partition(const struct rs_bvh__sah *s, const struct rs_bvh__task *t,
                      const struct node_scale *sc, const struct split *sp,
                      struct rs_bvh__task *left, struct rs_bvh__task *right)
{
	*left = (struct rs_bvh__task){.begin = t->begin, .buf = t->buf};
	*right = (struct rs_bvh__task){.end = t->end, .buf = t->buf};
	if (sp->kind == SPLIT_MEDIAN) {
		/* Halves of the list, in place. */
		const struct rs_bvh__item *items = task_items(s, t);
		uint32_t i = t->begin + (t->end - t->begin) / 2;
		float lo[4], hi[4];
		box_empty4(lo, hi);
		rs_v4 lclo = rs_v4_load(lo), lchi = rs_v4_load(hi), rclo = lclo, rchi = lchi;
		box_empty4(left->lo, left->hi);
		box_empty4(right->lo, right->hi);
		for (uint32_t m = t->begin; m < t->end; m++) {
			rs_v4 c = rs_v4_centroid(rs_v4_load(items[m].lo), rs_v4_load(items[m].hi));
			if (m < i) {
				lclo = rs_v4_min(lclo, c);
				lchi = rs_v4_max(lchi, c);
				grow(left->lo, left->hi, items[m].lo, items[m].hi);
			} else {
				rclo = rs_v4_min(rclo, c);
				rchi = rs_v4_max(rchi, c);
				grow(right->lo, right->hi, items[m].lo, items[m].hi);
			}
		}
		left->end = right->begin = i;
		rs_v4_store(left->clo, lclo);
		rs_v4_store(left->chi, lchi);
		rs_v4_store(right->clo, rclo);
		rs_v4_store(right->chi, rchi);
		return;
	}
	uint32_t n = t->end - t->begin;
	uint32_t chunks = s->pool && n >= PAR_BIN_MIN ? n / CHUNK : 1;
	chunks = chunks < s->max_chunks ? chunks : s->max_chunks;
	struct rs_bvh__part p;
	if (chunks < 2) {
		uint32_t l = t->begin, r = t->end;
		part_range(s, task_items(s, t), t->buf ? s->items : s->tmp, t->begin, t->end, &l,
		           &r, sc, sp, &p);
		left->buf = right->buf = !t->buf;
	} else {
		struct part_job job;
		memset(&job, 0, sizeof job);
		job = (struct part_job){.s = s, .t = t, .sc = sc, .sp = sp, .chunks = chunks};
		rs_bvh__pool_run(s->pool, chunks, part_chunk, &job);
		/* min, max and counts merge exactly, in any grouping. */
		p = s->chunk_part[0];
		for (uint32_t c = 1; c < chunks; c++) {
			const struct rs_bvh__part *o = &s->chunk_part[c];
			p.left += o->left;
			grow(p.lclo, p.lchi, o->lclo, o->lchi);
			grow(p.rclo, p.rchi, o->rclo, o->rchi);
		}
		child_tasks(t, sp, &p, left, right);
		struct rs_bvh__task *child[2] = {left, right};
		struct rs_bvh__prebin *slot[2] = {NULL, NULL};
		for (int k = 0; k < 2; k++) {
			uint32_t m = child[k]->end - child[k]->begin;
			if (m < PAR_BIN_MIN || m < s->prebin_min || m <= SMALL_NODE)
				continue;
			node_scale(s->nbins, child[k], &job.child_sc[k]);
			slot[k] = job.child_sc[k].axes ? free_slot(s, slot[0]) : NULL;
			job.bin_child[k] = slot[k] != NULL;
		}
		rs_bvh__pool_run(s->pool, chunks, move_chunk, &job);
		for (int k = 0; k < 2; k++)
			if (slot[k])
				keep_child_bins(s, child[k], (uint32_t)k, chunks, slot[k]);
		return;
	}
	child_tasks(t, sp, &p, left, right);
}

/* Which child comes first in the pre-order (the walk meets it first: for closest hit its
 * hits shrink tmax before the sibling's box is tested, for any hit it may end the walk):
 * the one with the smaller surface area. Of the orders measured (docs/bvh.md: lower side
 * of the plane, larger area, more or fewer triangles, smaller area) it gave the lowest hit
 * numbers on Box, Cow9 and Cow17. */
static int second_first(const struct rs_bvh__task *l, const struct rs_bvh__task *r)
{
	return rs_bvh__box_area(r->lo, r->hi) < rs_bvh__box_area(l->lo, l->hi);
}

void rs_bvh__build_subtree(const struct rs_bvh__sah *s, struct rs_bvh__scratch *w,
                           const struct rs_bvh__task *root, struct rs_bvh__emit *out)
{
	size_t top = 0;
	w->stack[top] = *root;
	w->stack[top++].parent = RS_BVH_NO_PARENT;
	while (top > 0) {
		struct rs_bvh__task t = w->stack[--top];
		uint32_t k = (uint32_t)out->count++;
		struct rs_bvh_node *node = &out->nodes[k];
		out->parent[k] = t.parent;
		node->first = 0;
		node->count = 0;
		/* Levels are set by rs_bvh__finalize(); until then a placeholder is told apart by
		 * its level alone (place_subtrees(), stitch()), so every other node must not hold a
		 * stale RS_BVH_DEFERRED from reused memory. */
		node->level = 0;
		if (t.end - t.begin <= out->defer) {
			node->level = RS_BVH_DEFERRED;
			node->first = (uint32_t)out->deferred_count;
			out->deferred[out->deferred_count++] = t;
			if (out->on_defer)
				out->on_defer(out->defer_ctx, node->first, k);
			continue;
		}
		struct node_scale sc;
		struct split sp;
		find_split(s, w, &t, &sc, &sp);
		if (sp.kind == SPLIT_LEAF) {
			/* A leaf's records end where the triangle order is read from. */
			if (t.buf)
				memcpy(s->items + t.begin, s->tmp + t.begin,
				       (t.end - t.begin) * sizeof *s->items);
			memcpy(node->lo, t.lo, sizeof node->lo);
			memcpy(node->hi, t.hi, sizeof node->hi);
			node->first = t.begin;
			node->count = t.end - t.begin;
			continue;
		}
		rs_bvh__box_empty(node->lo, node->hi);
		struct rs_bvh__task l, r;
		partition(s, &t, &sc, &sp, &l, &r);
		l.parent = r.parent = k;
		/* LIFO: push the second child first so the first child follows its parent. */
		if (second_first(&l, &r)) {
			w->stack[top++] = l;
			w->stack[top++] = r;
		} else {
			w->stack[top++] = r;
			w->stack[top++] = l;
		}
	}
}

/* Vertex v as four lanes (lane 3 zero). A four-wide load reads one float past the vertex,
 * so the last vertex of the array comes from a padded copy. */
static inline rs_v4 vertex(const float *positions, uint32_t v, size_t vertex_count,
                           const float last[4])
{
	return v + (size_t)1 < vertex_count ? rs_v4_load3(positions + 3 * (size_t)v)
	                                    : rs_v4_load(last);
}

/* x - x is 0 for every finite x, NaN for an infinity or a NaN. */
static inline int finite3(rs_v4 v)
{
	rs_v4 zero = rs_v4_set(0.0f, 0.0f, 0.0f, 0.0f);
	return (rs_v4_ge_mask(rs_v4_sub(v, v), zero) & rs_v4_ge_mask(zero, rs_v4_sub(v, v)) & 7) ==
	       7;
}

uint32_t rs_bvh__items_fill(struct rs_bvh__item *items, const float *positions, size_t vertex_count,
                            const uint32_t *indices, uint32_t begin, uint32_t end,
                            struct rs_bvh__task *bounds)
{
	float lo4[4], hi4[4];
	box_empty4(lo4, hi4);
	rs_v4_store(bounds->lo, rs_v4_load(lo4));
	rs_v4_store(bounds->hi, rs_v4_load(hi4));
	if (vertex_count == 0)
		return begin; /* every index is out of range */
	rs_v4 blo = rs_v4_load(lo4), bhi = rs_v4_load(hi4), clo = blo, chi = bhi;
	const float *p = positions + 3 * (vertex_count - 1);
	const float last[4] = {p[0], p[1], p[2], 0.0f};
	/* Adding +0 turns -0 into +0. Chunks merge in list order, where min and max of equal
	 * values keep the later one either way; without signed zeros they would not depend on
	 * the order at all. */
	const rs_v4 zero = rs_v4_set(0.0f, 0.0f, 0.0f, 0.0f);
	uint32_t t = begin;
	for (; t < end; t++) {
		const uint32_t *tri = indices + 3 * (size_t)t;
		if (tri[0] >= vertex_count || tri[1] >= vertex_count || tri[2] >= vertex_count)
			break;
		rs_v4 v0 = vertex(positions, tri[0], vertex_count, last);
		rs_v4 v1 = vertex(positions, tri[1], vertex_count, last);
		rs_v4 v2 = vertex(positions, tri[2], vertex_count, last);
		if (!finite3(v0) || !finite3(v1) || !finite3(v2))
			break;
		rs_v4 lo = rs_v4_add(rs_v4_min(rs_v4_min(v0, v1), v2), zero);
		rs_v4 hi = rs_v4_add(rs_v4_max(rs_v4_max(v0, v1), v2), zero);
		struct rs_bvh__item *it = &items[t];
		rs_v4_store(it->lo, lo);
		rs_v4_store(it->hi, hi);
		rs_bvh__item_set_id(it, t);
		rs_v4 c = rs_v4_centroid(lo, hi);
		blo = rs_v4_min(blo, lo);
		bhi = rs_v4_max(bhi, hi);
		clo = rs_v4_min(clo, c);
		chi = rs_v4_max(chi, c);
	}
	rs_v4_store(bounds->lo, blo);
	rs_v4_store(bounds->hi, bhi);
	rs_v4_store(bounds->clo, clo);
	rs_v4_store(bounds->chi, chi);
	return t;
}

int rs_bvh__wide_allowed = 1;

int rs_bvh__wide(void)
{
#ifdef RS_BVH_WIDE
	/* __builtin_cpu_supports() also checks that the OS saves the AVX registers. */
	return rs_bvh__wide_allowed && __builtin_cpu_supports("avx");
#else
	return 0;
#endif
}

int rs_bvh__scratch_init(struct rs_bvh__scratch *w, uint32_t nbins, size_t max_items)
{
	memset(w, 0, sizeof *w);
	w->binning.bins = aligned_alloc(
	    RS_BVH_LINE, rs_bvh__line_up(3 * (size_t)nbins * sizeof *w->binning.bins));
	w->binning.counts = aligned_alloc(
	    RS_BVH_LINE, rs_bvh__line_up(3 * (size_t)nbins * sizeof *w->binning.counts));
	/* Each pop pushes at most two tasks, so the stack never holds more than the depth
	 * plus one, and the depth is below the record count. */
	w->stack_cap = max_items + 1;
	w->stack = malloc(w->stack_cap * sizeof *w->stack);
	if (!w->binning.bins || !w->binning.counts || !w->stack) {
		rs_bvh__scratch_free(w);
		return 0;
	}
	return 1;
}

void rs_bvh__scratch_free(struct rs_bvh__scratch *w)
{
	free(w->binning.bins);
	free(w->binning.counts);
	free(w->stack);
	memset(w, 0, sizeof *w);
}
