/*
 * raystream-bench --builds: BVH build time against the peer's. Our SAH builder
 * (rs_bvh_build) and Embree 3's medium-quality build (the one Embree uses for scenes that
 * change) over the same mesh on the same number of threads, one build of each in turn,
 * median of at least 7 each, wall clock and the process's CPU time (all threads: the work, which
 * a loaded machine distorts less); beside them our tree's size and SAH cost, and whether the tree
 * is the one-thread tree to the byte (it must be: threads share the work, never the
 * decisions).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "peer.h"
#include "raystream/rs_bvh.h"
#include "raystream/rs_scenegen.h"
#include "tool_common.h"

enum { MIN_REPEATS = 7 };

struct mesh_build {
	const struct rs_scene *scene;
	size_t tris, cap, count;
	struct rs_bvh_node *nodes;
	uint32_t *order;
};

/* The process's CPU time, all threads, to the nanosecond (getrusage counts in ticks). */
static double process_cpu_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
	return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static enum rs_status our_build(struct mesh_build *m, uint32_t threads, double *ms, double *cpu_ms,
                                struct rs_error *err)
{
	struct rs_bvh_desc desc = {.builder = RS_BVH_SAH, .threads = threads};
	double t0 = rs_now_ms(), c0 = process_cpu_ms();
	enum rs_status s = rs_bvh_build(&desc, rs_scene_positions(m->scene),
	                                rs_scene_vertex_count(m->scene), rs_scene_indices(m->scene),
	                                m->tris, m->nodes, m->cap, m->order, &m->count, err);
	*ms = rs_now_ms() - t0;
	*cpu_ms = process_cpu_ms() - c0;
	return s;
}

/* Medians of one side's builds: wall and CPU ms. */
struct timing {
	double wall, cpu;
};

#ifdef RS_BENCH_HAVE_EMBREE
#define HAVE_PEER 1
#else
#define HAVE_PEER 0
#endif

/* Ours and the peer's (when `peer`), alternately. */
static enum rs_status time_builds(struct mesh_build *m, uint32_t threads, uint32_t repeats,
                                  bool peer, struct timing *ours, struct timing *theirs,
                                  struct rs_error *err)
{
	double t_ours[32], t_peer[32], c_ours[32], c_peer[32];
	enum rs_status s = RS_OK;
#ifdef RS_BENCH_HAVE_EMBREE
	struct bench_embree_build *e = NULL;
	if (peer)
		s = bench_embree_build_create(threads, rs_scene_positions(m->scene),
		                              rs_scene_vertex_count(m->scene),
		                              rs_scene_indices(m->scene), m->tris, &e, err);
#endif
	/* One untimed build each first (fresh buffers' page faults, threads starting). */
	for (uint32_t r = 0; r <= repeats && s == RS_OK; ++r) {
		uint32_t slot = r ? r - 1 : 0;
		s = our_build(m, threads, &t_ours[slot], &c_ours[slot], err);
#ifdef RS_BENCH_HAVE_EMBREE
		if (s == RS_OK && peer)
			s = bench_embree_build_once(e, &t_peer[slot], &c_peer[slot], err);
#endif
	}
#ifdef RS_BENCH_HAVE_EMBREE
	bench_embree_build_destroy(&e);
#endif
	if (s != RS_OK)
		return s;
	*ours = (struct timing){rs_tool_median(t_ours, repeats), rs_tool_median(c_ours, repeats)};
	*theirs = (struct timing){0.0, 0.0};
	if (peer)
		*theirs = (struct timing){rs_tool_median(t_peer, repeats),
		                          rs_tool_median(c_peer, repeats)};
	return RS_OK;
}

static int bench_scene(const struct bench_options *o, const char *name, uint32_t repeats)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	if (rs_scenegen_load(name, &scene, &err) != RS_OK) {
		fprintf(stderr, "raystream-bench: %s\n", err.message);
		return 1;
	}
	struct mesh_build m = {.scene = scene, .tris = rs_scene_triangle_count(scene)};
	struct rs_bvh_desc sah = {.builder = RS_BVH_SAH};
	m.cap = rs_bvh_node_bound(&sah, m.tris);
	m.nodes = malloc((m.cap ? m.cap : 1) * sizeof *m.nodes);
	m.order = malloc((m.tris ? m.tris : 1) * sizeof *m.order);
	struct rs_bvh_node *one_nodes = malloc((m.cap ? m.cap : 1) * sizeof *one_nodes);
	uint32_t *one_order = malloc((m.tris ? m.tris : 1) * sizeof *one_order);
	size_t one_count = 0;
	int code = m.nodes && m.order && one_nodes && one_order ? 0 : 1;
	if (code)
		fprintf(stderr, "raystream-bench: out of memory\n");
	uint32_t runs[2] = {1, o->threads};
	bool peer = HAVE_PEER && o->peer;
	for (uint32_t k = 0; k < (o->threads > 1 ? 2u : 1u) && code == 0; ++k) {
		struct timing ours, theirs;
		if (time_builds(&m, runs[k], repeats, peer, &ours, &theirs, &err) != RS_OK) {
			fprintf(stderr, "raystream-bench: %s: %s\n", name, err.message);
			code = 1;
			break;
		}
		if (k == 0) {
			memcpy(one_nodes, m.nodes, m.count * sizeof *m.nodes);
			memcpy(one_order, m.order, m.tris * sizeof *m.order);
			one_count = m.count;
		}
		bool same = m.count == one_count &&
		            !memcmp(one_nodes, m.nodes, m.count * sizeof *m.nodes) &&
		            !memcmp(one_order, m.order, m.tris * sizeof *m.order);
		struct rs_bvh_stats st;
		rs_bvh_stats(m.nodes, m.count, 1.0f, &st);
		char peer_ms[64] = "- | -", ratio[64] = "- | -";
		if (peer) {
			snprintf(peer_ms, sizeof peer_ms, "%.2f | %.2f", theirs.wall, theirs.cpu);
			snprintf(ratio, sizeof ratio, "%.2f | %.2f", ours.wall / theirs.wall,
			         ours.cpu / theirs.cpu);
		}
		printf("| %-5s | %6zu | %u | %.2f | %.2f | %s | %s | %zu | %.3f | %s |\n", name,
		       m.tris, runs[k], ours.wall, ours.cpu, peer_ms, ratio, m.count, st.sah_cost,
		       same ? "yes" : "NO");
		if (!same)
			code = 1;
	}
	free(m.nodes);
	free(m.order);
	free(one_nodes);
	free(one_order);
	rs_scene_destroy(&scene);
	return code;
}

static void print_load(const char *when)
{
	double load[3];
	if (getloadavg(load, 3) == 3)
		printf("load average %s: %.2f %.2f %.2f\n", when, load[0], load[1], load[2]);
}

int bench_builds(const struct bench_options *o)
{
	uint32_t repeats = o->repeats < MIN_REPEATS ? MIN_REPEATS : o->repeats;
	bool peer = HAVE_PEER && o->peer;
#ifdef RS_BENCH_HAVE_EMBREE
	const char *peer_name = bench_peer_name();
#else
	const char *peer_name = "no peer (Embree 3 not found at build time)";
#endif
	printf("BVH build time, ms: raystream sah (rs_bvh_build) vs %s%s, same mesh and threads,\n"
	       "built in turn, median of %u builds each\n\n",
	       peer ? peer_name : "no peer", peer ? " RTC_BUILD_QUALITY_MEDIUM" : "", repeats);
	print_load("at start");
	printf("\n| scene | tris | threads | ours ms | ours CPU ms | peer ms | peer CPU ms | "
	       "ours / peer | CPU ours / peer | nodes | SAH cost | same tree as 1 thread |\n"
	       "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
	int code = 0;
	for (size_t s = 0; s < BENCH_SCENE_COUNT; ++s) {
		if (o->only && strcmp(o->only, bench_scenes[s]) != 0)
			continue;
		code |= bench_scene(o, bench_scenes[s], repeats);
	}
	printf("\n");
	print_load("at end");
	return code;
}
