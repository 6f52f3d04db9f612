/* raystream-bench's peer tracer (Intel Embree 3, built only when CMake finds it): the CPU
 * reference's paths with Embree answering every ray, its rays recorded so they can be traced
 * again by Embree alone, on the same threads, for a rays-per-second figure of the peer. */
#ifndef RS_BENCH_PEER_H
#define RS_BENCH_PEER_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_render.h"

struct bench_peer;

/* A peer holding up to `max_rays` recorded rays (0: record nothing). */
enum rs_status bench_peer_create(uint64_t max_rays, uint32_t threads, struct bench_peer **out,
                                 struct rs_error *err);
void bench_peer_destroy(struct bench_peer **peer);

/* "Embree 3.13.5" */
const char *bench_peer_name(void);

/* For rs_renderer_create_cpu_with(): Embree's closest and any-hit queries, built (prepare)
 * over the renderer's own packed triangles, slot for slot. */
const struct rs_trace_intersector *bench_peer_intersector(struct bench_peer *peer);

/* Record every ray of the frames rendered while on (the recording restarts when turned on). */
void bench_peer_record(struct bench_peer *peer, bool on);

/* Rays recorded: closest-hit and shadow queries, and how many of each hit. RS_ERR_LIMIT when
 * more rays came than max_rays. */
enum rs_status bench_peer_recorded(const struct bench_peer *peer, uint64_t *out_closest,
                                   uint64_t *out_occluded, uint64_t *out_hits,
                                   struct rs_error *err);

/* Trace the recorded rays again with Embree alone on `threads` threads, one ray at a time
 * (rtcIntersect1 / rtcOccluded1) or as streams of 256 rays of one kind (rtcIntersect1M /
 * rtcOccluded1M, which Embree packs into SIMD packets): the wall time, and the hits found
 * (equal to the recorded hits when the replay did the same work). */
enum rs_status bench_peer_replay(struct bench_peer *peer, bool stream, double *out_ms,
                                 uint64_t *out_hits, struct rs_error *err);

/* --table 3's peer: Embree's own BVH build (RTC_BUILD_QUALITY_MEDIUM) over a mesh (the
 * caller keeps `indices` alive) on a device of `threads` threads. */
struct bench_embree_build;
enum rs_status bench_embree_build_create(uint32_t threads, const float *positions,
                                         size_t vertex_count, const uint32_t *indices,
                                         size_t triangle_count, struct bench_embree_build **out,
                                         struct rs_error *err);
/* One build from scratch: rtcCommitScene's wall time and the process's CPU time in it. */
enum rs_status bench_embree_build_once(struct bench_embree_build *build, double *out_ms,
                                       double *out_cpu_ms, struct rs_error *err);
void bench_embree_build_destroy(struct bench_embree_build **build);

#endif
