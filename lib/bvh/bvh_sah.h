/* Private to the SAH builder: the triangle records, the per-node split search and the
 * serial subtree build (bvh_sah.c), shared with the driver that runs subtrees on threads
 * and stitches them into one pre-order array (bvh_sah_build.c). */
#ifndef RS_BVH_SAH_H
#define RS_BVH_SAH_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "bvh_internal.h"

/* A triangle record, 32 bytes: its box, four floats a side for bvh_v4.h, and the input id
 * in the two lanes 3 (the centroid is recomputed where needed, the same bits every time).
 * Records are moved, not indexed, so every pass reads memory in order.
 *
 * The id's low 23 and high 8 bits are the mantissas of two floats in [1, 2): the lanes 3
 * go through the same multiplies as the coordinates, and a denormal there (an id's plain
 * bits) costs a microcode assist per operation (measured: 1.6x the build time). */
struct rs_bvh__item {
	float lo[4], hi[4];
};

#define RS_BVH_ID_ONE 0x3f800000u /* 1.0f */
#define RS_BVH_ID_LOW 0x7fffffu

static inline void rs_bvh__item_set_id(struct rs_bvh__item *it, uint32_t id)
{
	uint32_t low = RS_BVH_ID_ONE | (id & RS_BVH_ID_LOW), high = RS_BVH_ID_ONE | (id >> 23);
	memcpy(&it->lo[3], &low, sizeof low);
	memcpy(&it->hi[3], &high, sizeof high);
}

static inline uint32_t rs_bvh__item_id(const struct rs_bvh__item *it)
{
	uint32_t low, high;
	memcpy(&low, &it->lo[3], sizeof low);
	memcpy(&high, &it->hi[3], sizeof high);
	return (low & RS_BVH_ID_LOW) | (high & 0xffu) << 23;
}

/* A node still to build: records [begin, end), their bounds and their centroids' bounds
 * (lane 3 unused). */
struct rs_bvh__task {
	uint32_t begin, end, parent;
	uint32_t buf; /* where its records are: 0 items, 1 tmp (the partition moves them) */
	float lo[4], hi[4];
	float clo[4], chi[4];
};

/* One bin of one axis (its count is kept apart). */
struct rs_bvh__bin {
	float lo[4], hi[4];
};

/* What one pass over a node's records gathers: 3 * nbins bins and counts, and the two
 * sides of the size split (large triangles, the rest). */
/* Bytes rounded up to whole cache lines. What one thread writes while another works (its
 * bins, a chunk's results) sits on lines of its own: two threads writing one line make it
 * move between their cores at every write (on Cow17 this cost the two-thread build's
 * subtrees about a tenth of their time). */
#define RS_BVH_LINE 64
static inline size_t rs_bvh__line_up(size_t bytes)
{
	return (bytes + RS_BVH_LINE - 1) & ~(size_t)(RS_BVH_LINE - 1);
}

struct rs_bvh__binning {
	_Alignas(RS_BVH_LINE) struct rs_bvh__bin *bins;
	uint32_t *counts;
	float blo[4], bhi[4], slo[4], shi[4];
	uint32_t large;
};

/* What one chunk of a big node's partition found: its records going left and right and
 * their centroid bounds. */
struct rs_bvh__part {
	_Alignas(RS_BVH_LINE) uint32_t left, right;
	float lclo[4], lchi[4], rclo[4], rchi[4];
};

/* Shared, read-only while subtrees are built (apart from disjoint record ranges). */
struct rs_bvh__sah {
	/* Records, in two buffers of the same size: a node's partition reads its range of one
	 * and writes the children's into the same range of the other (buf[task.buf]); a leaf's
	 * records end in buf[0] (items). */
	struct rs_bvh__item *items, *tmp;
	uint32_t nbins, leaf_size;
	double ct;
	/* Plane costs four at a time with AVX (rs_bvh__wide()); the same bits either way. */
	int wide;
	/* Parallel binning of the nodes above the subtrees (NULL: serial): chunk c of a big
	 * node bins into chunk_bins[c]. */
	struct rs_bvh__pool *pool;
	struct rs_bvh__binning *chunk_bins;
	struct rs_bvh__part *chunk_part;
	uint32_t max_chunks;
	/* Children of a chunked partition with at least prebin_min records are binned while
	 * their records are copied into place (chunk c's left and right blocks into
	 * child_bins[2c] and [2c + 1]), merged into a free prebin slot, and find_split() takes
	 * the slot instead of binning them again. The bins are the same (min, max and counts
	 * merge exactly in any grouping). */
	struct rs_bvh__binning *child_bins;
	struct rs_bvh__prebin *prebin;
	uint32_t prebins, prebin_min;
};

struct rs_bvh__prebin {
	struct rs_bvh__binning b;
	uint32_t begin, end;
	int used;
};

/* One thread's scratch: the bins of the node at hand and the task stack. */
struct rs_bvh__scratch {
	struct rs_bvh__binning binning;
	struct rs_bvh__task *stack;
	size_t stack_cap;
};

/* Placeholder node of a subtree left for later: level = DEFERRED, first = its index in the
 * deferred list. */
#define RS_BVH_DEFERRED UINT32_MAX

/* A subtree's output: nodes and parent links (local indices), and deferred subtrees. */
struct rs_bvh__emit {
	struct rs_bvh_node *nodes;
	uint32_t *parent;
	size_t count;
	/* Tasks of at most `defer` records become placeholders (0: build everything). */
	uint32_t defer;
	struct rs_bvh__task *deferred;
	size_t deferred_count;
	/* Called (when set) as each placeholder is emitted: deferred[j] at node k. */
	void (*on_defer)(void *ctx, uint32_t j, size_t k);
	void *defer_ctx;
};

/* Whether this CPU runs the AVX plane costs (and rs_bvh__wide_allowed is set: a test clears
 * it to build the same trees without them and compare). */
extern int rs_bvh__wide_allowed;
int rs_bvh__wide(void);

int rs_bvh__scratch_init(struct rs_bvh__scratch *s, uint32_t nbins, size_t max_items);
void rs_bvh__scratch_free(struct rs_bvh__scratch *s);

/* Records, bounds and centroid bounds of triangles [begin, end), checking each triangle on
 * the way: returns the first one with a vertex out of range or not finite (and stops
 * there), or end. */
uint32_t rs_bvh__items_fill(struct rs_bvh__item *items, const float *positions, size_t vertex_count,
                            const uint32_t *indices, uint32_t begin, uint32_t end,
                            struct rs_bvh__task *bounds);

/* Build the subtree of `root` in pre-order into out (root's parent: RS_BVH_NO_PARENT). */
void rs_bvh__build_subtree(const struct rs_bvh__sah *s, struct rs_bvh__scratch *w,
                           const struct rs_bvh__task *root, struct rs_bvh__emit *out);

#endif
