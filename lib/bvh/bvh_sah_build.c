/* The SAH build on the threads it is given. One thread builds straight into the output.
 * With more, the nodes above subtrees of at most `defer` records are built first (their big
 * nodes binned in chunks on every thread), the subtrees are then built on the threads,
 * largest first, each into its own range of the output array, and one sweep moves them to
 * their places in the pre-order array. Each node is decided by bvh_sah.c from its records alone, so
 * the tree is the same for every thread count; only where its nodes were written differs. */
#include <stdlib.h>
#include <string.h>

#include "bvh_sah.h"

/* Below this many triangles one thread builds everything (starting threads costs more). */
#define PAR_MIN 8192u
/* Record setup chunk, and the most chunks a big node is binned in. */
#define FILL_CHUNK 16384u
#define MAX_CHUNKS 64u

struct by_size {
	uint32_t size, index;
};

struct build {
	struct rs_bvh__sah s;
	/* The same, without the pool: a subtree already runs on a worker, so it bins serially
	 * (the pool runs one loop at a time; the bins are the same either way). */
	struct rs_bvh__sah sub;
	struct rs_bvh__scratch *scratch; /* one per worker */
	uint32_t workers;
	const float *positions;
	size_t vertex_count;
	const uint32_t *indices;
	uint32_t n;
	/* Chunked record setup: bounds per chunk, and where each chunk stopped (its end, or
	 * its first bad triangle). */
	struct rs_bvh__task *fill_bounds;
	uint32_t *fill_stop;
	uint32_t fill_chunks;
	/* The nodes above the subtrees, the subtrees (by size, largest first), where subtree
	 * j was built (nodes[sub_at[j]...), parent links local) and its node count. */
	struct rs_bvh__emit top;
	uint32_t *map; /* top node -> output index */
	struct by_size *by_size;
	size_t *sub_at, *sub_count;
	struct rs_bvh_node *nodes;
	uint32_t *parent;
};

static uint32_t fill_edge(const struct build *b, uint32_t c)
{
	return (uint32_t)((uint64_t)b->n * c / b->fill_chunks);
}

static void fill_chunk(void *ctx, uint32_t c, uint32_t worker)
{
	(void)worker;
	struct build *b = ctx;
	b->fill_stop[c] =
	    rs_bvh__items_fill(b->s.items, b->positions, b->vertex_count, b->indices,
	                       fill_edge(b, c), fill_edge(b, c + 1), &b->fill_bounds[c]);
}

static void build_deferred(void *ctx, uint32_t job, uint32_t worker)
{
	struct build *b = ctx;
	uint32_t j = b->by_size[job].index;
	struct rs_bvh__emit e = {.nodes = b->nodes + b->sub_at[j],
	                         .parent = b->parent + b->sub_at[j]};
	rs_bvh__build_subtree(&b->sub, &b->scratch[worker], &b->top.deferred[j], &e);
	b->sub_count[j] = e.count;
}

/* Larger first; equal sizes in list order (qsort is not stable). */
static int larger_first(const void *pa, const void *pb)
{
	const struct by_size *a = pa, *b = pb;
	if (a->size != b->size)
		return a->size < b->size ? 1 : -1;
	return (a->index > b->index) - (a->index < b->index);
}

/* Where each subtree is built: the top tree's entries in pre-order, each top node given one
 * slot and subtree j room for its worst case, 2 m_j - 1 nodes. A full binary tree over D
 * subtrees has D - 1 top nodes, so the slots add up to exactly 2n - 1, the output's
 * capacity; and an entry's final place (actual counts before it) is never to the right of
 * its slot (worst cases before it). */
static void place_subtrees(struct build *b)
{
	size_t at = 0;
	for (size_t i = 0; i < b->top.count; i++) {
		const struct rs_bvh_node *node = &b->top.nodes[i];
		if (node->level != RS_BVH_DEFERRED) {
			at++;
			continue;
		}
		const struct rs_bvh__task *t = &b->top.deferred[node->first];
		b->sub_at[node->first] = at;
		at += 2 * (size_t)(t->end - t->begin) - 1;
	}
}

/* One sweep in pre-order: top nodes written, subtrees moved left to their final places
 * (never onto a slot still to be read: see place_subtrees()), parent links made global. */
static size_t stitch(struct build *b)
{
	const struct rs_bvh__emit *top = &b->top;
	size_t out = 0;
	for (size_t i = 0; i < top->count; i++) {
		b->map[i] = (uint32_t)out;
		uint32_t up =
		    top->parent[i] == RS_BVH_NO_PARENT ? RS_BVH_NO_PARENT : b->map[top->parent[i]];
		const struct rs_bvh_node *node = &top->nodes[i];
		if (node->level != RS_BVH_DEFERRED) {
			b->nodes[out] = *node;
			b->parent[out++] = up;
			continue;
		}
		size_t from = b->sub_at[node->first], count = b->sub_count[node->first];
		memmove(b->nodes + out, b->nodes + from, count * sizeof *b->nodes);
		/* Forward, reading at or after where it writes (out <= from). */
		for (size_t k = 0; k < count; k++) {
			uint32_t p = b->parent[from + k];
			b->parent[out + k] = p == RS_BVH_NO_PARENT ? up : p + (uint32_t)out;
		}
		out += count;
	}
	return out;
}

static size_t build_parallel(struct build *b, struct rs_bvh__task *root)
{
	rs_bvh__build_subtree(&b->s, &b->scratch[0], root, &b->top);
	size_t subs = b->top.deferred_count;
	for (size_t j = 0; j < subs; j++) {
		const struct rs_bvh__task *t = &b->top.deferred[j];
		b->by_size[j] = (struct by_size){t->end - t->begin, (uint32_t)j};
	}
	qsort(b->by_size, subs, sizeof *b->by_size, larger_first);
	place_subtrees(b);
	rs_bvh__pool_run(b->s.pool, (uint32_t)subs, build_deferred, b);
	return stitch(b);
}

static void free_build(struct build *b)
{
	for (uint32_t w = 0; b->scratch && w < b->workers; w++)
		rs_bvh__scratch_free(&b->scratch[w]);
	free(b->scratch);
	rs_bvh__pool_stop(b->s.pool);
	if (b->s.chunk_bins) {
		free(b->s.chunk_bins[0].bins);
		free(b->s.chunk_bins[0].counts);
	}
	free(b->s.chunk_bins);
	free(b->s.items);
	free(b->s.tmp);
	free(b->s.chunk_part);
	free(b->fill_bounds);
	free(b->fill_stop);
	free(b->top.nodes);
	free(b->top.parent);
	free(b->top.deferred);
	free(b->map);
	free(b->by_size);
	free(b->sub_at);
	free(b->sub_count);
	free(b->parent);
}

/* Everything the threaded build needs beyond the records and worker 0's scratch. */
static int alloc_parallel(struct build *b, uint32_t nbins)
{
	size_t n = b->n, cap = 2 * n;
	b->s.max_chunks = MAX_CHUNKS;
	b->s.chunk_bins = calloc(MAX_CHUNKS, sizeof *b->s.chunk_bins);
	b->s.chunk_part = malloc(MAX_CHUNKS * sizeof *b->s.chunk_part);
	struct rs_bvh__bin *bins = malloc((size_t)MAX_CHUNKS * 3 * nbins * sizeof *bins);
	uint32_t *counts = malloc((size_t)MAX_CHUNKS * 3 * nbins * sizeof *counts);
	if (!b->s.chunk_bins || !b->s.chunk_part || !bins || !counts) {
		free(bins);
		free(counts);
		return 0;
	}
	for (uint32_t c = 0; c < MAX_CHUNKS; c++) {
		b->s.chunk_bins[c].bins = bins + (size_t)c * 3 * nbins;
		b->s.chunk_bins[c].counts = counts + (size_t)c * 3 * nbins;
	}
	/* Sized for the worst case; pages are only touched as far as they are used. */
	b->top.nodes = malloc(cap * sizeof *b->top.nodes);
	b->top.parent = malloc(cap * sizeof *b->top.parent);
	b->top.deferred = malloc(n * sizeof *b->top.deferred);
	b->map = malloc(cap * sizeof *b->map);
	b->by_size = malloc(n * sizeof *b->by_size);
	b->sub_at = malloc(n * sizeof *b->sub_at);
	b->sub_count = malloc(n * sizeof *b->sub_count);
	return b->top.nodes && b->top.parent && b->top.deferred && b->map && b->by_size &&
	       b->sub_at && b->sub_count;
}

enum rs_status rs_bvh__build_sah(const struct rs_bvh_desc *desc, const float *positions,
                                 size_t vertex_count, const uint32_t *indices,
                                 size_t triangle_count, struct rs_bvh_node *nodes, uint32_t *order,
                                 size_t *out_count, struct rs_error *err)
{
	struct build b = {.positions = positions,
	                  .vertex_count = vertex_count,
	                  .indices = indices,
	                  .n = (uint32_t)triangle_count,
	                  .nodes = nodes};
	b.s.nbins = desc->sah_bins;
	b.s.leaf_size = desc->leaf_size;
	b.s.ct = desc->traversal_cost;
	uint32_t threads = triangle_count >= PAR_MIN ? desc->threads : 1;
	int ok = 1;
	if (threads > 1) {
		b.s.pool = rs_bvh__pool_start(threads);
		ok = b.s.pool != NULL;
	}
	b.workers = rs_bvh__pool_workers(b.s.pool);
	/* Subtrees of at most `defer` records: at least four per worker, so the largest-first
	 * order keeps every worker busy to the end, while the upper nodes (whose partition
	 * is serial) stay few. Measured on Cow17, two threads (callgrind, per thread): n / 16
	 * left the caller 158 M instructions against the helper's 124 M, n / 8 141 M against
	 * 141 M. */
	uint32_t defer = b.workers > 1 ? b.n / (4 * b.workers) : 0;
	b.s.items = malloc(triangle_count * sizeof *b.s.items);
	b.s.tmp = malloc(triangle_count * sizeof *b.s.tmp);
	b.parent = malloc((2 * triangle_count - 1) * sizeof *b.parent);
	b.scratch = calloc(b.workers, sizeof *b.scratch);
	b.fill_chunks = (b.n + FILL_CHUNK - 1) / FILL_CHUNK;
	b.fill_bounds = malloc(b.fill_chunks * sizeof *b.fill_bounds);
	b.fill_stop = malloc(b.fill_chunks * sizeof *b.fill_stop);
	ok = ok && b.s.items && b.s.tmp && b.parent && b.scratch && b.fill_bounds && b.fill_stop;
	for (uint32_t w = 0; ok && w < b.workers; w++)
		ok = rs_bvh__scratch_init(&b.scratch[w], b.s.nbins, w == 0 ? b.n : defer);
	if (ok && b.workers > 1)
		ok = alloc_parallel(&b, b.s.nbins);
	if (!ok) {
		free_build(&b);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory (%zu triangles)",
		                    triangle_count);
	}
	rs_bvh__pool_run(b.s.pool, b.fill_chunks, fill_chunk, &b);
	for (uint32_t c = 0; c < b.fill_chunks; c++) {
		if (b.fill_stop[c] != fill_edge(&b, c + 1)) {
			enum rs_status s = rs_bvh__check_triangle(positions, vertex_count, indices,
			                                          b.fill_stop[c], err);
			free_build(&b);
			return s;
		}
	}
	/* Chunk bounds merge exactly (min and max), in any order. */
	struct rs_bvh__task root = b.fill_bounds[0];
	for (uint32_t c = 1; c < b.fill_chunks; c++) {
		const struct rs_bvh__task *f = &b.fill_bounds[c];
		for (int a = 0; a < 3; a++) {
			root.lo[a] = f->lo[a] < root.lo[a] ? f->lo[a] : root.lo[a];
			root.hi[a] = f->hi[a] > root.hi[a] ? f->hi[a] : root.hi[a];
			root.clo[a] = f->clo[a] < root.clo[a] ? f->clo[a] : root.clo[a];
			root.chi[a] = f->chi[a] > root.chi[a] ? f->chi[a] : root.chi[a];
		}
	}
	root.begin = 0;
	root.end = b.n;
	root.buf = 0;
	size_t count;
	if (b.workers > 1) {
		b.top.defer = defer;
		b.sub = b.s;
		b.sub.pool = NULL;
		count = build_parallel(&b, &root);
	} else {
		struct rs_bvh__emit e = {.nodes = nodes, .parent = b.parent};
		rs_bvh__build_subtree(&b.s, &b.scratch[0], &root, &e);
		count = e.count;
	}
	enum rs_status status = RS_OK;
	if (!rs_bvh__finalize(nodes, count, b.parent)) {
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
	} else {
		/* Leaves own contiguous record ranges; when the right child is emitted first
		 * the ranges are no longer increasing in pre-order, which the layout allows. */
		for (size_t t = 0; t < triangle_count; t++)
			order[t] = rs_bvh__item_id(&b.s.items[t]);
		*out_count = count;
	}
	free_build(&b);
	return status;
}
