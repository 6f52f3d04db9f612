/* Shared pieces of the reference renderer (Parts 2 and 3 of rs_trace.h): small
 * double-precision vector helpers (rs_vec.h), the frame's ray queries and the kernels of
 * one path (surface, shading, next ray, spawn). Not installed. */
#ifndef RS_TRACE_INTERNAL_H
#define RS_TRACE_INTERNAL_H

#include <math.h>

#include "intersect_internal.h"
#include "raystream/rs_trace.h"
#include "private/rs_vec.h"

/* The frame's ray queries: the packed BVH, or the caller's intersector. */
static inline bool rs_trace_frame_closest(const struct rs_trace_frame *frame,
                                          const struct rs_ray *ray, struct rs_hit *hit,
                                          struct rs_trace_counters *counters)
{
	if (frame->intersector)
		return frame->intersector->closest(frame->intersector->user, ray, hit);
	if (frame->two_level) {
		struct rs_instance_hit ih;
		bool found =
		    rs_trace_two_level_closest(frame->two_level, frame->test, ray, &ih, counters);
		*hit = ih.hit;
		hit->instance = ih.instance;
		return found;
	}
	return rs__trace_closest_local(frame->packed, frame->test, ray, hit, counters);
}

static inline bool rs_trace_frame_occluded(const struct rs_trace_frame *frame,
                                           const struct rs_ray *ray,
                                           struct rs_trace_counters *counters)
{
	if (frame->intersector)
		return frame->intersector->occluded(frame->intersector->user, ray);
	if (frame->two_level)
		return rs_trace_two_level_occluded(frame->two_level, frame->test, ray, counters);
	return rs__trace_occluded_local(frame->packed, frame->test, ray, counters);
}

/* One path: the pass loop. primary: packed frame, unit dir. segments may be NULL (their rays
 * are reported in world coordinates). */
void rs_trace_path_run(const struct rs_trace_frame *frame, const struct rs_ray *primary,
                       struct rs_trace_path *out, struct rs_trace_segment *segments);

/* Surface data at a hit, read from the packed textures. */
struct rs_surface {
	double point[3]; /* R5's P: from the barycentrics, pulled into the triangle */
	double delta;    /* R5's offset for rays leaving here */
	double ng[3];    /* unit geometric normal facing the incoming ray */
	double n[3];     /* unit shading normal, on ng's side */
	int entering;    /* dir . (v1-v0)x(v2-v0) < 0: the ray enters the closed mesh */
	float diffuse[3];
	float specular, shininess, reflectance, transmittance, ior;
	uint32_t flags;
	uint32_t skip; /* what rays leaving here skip: the slot, or two-level the scene id */
};

void rs_trace_surface(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                      const struct rs_hit *hit, struct rs_surface *out);

/* Local shading (ambient + lights seen through shadow feelers) added to rgb * throughput. */
void rs_trace_shade(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                    const struct rs_hit *hit, const struct rs_surface *s, double throughput,
                    double rgb[3], struct rs_trace_path *path);

/* Next-ray step: fills next and its weight; returns RS_RAY_ACTIVE or RS_RAY_DIFFUSE. */
enum rs_ray_state rs_trace_next_ray(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                                    const struct rs_hit *hit, const struct rs_surface *s,
                                    struct rs_ray *next, double *out_weight);

/* Ray leaving the surface along unit dir (docs/tracer.md R5): from s->point, delta to dir's
 * side of ng, skipping the slot. */
void rs_trace_spawn(const struct rs_surface *s, const double dir[3], uint32_t slot,
                    struct rs_ray *out);

#endif
