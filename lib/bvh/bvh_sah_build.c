/* The SAH build on the threads it is given. One thread builds straight into the output.
 * With more, the caller's thread builds the nodes above subtrees of at most `defer` records
 * (their big nodes binned in chunks on every thread); each subtree is handed out as soon as
 * it is emitted and built by a helper between those chunk loops, or by any thread once the
 * upper nodes are done (the largest waiting first), each into its own range of the output
 * array; a thread with no subtree left moves the finished ones to their places in the
 * pre-order array, in order, while the last are built. Each node is decided by bvh_sah.c
 * from its records alone, so the tree is the same for every thread count; only where its
 * nodes were written meanwhile differs. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_sah.h"

/* Below this many triangles one thread builds everything (starting threads costs more). */
#define PAR_MIN 8192u
/* Record setup chunk, and the most chunks a big node is binned in. */
#define FILL_CHUNK 16384u
#define MAX_CHUNKS 64u
/* Children binned ahead that may wait at once (pending upper nodes; beyond, a child is
 * binned when its turn comes). */
#define MAX_PREBINS 64u

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
	/* The nodes above the subtrees, where subtree j was built (nodes[sub_at[j]...),
	 * parent links local) and its node count. */
	struct rs_bvh__emit top;
	uint32_t *span; /* top entry -> the number of top entries in its subtree */
	size_t *sub_at, *sub_count;
	/* End of the last subtree's slot, and the top nodes emitted before it (place_subtree()). */
	size_t slots, slots_tops;
	/* Subtrees emitted and not yet taken (indices into top.deferred), under lock; done
	 * is signalled when the last one posted is finished. */
	pthread_mutex_t lock;
	pthread_cond_t done;
	uint32_t *waiting;
	uint32_t waiting_count, posted;
	/* Also read without the lock, by the caller's thread polling for the end. */
	atomic_uint finished;
	/* The stitch (stitch_some()), in pre-order as far as the subtrees are done: the next
	 * top entry, the next place in the output, how many top nodes are open (ancestors of
	 * the next entry, kept in top.parent, free once span is known) and how many levels of
	 * rank[] are zeroed. Under lock: ready (the upper tree is complete), stitching (one
	 * thread at it) and each subtree's done flag. */
	size_t st_next, st_out, st_open, rank_zeroed;
	uint8_t *sub_done;
	int ready;
	atomic_int stitching;
	/* Subtree j's node count per level, levels[sub_at[j] ...] (its slot has room: a tree
	 * over m records is at most m - 1 levels high), sub_levels[j] of them; then, in the
	 * stitch, the nodes on each level before it in the pre-order. */
	uint32_t *levels, *sub_levels, *rank;
	struct rs_bvh_node *nodes;
	uint32_t *parent;
	uint32_t *order;
	char *block; /* every array above, in one allocation (layout()) */
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

/* The triangle order of records [begin, end), read from their final places. */
static void order_range(struct build *b, uint32_t begin, uint32_t end)
{
	for (uint32_t t = begin; t < end; t++)
		b->order[t] = rs_bvh__item_id(&b->s.items[t]);
}

/* The same in chunks of FILL_CHUNK (one thread). */
static void order_chunk(void *ctx, uint32_t c, uint32_t worker)
{
	(void)worker;
	struct build *b = ctx;
	order_range(b, fill_edge(b, c), fill_edge(b, c + 1));
}

static void build_deferred(struct build *b, uint32_t j, uint32_t worker)
{
	struct rs_bvh__emit e = {.nodes = b->nodes + b->sub_at[j],
	                         .parent = b->parent + b->sub_at[j]};
	rs_bvh__build_subtree(&b->sub, &b->scratch[worker], &b->top.deferred[j], &e);
	b->sub_count[j] = e.count;
	/* Finished here, on this thread, as far as the subtree alone decides: boxes, levels,
	 * escapes and ranks within it; the stitch adds where it lands. */
	uint32_t top = rs_bvh__finalize_up(e.nodes, e.count, e.parent);
	uint32_t *rank = b->levels + b->sub_at[j];
	memset(rank, 0, ((size_t)top + 1) * sizeof *rank);
	rs_bvh__finalize_rank(e.nodes, e.count, rank);
	b->sub_levels[j] = top + 1;
	/* Its leaves' records are where they end (still in cache): their triangle order. */
	order_range(b, b->top.deferred[j].begin, b->top.deferred[j].end);
}

static void rank_zero(struct build *b, uint32_t level)
{
	if (level >= b->rank_zeroed) {
		memset(b->rank + b->rank_zeroed, 0, (level + 1 - b->rank_zeroed) * sizeof *b->rank);
		b->rank_zeroed = (size_t)level + 1;
	}
}

/* The stitch: the upper tree's entries in pre-order, each written to its final place (the
 * places so far plus one), a subtree moved left from its slot (never onto a slot still to
 * be read or written: see place_subtree()) with its escapes and ranks offset by what
 * precedes it, an upper node written when the last entry of its subtree is (its level and
 * box from its children, as rs_bvh__finalize_up() would; its rank is the count of nodes on
 * its level before it, and only its descendants, all lower, came since its place). It
 * goes as far as the subtrees are done (all: every one is), so a thread that has no
 * subtree left to build stitches while the last ones are built. One thread at a time. */
static void stitch_some(struct build *b, int all)
{
	struct rs_bvh__emit *top = &b->top;
	while (b->st_next < top->count) {
		size_t i = b->st_next;
		struct rs_bvh_node *node = &top->nodes[i];
		const struct rs_bvh_node *done;
		if (node->level == RS_BVH_DEFERRED) {
			uint32_t j = node->first;
			if (!all) {
				pthread_mutex_lock(&b->lock);
				int ready = b->sub_done[j];
				pthread_mutex_unlock(&b->lock);
				if (!ready)
					return;
			}
			size_t from = b->sub_at[j], count = b->sub_count[j], out = b->st_out;
			const uint32_t *levels = b->levels + from;
			rank_zero(b, b->sub_levels[j] - 1);
			memmove(b->nodes + out, b->nodes + from, count * sizeof *b->nodes);
			for (size_t k = 0; k < count; k++) {
				struct rs_bvh_node *n = &b->nodes[out + k];
				n->escape += (uint32_t)out;
				n->order += b->rank[n->level];
			}
			for (uint32_t l = 0; l < b->sub_levels[j]; l++)
				b->rank[l] += levels[l];
			done = &b->nodes[out];
			b->st_out += count;
		} else if (node->count > 0) {
			/* A leaf of the upper tree (leaf_size above defer). */
			rank_zero(b, 0);
			node->level = 0;
			node->escape = (uint32_t)b->st_out + 1;
			node->order = b->rank[0]++;
			b->nodes[b->st_out++] = *node;
			done = node;
		} else {
			/* Open until its last entry is written: its place in escape meanwhile, its
			 * level (0 from the upper build) grown by its children. */
			top->parent[b->st_open++] = (uint32_t)i;
			node->escape = (uint32_t)b->st_out++;
			b->st_next++;
			continue;
		}
		b->st_next++;
		/* Into its parent; a parent whose last entry this was is finished in turn. */
		while (b->st_open > 0) {
			uint32_t e = top->parent[b->st_open - 1];
			struct rs_bvh_node *p = &top->nodes[e];
			p->level = done->level + 1 > p->level ? done->level + 1 : p->level;
			for (int a = 0; a < 3; a++) {
				p->lo[a] = done->lo[a] < p->lo[a] ? done->lo[a] : p->lo[a];
				p->hi[a] = done->hi[a] > p->hi[a] ? done->hi[a] : p->hi[a];
			}
			if (e + b->span[e] != b->st_next)
				break;
			rank_zero(b, p->level);
			uint32_t out = p->escape;
			p->escape = (uint32_t)b->st_out;
			p->order = b->rank[p->level]++;
			b->nodes[out] = *p;
			done = p;
			b->st_open--;
		}
	}
}

/* The stitch as far as it goes now, unless another thread is at it or the upper tree is
 * not complete yet. */
static void try_stitch(struct build *b)
{
	pthread_mutex_lock(&b->lock);
	if (!b->ready || b->stitching) {
		pthread_mutex_unlock(&b->lock);
		return;
	}
	b->stitching = 1;
	pthread_mutex_unlock(&b->lock);
	stitch_some(b, 0);
	pthread_mutex_lock(&b->lock);
	b->stitching = 0;
	pthread_cond_broadcast(&b->done);
	pthread_mutex_unlock(&b->lock);
}

/* One waiting subtree built on this thread, the largest (equal sizes: the first emitted);
 * 0 when none waits. The pool's idle work on the helpers. */
static int take_subtree(void *ctx, uint32_t worker)
{
	struct build *b = ctx;
	pthread_mutex_lock(&b->lock);
	if (b->waiting_count == 0) {
		pthread_mutex_unlock(&b->lock);
		try_stitch(b);
		return 0;
	}
	uint32_t best = 0;
	for (uint32_t i = 1; i < b->waiting_count; i++) {
		const struct rs_bvh__task *t = &b->top.deferred[b->waiting[i]];
		const struct rs_bvh__task *o = &b->top.deferred[b->waiting[best]];
		uint32_t m = t->end - t->begin, mo = o->end - o->begin;
		if (m > mo || (m == mo && b->waiting[i] < b->waiting[best]))
			best = i;
	}
	uint32_t j = b->waiting[best];
	b->waiting[best] = b->waiting[--b->waiting_count];
	pthread_mutex_unlock(&b->lock);
	build_deferred(b, j, worker);
	pthread_mutex_lock(&b->lock);
	b->sub_done[j] = 1;
	if (++b->finished == b->posted)
		pthread_cond_broadcast(&b->done);
	pthread_mutex_unlock(&b->lock);
	return 1;
}

/* Where subtree j, emitted as top entry k, is built; then it is handed to the helpers.
 * The top tree's entries in pre-order (the order they are emitted in), each top node given
 * one slot and subtree j room for its worst case, 2 m_j - 1 nodes. A full binary tree over
 * D subtrees has D - 1 top nodes, so the slots add up to exactly 2n - 1, the output's
 * capacity; and an entry's final place (actual counts before it) is never to the right of
 * its slot (worst cases before it). */
static void place_subtree(void *ctx, uint32_t j, size_t k)
{
	struct build *b = ctx;
	const struct rs_bvh__task *t = &b->top.deferred[j];
	/* Before entry k: k - j top nodes and subtrees 0 .. j - 1. */
	size_t at = b->slots + (k - j - b->slots_tops);
	b->sub_at[j] = at;
	b->slots = at + 2 * (size_t)(t->end - t->begin) - 1;
	b->slots_tops = k - j;
	pthread_mutex_lock(&b->lock);
	b->sub_done[j] = 0;
	b->waiting[b->waiting_count++] = j;
	b->posted++;
	pthread_mutex_unlock(&b->lock);
	rs_bvh__pool_poke(b->s.pool);
}

static size_t build_parallel(struct build *b, struct rs_bvh__task *root)
{
	b->top.on_defer = place_subtree;
	b->top.defer_ctx = b;
	rs_bvh__pool_idle(b->s.pool, take_subtree, b);
	rs_bvh__build_subtree(&b->s, &b->scratch[0], root, &b->top);
	/* The upper tree's own leaves (only when leaf_size exceeds defer); every other record
	 * is in a subtree, which reads its own triangle order. */
	for (size_t i = 0; i < b->top.count; i++) {
		const struct rs_bvh_node *node = &b->top.nodes[i];
		if (node->level != RS_BVH_DEFERRED && node->count > 0)
			order_range(b, node->first, node->first + node->count);
	}
	/* The upper tree is complete: the stitch may start (top.parent is free after this:
	 * the stitch keeps its open nodes there). */
	const struct rs_bvh__emit *top = &b->top;
	for (size_t i = 0; i < top->count; i++)
		b->span[i] = 1;
	for (size_t i = top->count; i-- > 0;)
		if (top->parent[i] != RS_BVH_NO_PARENT)
			b->span[top->parent[i]] += b->span[i];
	pthread_mutex_lock(&b->lock);
	b->ready = 1;
	pthread_mutex_unlock(&b->lock);
	/* Every subtree is posted now: the rest are built here and on the helpers, and
	 * whoever finds none left stitches meanwhile. */
	while (take_subtree(b, 0))
		;
	/* The last subtrees and the stitch: polled for a while (the pool's polls), as a wait
	 * of a few tens of microseconds is common here and waking a sleeping thread costs
	 * about as much; then slept on. */
	for (uint32_t k = 0;
	     k < rs_bvh__pool_polls(b->s.pool) &&
	     (atomic_load_explicit(&b->finished, memory_order_relaxed) < b->posted ||
	      atomic_load_explicit(&b->stitching, memory_order_relaxed));
	     k++)
		rs_bvh__pool_relax();
	pthread_mutex_lock(&b->lock);
	while (b->finished < b->posted || b->stitching)
		pthread_cond_wait(&b->done, &b->lock);
	pthread_mutex_unlock(&b->lock);
	rs_bvh__pool_idle(b->s.pool, NULL, NULL);
	stitch_some(b, 1);
	return b->st_out;
}

static void free_build(struct build *b)
{
	for (uint32_t w = 0; b->scratch && w < b->workers; w++)
		rs_bvh__scratch_free(&b->scratch[w]);
	rs_bvh__pool_stop(b->s.pool);
	free(b->block);
}

/* `bytes` more of the block, on cache lines of their own (rs_bvh__line_up()); NULL while
 * only the size is being found (block NULL). */
static void *take(char *block, size_t *at, size_t bytes)
{
	size_t from = *at;
	*at += rs_bvh__line_up(bytes);
	return block ? block + from : NULL;
}

/* Every array of the build in one block (pass NULL to get its size, then the block). One
 * allocation instead of twenty: freed separately, the threaded build's arrays (~30 MB for
 * Cow17, mostly the worst-case sizes of the upper tree's, barely touched) left glibc's
 * heap top above its trim threshold, so every build gave the heap back to the kernel and
 * the next one faulted its records in again (0.7-1 ms of a 13 ms two-thread build). One
 * block's size sets the trim threshold above itself. */
static size_t layout(struct build *b, char *block)
{
	size_t at = 0, n = b->n, cap = 2 * n;
	b->block = block;
	b->s.items = take(block, &at, n * sizeof *b->s.items);
	b->s.tmp = take(block, &at, n * sizeof *b->s.tmp);
	b->parent = take(block, &at, (2 * n - 1) * sizeof *b->parent);
	b->scratch = take(block, &at, b->workers * sizeof *b->scratch);
	b->fill_bounds = take(block, &at, b->fill_chunks * sizeof *b->fill_bounds);
	b->fill_stop = take(block, &at, b->fill_chunks * sizeof *b->fill_stop);
	if (b->workers < 2)
		return at;
	/* Each chunk's results on cache lines of their own. */
	uint32_t nb = b->s.nbins;
	size_t bin_stride = rs_bvh__line_up(3 * (size_t)nb * sizeof(struct rs_bvh__bin)) /
	                    sizeof(struct rs_bvh__bin);
	size_t count_stride = rs_bvh__line_up(3 * (size_t)nb * sizeof(uint32_t)) / sizeof(uint32_t);
	b->s.max_chunks = MAX_CHUNKS;
	b->s.chunk_bins = take(block, &at, MAX_CHUNKS * sizeof *b->s.chunk_bins);
	b->s.chunk_part = take(block, &at, MAX_CHUNKS * sizeof *b->s.chunk_part);
	struct rs_bvh__bin *bins =
	    take(block, &at, MAX_CHUNKS * bin_stride * sizeof(struct rs_bvh__bin));
	uint32_t *counts = take(block, &at, MAX_CHUNKS * count_stride * sizeof(uint32_t));
	for (uint32_t c = 0; block && c < MAX_CHUNKS; c++) {
		b->s.chunk_bins[c].bins = bins + c * bin_stride;
		b->s.chunk_bins[c].counts = counts + c * count_stride;
	}
	/* Both children of each chunk, and the slots the merged bins wait in. */
	b->s.child_bins = take(block, &at, 2 * MAX_CHUNKS * sizeof *b->s.child_bins);
	bins = take(block, &at, 2 * MAX_CHUNKS * bin_stride * sizeof(struct rs_bvh__bin));
	counts = take(block, &at, 2 * MAX_CHUNKS * count_stride * sizeof(uint32_t));
	for (uint32_t c = 0; block && c < 2 * MAX_CHUNKS; c++) {
		b->s.child_bins[c].bins = bins + c * bin_stride;
		b->s.child_bins[c].counts = counts + c * count_stride;
	}
	b->s.prebins = MAX_PREBINS;
	b->s.prebin = take(block, &at, MAX_PREBINS * sizeof *b->s.prebin);
	bins = take(block, &at, MAX_PREBINS * bin_stride * sizeof(struct rs_bvh__bin));
	counts = take(block, &at, MAX_PREBINS * count_stride * sizeof(uint32_t));
	for (uint32_t i = 0; block && i < MAX_PREBINS; i++) {
		b->s.prebin[i].b.bins = bins + i * bin_stride;
		b->s.prebin[i].b.counts = counts + i * count_stride;
		b->s.prebin[i].used = 0;
	}
	/* Sized for the worst case; pages are only touched as far as they are used. */
	b->top.nodes = take(block, &at, cap * sizeof *b->top.nodes);
	b->top.parent = take(block, &at, cap * sizeof *b->top.parent);
	b->top.deferred = take(block, &at, n * sizeof *b->top.deferred);
	b->span = take(block, &at, cap * sizeof *b->span);
	b->sub_done = take(block, &at, n * sizeof *b->sub_done);
	b->levels = take(block, &at, cap * sizeof *b->levels);
	b->sub_levels = take(block, &at, n * sizeof *b->sub_levels);
	b->rank = take(block, &at, (n + 1) * sizeof *b->rank);
	b->waiting = take(block, &at, n * sizeof *b->waiting);
	b->sub_at = take(block, &at, n * sizeof *b->sub_at);
	b->sub_count = take(block, &at, n * sizeof *b->sub_count);
	return at;
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
	                  .nodes = nodes,
	                  .order = order};
	b.s.nbins = desc->sah_bins;
	b.s.leaf_size = desc->leaf_size;
	b.s.ct = desc->traversal_cost;
	b.s.wide = rs_bvh__wide();
	uint32_t threads = triangle_count >= PAR_MIN ? desc->threads : 1;
	int ok = 1;
	if (threads > 1) {
		b.s.pool = rs_bvh__pool_start(threads);
		ok = b.s.pool != NULL;
	}
	b.workers = rs_bvh__pool_workers(b.s.pool);
	/* Subtrees of at most `defer` records: at least eight per worker, so taking the
	 * largest waiting first keeps every worker busy to the end, while the upper nodes (binned
	 * and partitioned in chunks on every thread) stay few. Measured on Cow17, two threads,
	 * against Embree alternately (docs/benchmarks.md): n / 8 threads 1.00-1.02x Embree's
	 * time, n / 4 1.02-1.03x, n / 2 1.09-1.11x. (Before the upper nodes were partitioned on
	 * the threads, callgrind per thread put n / 16 at 158 M instructions on the caller
	 * against 124 M on the helper, n / 8 at 141 M on each.) */
	uint32_t defer = b.workers > 1 ? b.n / (8 * b.workers) : 0;
	b.s.prebin_min = defer + 1;
	b.fill_chunks = (b.n + FILL_CHUNK - 1) / FILL_CHUNK;
	char *block = ok ? aligned_alloc(RS_BVH_LINE, layout(&b, NULL)) : NULL;
	ok = block != NULL;
	if (ok) {
		layout(&b, block);
		/* Zeroed: a scratch not yet made is freed as empty. */
		memset(b.scratch, 0, b.workers * sizeof *b.scratch);
	}
	for (uint32_t w = 0; ok && w < b.workers; w++)
		ok = rs_bvh__scratch_init(&b.scratch[w], b.s.nbins, w == 0 ? b.n : defer);
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
	int finished = 1;
	if (b.workers > 1) {
		/* The subtrees finish themselves on their threads, the stitch the rest. */
		b.top.defer = defer;
		b.sub = b.s;
		b.sub.pool = NULL;
		b.sub.prebins = 0; /* no subtree root is binned ahead (prebin_min) */
		pthread_mutex_init(&b.lock, NULL);
		pthread_cond_init(&b.done, NULL);
		count = build_parallel(&b, &root);
		pthread_cond_destroy(&b.done);
		pthread_mutex_destroy(&b.lock);
	} else {
		struct rs_bvh__emit e = {.nodes = nodes, .parent = b.parent};
		rs_bvh__build_subtree(&b.s, &b.scratch[0], &root, &e);
		count = e.count;
		finished = rs_bvh__finalize(nodes, count, b.parent);
	}
	enum rs_status status = RS_OK;
	if (!finished) {
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "bvh: out of memory");
	} else {
		/* Leaves own contiguous record ranges; when the right child is emitted first
		 * the ranges are no longer increasing in pre-order, which the layout allows.
		 * Threads read the order as each subtree is done (build_deferred()). */
		if (b.workers < 2)
			rs_bvh__pool_run(b.s.pool, b.fill_chunks, order_chunk, &b);
		*out_count = count;
	}
	free_build(&b);
	return status;
}
