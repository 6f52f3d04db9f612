/* Private helpers shared by the BVH builders: leaf bounds and the pass that turns a
 * pre-order node list with parent links into the threaded layout (escape, level, order,
 * interior bounds). */
#ifndef RS_BVH_INTERNAL_H
#define RS_BVH_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_bvh.h"

/** Most SAH bins (rs_bvh_desc.sah_bins): the SAH sweep keeps per-bin arrays this long. */
#define RS_BVH_MAX_BINS 256u

/** Parent of a top-level node (a flat list is a forest of top-level leaves). */
#define RS_BVH_NO_PARENT UINT32_MAX

/** Empty box: lo = +FLT_MAX, hi = -FLT_MAX. */
void rs_bvh__box_empty(float lo[3], float hi[3]);
/** Grow lo/hi by the three vertices of input triangle `tri`. */
void rs_bvh__box_add_triangle(float lo[3], float hi[3], const float *positions,
                              const uint32_t *indices, uint32_t tri);
/** Surface area of a box (0 for an empty one). */
double rs_bvh__box_area(const float lo[3], const float hi[3]);

/**
 * Finish a pre-order node list: nodes[] have leaf fields (bounds, first, count) set and
 * interior bounds empty; parent[i] < i or RS_BVH_NO_PARENT. Computes escape (i + subtree
 * size), level (height), order (left-to-right rank within the level) and interior bounds
 * as the union of the children, bottom-up. Returns false when out of memory.
 */
int rs_bvh__finalize(struct rs_bvh_node *nodes, size_t node_count, const uint32_t *parent);
/* rs_bvh__finalize() in two steps, for a subtree finished on its own thread: the bottom-up
 * pass (escape holds the subtree size, not yet i + size; returns the highest level), then
 * escape += i and order from rank[level]++ (rank[] zeroed by the caller, one per level;
 * it ends holding the number of nodes on each level). */
uint32_t rs_bvh__finalize_up(struct rs_bvh_node *nodes, size_t node_count, const uint32_t *parent);
void rs_bvh__finalize_rank(struct rs_bvh_node *nodes, size_t node_count, uint32_t *rank);

/* Worker threads of one build (bvh_pool.c). A loop runs fn(ctx, job, worker) for every job
 * in [0, jobs), worker in [0, rs_bvh__pool_workers()); the caller's thread is worker 0.
 * rs_bvh__pool_start() may start fewer helpers than asked (NULL: out of memory); a NULL
 * pool runs loops on the caller's thread. */
struct rs_bvh__pool;
typedef void (*rs_bvh__job_fn)(void *ctx, uint32_t job, uint32_t worker);
struct rs_bvh__pool *rs_bvh__pool_start(uint32_t threads);
uint32_t rs_bvh__pool_workers(const struct rs_bvh__pool *pool);
void rs_bvh__pool_run(struct rs_bvh__pool *pool, uint32_t jobs, rs_bvh__job_fn fn, void *ctx);
void rs_bvh__pool_stop(struct rs_bvh__pool *pool);
/* Work for the helpers between loops: once set, a helper with no loop to join calls
 * idle(ctx, worker) until it returns 0 (nothing to do now) or a loop is published, and
 * after a 0 waits for the next loop or rs_bvh__pool_poke() (new work). The caller's thread
 * never calls it. NULL clears it, and returns once no helper can call the old one (which
 * should by then return 0 at once). The idle work must make its own results visible (the
 * pool orders nothing about it). */
typedef int (*rs_bvh__idle_fn)(void *ctx, uint32_t worker);
void rs_bvh__pool_idle(struct rs_bvh__pool *pool, rs_bvh__idle_fn idle, void *ctx);
void rs_bvh__pool_poke(struct rs_bvh__pool *pool);
/* How many times a thread of this pool polls before it sleeps (0: it does not poll, as
 * when threads outnumber the cores), and one poll's pause. */
uint32_t rs_bvh__pool_polls(const struct rs_bvh__pool *pool);
void rs_bvh__pool_relax(void);

/* RS_OK, or RS_ERR_BAD_DATA naming the first of triangle tri's vertices that is out of
 * range or not finite (the message rs_bvh_build() gives for the first bad triangle). */
enum rs_status rs_bvh__check_triangle(const float *positions, size_t vertex_count,
                                      const uint32_t *indices, size_t tri, struct rs_error *err);

/* Builders. Inputs are validated by rs_bvh_build() (the SAH builder checks the mesh itself,
 * with rs_bvh__check_triangle() for the message); each writes nodes, triangle order and
 * the node count. SAH may fail with RS_ERR_NO_MEMORY (and RS_ERR_BAD_DATA). */
enum rs_status rs_bvh__build_flat(uint32_t leaf_size, const float *positions,
                                  const uint32_t *indices, size_t triangle_count,
                                  struct rs_bvh_node *nodes, uint32_t *order, size_t *out_count,
                                  struct rs_error *err);
enum rs_status rs_bvh__build_paper(const float *positions, const uint32_t *indices,
                                   size_t triangle_count, struct rs_bvh_node *nodes,
                                   uint32_t *order, size_t *out_count, struct rs_error *err);
enum rs_status rs_bvh__build_sah(const struct rs_bvh_desc *desc, const float *positions,
                                 size_t vertex_count, const uint32_t *indices,
                                 size_t triangle_count, struct rs_bvh_node *nodes, uint32_t *order,
                                 size_t *out_count, struct rs_error *err);

#endif
