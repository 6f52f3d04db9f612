/* Shared pieces of the reference renderer (Part 2 of rs_trace.h): small double-precision
 * vector helpers (rs_vec.h) and the per-frame constants every path reads. Not installed. */
#ifndef RS_TRACE_RENDER_INTERNAL_H
#define RS_TRACE_RENDER_INTERNAL_H

#include <math.h>

#include "accel_internal.h"
#include "raystream/rs_trace.h"
#include "private/rs_vec.h"

/* Constants of one frame, resolved once by rs_trace_frame_init(). */
struct rs_trace_frame {
	const struct rs_packed *packed;
	enum rs_triangle_test test;
	uint32_t passes;
	uint32_t light_count;
	const struct rs_light *lights;
	double ambient;
	double spawn_scale;        /* R5's S: offset relative to the hit triangle's magnitude */
	double spawn_floor;        /* R5's floor on that magnitude: the frame's half-size / 16 */
	double origin[3];          /* the packed frame's origin (R1): lights are moved by it */
	bool has_geometry;         /* false: every ray misses (empty scene) */
	struct rs_environment env; /* centre already in the packed frame */
	const struct rs_trace_intersector *intersector; /* NULL: walk packed's BVH */
};

/* The frame's ray queries: the packed BVH, or the caller's intersector. */
static inline bool rs_trace_frame_closest(const struct rs_trace_frame *frame,
                                          const struct rs_ray *ray, struct rs_hit *hit,
                                          struct rs_trace_counters *counters)
{
	if (frame->intersector)
		return frame->intersector->closest(frame->intersector->user, ray, hit);
	return rs__trace_closest_local(frame->packed, frame->test, ray, hit, counters);
}

static inline bool rs_trace_frame_occluded(const struct rs_trace_frame *frame,
                                           const struct rs_ray *ray,
                                           struct rs_trace_counters *counters)
{
	if (frame->intersector)
		return frame->intersector->occluded(frame->intersector->user, ray);
	return rs__trace_occluded_local(frame->packed, frame->test, ray, counters);
}

enum rs_status rs_trace_frame_init(const struct rs_scene *scene, const struct rs_packed *packed,
                                   const struct rs_trace_desc *desc, struct rs_trace_frame *out,
                                   struct rs_error *err);

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
