/**
 * @file rs_trace.h
 * The CPU reference tracer, in double precision: the definition of "correct" for every
 * other backend. It traverses the same packed textures the GLES kernels read (rs_pack.h)
 * and counts the paper's hit numbers (box tests and triangle tests per pixel).
 *
 * Part 1 (building blocks): ray/box and ray/triangle tests, closest-hit and any-hit
 * traversal of the threaded BVH, and brute force for checking them.
 * Part 2 (rendering): the paper's ray semantics over N passes; see docs/tracer.md.
 */
#ifndef RS_TRACE_H
#define RS_TRACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_pack.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Part 1: building blocks ------------------------------------------------------ */

/** Ray/triangle test. Zero (the default) is Moller-Trumbore, the paper's. */
enum rs_triangle_test {
	RS_TRIANGLE_MOLLER_TRUMBORE = 0,
	/** Woop, Benthin & Wald 2013: no ray slips through shared edges or vertices. */
	RS_TRIANGLE_WATERTIGHT = 1,
};

/** "No triangle" for rs_ray.skip_slot and rs_hit.slot. */
#define RS_NO_SLOT UINT32_MAX

/** A ray; hits count only for tmin < t < tmax. dir need not be unit length. */
struct rs_ray {
	double origin[3];
	double dir[3];
	double tmin;
	double tmax;
	uint32_t skip_slot; /**< packed triangle slot to ignore (the one the ray leaves), or RS_NO_SLOT */
};

/** Closest hit. u, v are the barycentric weights of v1 and v2 (v0 gets 1 - u - v). */
struct rs_hit {
	double t;
	double u, v;
	uint32_t slot;      /**< packed triangle slot (BVH order), RS_NO_SLOT on a miss */
	uint32_t triangle;  /**< scene triangle id */
};

/** Intersection test counts, as the paper counts them. */
struct rs_trace_counters {
	uint64_t box_tests;
	uint64_t triangle_tests;
};

/** Slab test of a ray (given 1/dir, IEEE infinities allowed) against a box. */
bool rs_intersect_box(const float lo[3], const float hi[3], const double origin[3],
		      const double inv_dir[3], double tmin, double tmax);

/**
 * Ray/triangle test with either algorithm: true and t, u, v when the ray hits the
 * triangle with tmin < t < tmax. Zero-area triangles and rays in the triangle's plane
 * never hit.
 */
bool rs_intersect_triangle(enum rs_triangle_test test, const double v0[3], const double v1[3],
			   const double v2[3], const struct rs_ray *ray, double *out_t,
			   double *out_u, double *out_v);

/** Closest hit through the packed BVH. counters may be NULL. */
bool rs_trace_closest(const struct rs_packed *packed, enum rs_triangle_test test,
		      const struct rs_ray *ray, struct rs_hit *out_hit,
		      struct rs_trace_counters *counters);

/** Any hit (shadow feelers): stops at the first triangle found. counters may be NULL. */
bool rs_trace_occluded(const struct rs_packed *packed, enum rs_triangle_test test,
		       const struct rs_ray *ray, struct rs_trace_counters *counters);

/** Closest hit by testing every triangle of the packed scene (for checking traversal). */
bool rs_trace_closest_brute(const struct rs_packed *packed, enum rs_triangle_test test,
			    const struct rs_ray *ray, struct rs_hit *out_hit);

/* ---- Part 2: rendering --------------------------------------------------------------- */

/** Ray states, as the paper names them. */
enum rs_ray_state {
	RS_RAY_ACTIVE = 0,       /**< has a next segment to trace */
	RS_RAY_MISSED = -1,      /**< left the scene: the environment kernel resolves it */
	RS_RAY_ENVIRONMENT = -2, /**< environment colour taken: finished */
	RS_RAY_DIFFUSE = -3,     /**< hit a surface that neither reflects nor refracts: finished */
};

/** Render options; zero-initialised means defaults. */
struct rs_trace_desc {
	uint32_t width, height;   /**< 0: the camera's size */
	uint32_t passes;          /**< ray segments per path; 0 -> 2 */
	uint32_t lights;          /**< use the scene's first N lights; 0 -> all */
	enum rs_triangle_test triangle_test;
	double ray_epsilon;       /**< self-hit offset relative to the scene's extent; 0 -> 1e-6 */
	uint32_t row_begin, row_end; /**< render only rows [begin, end); both 0 -> all */
};

/** Counts over the rendered pixels. Hit numbers are means per pixel over all its rays. */
struct rs_trace_stats {
	uint64_t pixels;
	uint64_t rays;            /**< path segments traced (primary, reflected, refracted) */
	uint64_t shadow_rays;
	uint64_t box_tests;
	uint64_t triangle_tests;
	double box_per_pixel;
	double triangle_per_pixel;
	double total_per_pixel;
};

/**
 * Render the scene from its camera.
 * @param out_rgb    caller-owned width*height*3 floats (linear RGB, row 0 = top), or NULL
 * @param out_depth  caller-owned width*height floats: primary-hit distance, +INFINITY on a
 *                   miss, or NULL
 * @param out_stats  may be NULL
 * Only rows [row_begin, row_end) are written when a row range is given.
 */
enum rs_status rs_trace_render(const struct rs_scene *scene, const struct rs_packed *packed,
			       const struct rs_trace_desc *desc, float *out_rgb, float *out_depth,
			       struct rs_trace_stats *out_stats, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
