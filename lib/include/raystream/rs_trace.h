/**
 * @file rs_trace.h
 * The CPU reference tracer, in double precision: the definition of "correct" for every
 * other backend. It traverses the same packed textures the GLES kernels read (rs_pack.h)
 * and counts the paper's hit numbers (box tests and triangle tests per pixel).
 *
 * Part 1 (building blocks): ray/box and ray/triangle tests, closest-hit and any-hit
 * traversal of the threaded BVH, and brute force for checking them.
 * Part 2 (rendering): the paper's ray semantics over N passes; see docs/tracer.md.
 * Part 3 (the frame description): every number of a frame, computed once from scene,
 * descriptor and camera; the CPU tracer reads it and the GLES backend hands the same
 * values to its kernels (uniforms and a generated #define prelude).
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

/** Ray/triangle test. Zero (the default) is the watertight test (docs/tracer.md R2). */
enum rs_triangle_test {
	/** Woop, Benthin & Wald 2013: no ray slips through shared edges or vertices. */
	RS_TRIANGLE_WATERTIGHT = 0,
	/** Moller-Trumbore, the paper's: rays can slip through exact shared edges. */
	RS_TRIANGLE_MOLLER_TRUMBORE = 1,
};

/** "No triangle" for rs_ray.skip_slot and rs_hit.slot. */
#define RS_NO_SLOT UINT32_MAX

/** A ray; hits count only for tmin < t < tmax. dir need not be unit length. */
struct rs_ray {
	double origin[3];
	double dir[3];
	double tmin;
	double tmax;
	uint32_t skip_slot; /**< packed triangle slot to ignore (the one the ray leaves), or
	                       RS_NO_SLOT */
};

/** Closest hit. u, v are the barycentric weights of v1 and v2 (v0 gets 1 - u - v). */
struct rs_hit {
	double t;
	double u, v;
	uint32_t slot;     /**< packed triangle slot (BVH order), RS_NO_SLOT on a miss */
	uint32_t triangle; /**< scene triangle id */
	/** Two-level frames (rs_trace_desc.two_level): the instance hit; unused otherwise. */
	uint32_t instance;
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

/**
 * Closest hit through the packed BVH; `ray` in world coordinates (packed->origin is
 * subtracted here). Ties in t go to the lower scene triangle id, so every BVH gives the
 * same hit (docs/tracer.md R4). counters may be NULL.
 */
bool rs_trace_closest(const struct rs_packed *packed, enum rs_triangle_test test,
                      const struct rs_ray *ray, struct rs_hit *out_hit,
                      struct rs_trace_counters *counters);

/** Any hit (shadow feelers), world ray: stops at the first triangle found. counters may be
 * NULL. */
bool rs_trace_occluded(const struct rs_packed *packed, enum rs_triangle_test test,
                       const struct rs_ray *ray, struct rs_trace_counters *counters);

/** Closest hit by testing every triangle of the packed scene, in slot order, with the
 * same tie-break (for checking traversal); world ray. */
bool rs_trace_closest_brute(const struct rs_packed *packed, enum rs_triangle_test test,
                            const struct rs_ray *ray, struct rs_hit *out_hit);

/** A closest hit of the two-level walk (rs_trace_instances_closest). */
struct rs_instance_hit {
	struct rs_hit hit; /**< t (of the world ray), u, v, the BLAS slot, the scene triangle id */
	uint32_t instance; /**< the instance hit, RS_NO_SLOT on a miss */
	/** Unit geometric normal in world space: the object-space e1 x e2 through the inverse
	 * transpose, so it faces the side the prototype's winding gives, mirrors included. */
	double normal[3];
};

/**
 * The CPU reference of the two-level walk (docs/bvh.md "Instances"), in double: the TLAS's
 * threaded order of the world ray's major direction; at an instance item the ray goes into the
 * mesh's BLAS frame (origin and direction through to_object, the direction not renormalised so
 * t is the same), the BLAS is walked in the threaded order of the object-space direction with
 * the best t so far as tmax, and the walk continues at the TLAS leaf's escape with the world
 * ray. The closest-hit rule (R4) is on scene triangle ids. World ray; its skip_slot is here a
 * scene triangle id to ignore (or RS_NO_SLOT). Counters: box tests of both levels (each BLAS
 * entered starts with its root's box), triangle tests of the BLASes; the TLAS's items are not
 * counted (their boxes are the leaf's). Threaded node formats only: false for wide4.
 */
bool rs_trace_instances_closest(const struct rs_packed_instances *packed,
                                enum rs_triangle_test test, const struct rs_ray *ray,
                                struct rs_instance_hit *out_hit,
                                struct rs_trace_counters *counters);
/** As rs_trace_instances_closest() but stops at the first hit (shadow rays). */
bool rs_trace_instances_occluded(const struct rs_packed_instances *packed,
                                 enum rs_triangle_test test, const struct rs_ray *ray,
                                 struct rs_trace_counters *counters);

/**
 * The same two-level walk on a merged packing (rs_pack_two_level()): the layout the GLES
 * kernels read, every instance value taken from the instance texture (floats). The ray is in
 * the merged packing's frame (relative to packed->all.origin, as rays of a frame are) and
 * its skip_slot is a scene triangle id; hit.slot is the merged slot, hit.triangle the scene
 * id. Counters count the TLAS's and every BLAS's box tests and the triangle tests
 * (docs/bvh.md "Instances on the GPU").
 */
bool rs_trace_two_level_closest(const struct rs_packed_two_level *packed,
                                enum rs_triangle_test test, const struct rs_ray *ray,
                                struct rs_instance_hit *out_hit,
                                struct rs_trace_counters *counters);
/** As rs_trace_two_level_closest() but stops at the first hit (shadow rays). */
bool rs_trace_two_level_occluded(const struct rs_packed_two_level *packed,
                                 enum rs_triangle_test test, const struct rs_ray *ray,
                                 struct rs_trace_counters *counters);

/* ---- Part 2: rendering --------------------------------------------------------------- */

/** Ray states, as the paper names them. */
enum rs_ray_state {
	RS_RAY_ACTIVE = 0,       /**< has a next segment to trace */
	RS_RAY_MISSED = -1,      /**< left the scene: the environment kernel resolves it */
	RS_RAY_ENVIRONMENT = -2, /**< environment colour taken: finished */
	RS_RAY_DIFFUSE = -3,     /**< hit a surface that neither reflects nor refracts: finished */
};

/**
 * Someone else's ray queries in place of the packed-BVH walk, under the reference's path
 * logic (to run a peer library on exactly the reference's rays: raystream-bench's Embree
 * peer). Rays arrive in the packed frame (relative to packed->origin, as the packed
 * positions are). Both calls must honour ray->tmin < t < ray->tmax and ray->skip_slot, and
 * hits must name the packed slot (the triangle's index in BVH slot order: shading reads the
 * packed textures there). Called from every render thread at once, so it must be
 * thread-safe. Box and triangle counts stay 0 under an intersector.
 */
struct rs_trace_intersector {
	bool (*closest)(void *user, const struct rs_ray *ray, struct rs_hit *out_hit);
	bool (*occluded)(void *user, const struct rs_ray *ray);
	/** Optional: called by the CPU renderer (rs_renderer_create_cpu_with()) at set_scene
	 * with the packed textures it will shade from, to build the peer's structure over the
	 * same triangles in the same slots. rs_trace_render() never calls it. */
	enum rs_status (*prepare)(void *user, const struct rs_packed *packed, struct rs_error *err);
	void *user;
};
/** Default spawn offset scale S of docs/tracer.md R5: 2^-16 (128 fp32 ulps). */
#define RS_TRACE_SPAWN_SCALE 0x1p-16

/** Render options; zero-initialised means defaults. */
struct rs_trace_desc {
	uint32_t width, height;              /**< 0: the camera's size */
	uint32_t passes;                     /**< ray segments per path; 0 -> 2 */
	uint32_t lights;                     /**< use the scene's first N lights; 0 -> all */
	enum rs_triangle_test triangle_test; /**< 0: watertight */
	/** Spawn offset relative to the largest coordinate of the hit triangle in the packed
	 * frame (docs/tracer.md R5); 0 -> RS_TRACE_SPAWN_SCALE. */
	double ray_epsilon;
	uint32_t row_begin, row_end; /**< render only rows [begin, end); both 0 -> all */
	/** Camera to render from instead of the scene's (its size is used when width or
	 * height is 0, like the scene camera's); NULL: the scene's. */
	const struct rs_camera *camera;
	/** Ray queries to use instead of walking `packed`'s BVH; NULL: the walk. */
	const struct rs_trace_intersector *intersector;
	/** An instanced scene packed in two levels (rs_pack_two_level()) to walk instead of a
	 * flattened BVH; `packed` must then be two_level->all (or a copy of it). Skip slots are
	 * scene triangle ids (a BLAS slot is shared by the instances of its mesh). NULL: one level.
	 */
	const struct rs_packed_two_level *two_level;
	/** Every light in front of a surface counts as visible: no shadow feelers are traced
	 * (rs_render's shadows=none). false: exact feelers. */
	bool unshadowed;
};

/** Counts over the rendered pixels. Hit numbers are means per pixel over all its rays. */
struct rs_trace_stats {
	uint64_t pixels;
	uint64_t rays; /**< path segments traced (primary, reflected, refracted) */
	uint64_t shadow_rays;
	uint64_t box_tests;
	uint64_t triangle_tests;
	double box_per_pixel;
	double triangle_per_pixel;
	double total_per_pixel;
};

/**
 * The primary ray through image position (px, py) in pixels, (0, 0) being the top-left
 * corner of the image and (x + 0.5, y + 0.5) the centre of pixel (x, y); row 0 = top;
 * camera->sample's offset (rs_trace_sample_offset()) is added.
 * Pinhole at camera->eye (resolved with rs_camera_resolve()), vertical field of view
 * fov_y_deg over `height` pixels, square pixels. width/height 0: the camera's size.
 * The direction has unit length (so t is a distance); tmin 0, tmax +INFINITY, no skip slot.
 */
void rs_trace_camera_ray(const struct rs_camera *camera, uint32_t width, uint32_t height, double px,
                         double py, struct rs_ray *out_ray);

/** Where a ray leaves the environment cube (see rs_trace_environment()). */
struct rs_env_hit {
	double point[3]; /**< exit point, on the face plane */
	uint32_t face;   /**< 0..5 = +x, -x, +y, -y, +z, -z */
	double s, t;     /**< position on the face in [0, 1] along axes (a+1)%3 and (a+2)%3 */
	uint32_t cell_s, cell_t; /**< grid cell, 0..grid-1 */
	bool line;               /**< the point lies on a grid line */
};

/**
 * Colour of the environment cube where a ray from `origin` along `dir` (any length > 0)
 * leaves it: the exit point, not the direction alone, picks the texel, so there is no
 * parallax. A zero direction answers face +x at its centre. `env` as rs_scene_environment()
 * resolves it (zero grid/line fields get their defaults here too). out_hit may be NULL.
 */
void rs_trace_environment(const struct rs_environment *env, const double origin[3],
                          const double dir[3], struct rs_env_hit *out_hit, double out_rgb[3]);

/** Mirror `dir` about the unit `normal`: dir - 2 (dir.normal) normal (any side). */
void rs_trace_reflect(const double dir[3], const double normal[3], double out_dir[3]);

/**
 * Snell refraction of the unit `dir` through a surface with unit `normal` facing against
 * `dir` (dir.normal <= 0), eta = n_from / n_to. Writes the unit refracted direction and
 * returns true, or returns false (total internal reflection) and leaves out_dir untouched.
 */
bool rs_trace_refract(const double dir[3], const double normal[3], double eta, double out_dir[3]);

/**
 * Schlick's approximation of the Fresnel reflectance for light going from index n_from to
 * n_to with cos_i = cosine of the incidence angle: R0 + (1 - R0)(1 - c)^5, R0 =
 * ((n_from - n_to) / (n_from + n_to))^2, c = cos_i when n_from <= n_to, else the cosine of
 * the transmitted angle; 1 under total internal reflection; 0 when n_from == n_to (no
 * interface) or an index is not positive. Always in [0, 1].
 */
double rs_trace_fresnel_schlick(double cos_i, double n_from, double n_to);

/** One traced segment of a path (for tests and for comparing backends pass by pass). */
struct rs_trace_segment {
	struct rs_ray ray;       /**< as traced (origin already offset, skip slot set), in world
	                              coordinates (traced in the packed frame, docs/tracer.md R1) */
	struct rs_hit hit;       /**< slot RS_NO_SLOT on a miss */
	double throughput;       /**< weight its contribution was scaled by */
	enum rs_ray_state state; /**< after this segment: ACTIVE (a next ray was made),
	                              ENVIRONMENT (missed, colour taken) or DIFFUSE */
};

/** Result of one path. */
struct rs_trace_path {
	double rgb[3];
	double depth; /**< first segment's hit distance (unit dir), +INFINITY on a miss */
	enum rs_ray_state state; /**< final state; ACTIVE means the pass budget ran out */
	uint32_t segments;       /**< segments traced (<= passes) */
	uint32_t shadow_rays;
	struct rs_trace_counters counters; /**< every test of every ray of the path */
};

/**
 * Trace one path from an arbitrary first ray with rs_trace_render()'s semantics (desc's
 * passes, lights, triangle test, epsilon; its size and rows are ignored). `primary->dir`
 * must be non-zero; it is normalised unless already unit length within 1e-12 (camera rays
 * are kept bit for bit, so they take the same path as in rs_trace_render()).
 * out_segments: caller-owned array of `passes` entries, or NULL. No allocation.
 */
enum rs_status rs_trace_ray_path(const struct rs_scene *scene, const struct rs_packed *packed,
                                 const struct rs_trace_desc *desc, const struct rs_ray *primary,
                                 struct rs_trace_path *out_path,
                                 struct rs_trace_segment *out_segments, struct rs_error *err);

/** Largest accepted rs_trace_desc.passes. */
#define RS_TRACE_MAX_PASSES 64u

/**
 * Render the scene from its camera.
 * @param out_rgb    caller-owned width*height*3 floats (linear RGB, row 0 = top), or NULL
 * @param out_depth  caller-owned width*height floats: primary-hit distance, +INFINITY on a
 *                   miss, or NULL
 * @param out_stats  may be NULL
 * Only rows [row_begin, row_end) are written when a row range is given; stats cover those
 * rows. Allocation-free; read-only on scene and packed, so several threads may render
 * disjoint row ranges at once. Semantics: docs/tracer.md.
 * RS_ERR_INVALID: bad descriptor (passes > RS_TRACE_MAX_PASSES, more lights than the scene
 * has, bad row range, epsilon < 0 or not finite), or packed not matching the scene.
 */
enum rs_status rs_trace_render(const struct rs_scene *scene, const struct rs_packed *packed,
                               const struct rs_trace_desc *desc, float *out_rgb, float *out_depth,
                               struct rs_trace_stats *out_stats, struct rs_error *err);

/* ---- Part 3: the frame description ------------------------------------------------ */

/** R3: slab distances are widened outwards by K = 16 ulps of the arithmetic's precision. */
#define RS_TRACE_BOX_K 0x1p-49      /**< double (the reference) */
#define RS_TRACE_BOX_K_FP32 0x1p-19 /**< fp32 (the kernels) */
/** The hits-only kernel's grid-unit box test (docs/gles.md "Hits only"): each axis widened
 * by this share of the largest |t| a grid plane can have, 65535 |step / d| + |(grid origin -
 * o) / d|, an absolute bound that covers its fp32 rounding and the triangle test's (R3's K
 * is relative to t; this test's rounding is not). */
#define RS_TRACE_GRID_BOX_E_FP32 0x1p-18
/** R2: a ray within this relative |d.n| / (|d| |n|) of a triangle's plane is parallel. */
#define RS_TRACE_PARALLEL_EPS 1e-13
/** R5's pull: a triangle less than PULL_HEIGHT delta high goes to its centroid, else each
 * barycentric is raised to at least PULL delta / (the triangle's height over that edge). */
#define RS_TRACE_SPAWN_PULL_HEIGHT 12.0
#define RS_TRACE_SPAWN_PULL 4.0
/** R5's floor F = max(R * FLOOR_SHARE, FLOOR_MIN), R half the scene's largest side. */
#define RS_TRACE_SPAWN_FLOOR_SHARE 0.0625
#define RS_TRACE_SPAWN_FLOOR_MIN 0x1p-64

/** The fixed constants of docs/tracer.md R2-R5, as values (what a backend hands on). */
struct rs_trace_rules {
	double box_k, box_k_fp32;             /**< R3 */
	double grid_box_e_fp32;               /**< R3 in grid units (hits-only kernel) */
	double parallel_eps;                  /**< R2 */
	double spawn_pull_height, spawn_pull; /**< R5 */
};

/**
 * One frame's numbers, resolved once by rs_trace_frame_init() from scene, packed textures
 * and descriptor: everything the tracer (and a GPU backend) reads besides the textures and
 * the camera. Positions are in the packed frame (R1) unless said otherwise.
 */
struct rs_trace_frame {
	const struct rs_packed *packed;
	enum rs_triangle_test test;
	uint32_t passes;      /**< resolved (0 -> 2) */
	uint32_t light_count; /**< resolved (0 -> all of the scene's) */
	/** The scene's lights, world coordinates: rs_trace_frame_light() gives one in the frame. */
	const struct rs_light *lights;
	double ambient;
	double origin[3];          /**< the packed frame's origin (R1) */
	double spawn_scale;        /**< R5's S: desc.ray_epsilon or RS_TRACE_SPAWN_SCALE */
	double spawn_floor;        /**< R5's F = max(R / 16, 2^-64) */
	double bounds_center[3];   /**< the scene's bounding box centre */
	double bounds_radius;      /**< and its half-diagonal (0 for an empty scene) */
	bool has_geometry;         /**< false: every ray misses (empty scene) */
	bool unshadowed;           /**< rs_trace_desc.unshadowed: no feelers, lights visible */
	struct rs_environment env; /**< resolved (rs_scene_environment()), centre in the frame */
	struct rs_trace_rules rules;
	const struct rs_trace_intersector *intersector; /**< NULL: walk packed's BVH */
	const struct rs_packed_two_level *two_level;    /**< rs_trace_desc.two_level */
};

/**
 * Resolve `desc` (NULL: defaults; its size, rows and camera are not read) against `scene`
 * and `packed` into `out`. `out` points at scene and packed, which must outlive it.
 * RS_ERR_INVALID as rs_trace_render() for a bad descriptor or packed not matching scene.
 */
enum rs_status rs_trace_frame_init(const struct rs_scene *scene, const struct rs_packed *packed,
                                   const struct rs_trace_desc *desc, struct rs_trace_frame *out,
                                   struct rs_error *err);

/** Light `i` (< light_count) moved into the packed frame, in double (R1). */
void rs_trace_frame_light(const struct rs_trace_frame *frame, uint32_t i, double out_position[3]);

/** R7: the range fp32 kernels compute in. Their triangle test multiplies three coordinates
 * relative to the ray's origin and a normal's length squares an area: a frame reaching
 * beyond MAX units from the packed frame's centre overflows the float range, one reaching
 * less than MIN underflows it (measured failures: ~2e13 and ~3e-11; docs/tracer.md R7). */
#define RS_TRACE_FP32_REACH_MIN 0x1p-26
#define RS_TRACE_FP32_REACH_MAX 0x1p40

/** How far a frame seen from `eye` (packed frame) reaches: the largest coordinate of the
 * scene's bounds, its environment box, the frame's lights and the eye, in the packed frame;
 * 0 for an empty scene (every ray misses: nothing to overflow). */
double rs_trace_frame_reach(const struct rs_trace_frame *frame, const double eye[3]);

/** A camera resolved for ray generation (docs/tracer.md, Ray generation). */
struct rs_trace_view {
	double eye[3];                  /**< relative to the origin given to rs_trace_view_init() */
	double fwd[3], right[3], up[3]; /**< unit forward and right; up = right x fwd */
	double tan_half_fov;            /**< b = tan(fov_y / 2) */
	double shift[2];                /**< lens shift */
	/** Added to every image position (pixels, +x right, +y down): the camera's sample
	 * offset, rs_trace_sample_offset(camera->sample); (0, 0) for sample 0. */
	double pixel_offset[2];
	uint32_t width, height;
};

/**
 * The basis of `camera` (resolved with rs_camera_resolve()) for an image of width x height
 * (0: the camera's size), its eye moved by -origin in double (NULL: kept in world).
 */
void rs_trace_view_init(const struct rs_camera *camera, const double origin[3], uint32_t width,
                        uint32_t height, struct rs_trace_view *out);

/**
 * The sub-pixel offset of refinement sample `sample`, in pixels, each coordinate in
 * [-0.5, 0.5): the R2 low-discrepancy sequence (Roberts 2018, the plastic number's
 * inverse powers) centred on the pixel, so sample 0 is (0, 0), the centre, and the first
 * N samples cover the pixel evenly for every N (the running mean converges at each frame).
 */
void rs_trace_sample_offset(uint32_t sample, double out[2]);

/** The primary ray through image position (px, py) + view->pixel_offset, as
 * rs_trace_camera_ray() describes. */
void rs_trace_view_ray(const struct rs_trace_view *view, double px, double py,
                       struct rs_ray *out_ray);

#ifdef __cplusplus
}
#endif
#endif
