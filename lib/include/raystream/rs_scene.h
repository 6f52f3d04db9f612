/**
 * @file rs_scene.h
 * A scene: triangles (fed from caller-owned vertex/index arrays, copied in), materials, a
 * camera, point lights, the environment cube and ambient light. Positions are kept in
 * double as given (and rounded to float); packing subtracts the scene's centre before
 * rounding them for the GPU (rs_pack.h). Normals are float; camera, lights and the rest
 * are double.
 */
#ifndef RS_SCENE_H
#define RS_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Material flags. */
enum rs_material_flags {
	/** Weight reflection/refraction by Fresnel (Schlick) instead of the fixed weights. */
	RS_MATERIAL_FRESNEL = 1u << 0,
};

/**
 * Surface description. Zero-initialised is a valid black, purely diffuse surface.
 * A surface with reflectance == 0 and transmittance == 0 ends its ray path (state -3).
 */
struct rs_material {
	float diffuse[3];    /**< Lambert colour */
	float specular;      /**< Phong specular weight (white highlight) */
	float shininess;     /**< Phong exponent; 0 means 1 */
	float reflectance;   /**< mirror reflection weight */
	float transmittance; /**< refraction weight */
	float ior;           /**< index of refraction; 0 means 1 (no bending) */
	uint32_t flags;      /**< enum rs_material_flags */
};

/**
 * A mesh to add: caller-owned arrays, read during rs_scene_add_mesh() only.
 * Strides are in bytes; 0 means tightly packed (3 floats or 3 doubles, 3 uint32).
 * Give exactly one of `positions` and `positions_f64`. Double positions are kept in double
 * until packing subtracts the scene's centre (docs/tracer.md R1, R6), so a scene far from
 * the origin loses no precision; float positions are already rounded where they lie.
 */
struct rs_mesh_desc {
	const float *positions; /**< vertex_count xyz triples, or NULL with positions_f64 */
	size_t vertex_count;
	size_t position_stride;
	/** Optional; NULL: angle-weighted normals computed from the positions in double. */
	const float *normals;
	size_t normal_stride;
	const uint32_t *indices; /**< triangle_count index triples into this mesh's vertices */
	size_t triangle_count;
	size_t index_stride;
	uint32_t material;           /**< id returned by rs_scene_add_material() */
	const double *positions_f64; /**< instead of positions: double xyz triples */
};

/** Pinhole camera. fov_y_deg is the paper's projection angle 2*atan(b/a). */
struct rs_camera {
	double eye[3];
	double target[3];
	double up[3];
	double fov_y_deg; /**< vertical field of view; 0 means 45 */
	/**
	 * Lens shift for off-axis frusta (a head-coupled view through a handheld screen): the
	 * image window's centre moves by shift[0] * b right and shift[1] * b up in the image
	 * plane at distance 1 along the view direction, b = tan(fov_y / 2). 0, 0: centred.
	 */
	double shift[2];
	uint32_t width, height; /**< image size the scene was framed for; 0 means 512 */
	/**
	 * Which sub-pixel sample of the pixels this frame's primary rays take (still-pose
	 * refinement, docs/view.md): 0 the pixel centres, n > 0 the centres moved by
	 * rs_trace_sample_offset(n). Averaging frames 0..N-1 gives an N-sample image.
	 */
	uint32_t sample;
};

/** A white-or-coloured point light without fall-off. */
struct rs_light {
	double position[3];
	double color[3]; /**< radiance scale per channel (1,1,1 = white, intensity 1) */
};

/**
 * The environment cube: rays leaving the scene are intersected with it (no parallax) and
 * take the colour there. Face order +x, -x, +y, -y, +z, -z. Each face shows a grid of
 * `grid` x `grid` cells whose lines (width line_width of a cell, centred on cell borders)
 * are the face colour times line_scale.
 */
struct rs_environment {
	double center[3];
	double half_size; /**< 0: derived from the scene bounds (2x largest extent) */
	float face_color[6][3];
	uint32_t grid;    /**< 0 means 16 */
	float line_width; /**< fraction of a cell; 0 means 0.06 */
	float line_scale; /**< 0 means 0.25 */
};

/** Axis-aligned bounds. */
struct rs_bounds {
	double lo[3];
	double hi[3];
};

struct rs_scene;

/** Scene options; zero-initialised means defaults. */
struct rs_scene_desc {
	size_t max_triangles; /**< refuse meshes beyond this total; 0 means 2^24 - 1 */
};

/**
 * Create an empty scene (no geometry; default camera, no lights, ambient 0.1, default
 * environment colours). Free with rs_scene_destroy().
 */
enum rs_status rs_scene_create(const struct rs_scene_desc *desc, struct rs_scene **out,
                               struct rs_error *err);

/** Free a scene and set *scene to NULL; NULL and *scene == NULL are allowed. */
void rs_scene_destroy(struct rs_scene **scene);

/** Add a material; its id (0, 1, ...) is written to out_id. Rejects NaN/negative values. */
enum rs_status rs_scene_add_material(struct rs_scene *scene, const struct rs_material *material,
                                     uint32_t *out_id, struct rs_error *err);

/**
 * Copy a mesh into the scene. Rejects (RS_ERR_BAD_DATA, nothing added) NaN or infinite
 * positions/normals, indices out of range, zero triangles, unknown material ids, and totals
 * beyond max_triangles. Zero-area triangles are kept (the tracers handle them).
 */
enum rs_status rs_scene_add_mesh(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                 struct rs_error *err);

/** Most prototypes (rs_scene_add_prototype) a scene holds. */
#define RS_SCENE_MAX_PROTOTYPES (1u << 20)

/**
 * An instance of a prototype mesh; zero-initialised is the identity transform of prototype 0
 * with the prototype's own material.
 */
struct rs_instance_desc {
	uint32_t mesh; /**< id returned by rs_scene_add_prototype() */
	/**
	 * Object -> world, 3x4 row-major: world = transform[.][0..2] * p + transform[.][3].
	 * All twelve values zero means the identity (so a zero descriptor is valid). Mirrors
	 * (negative determinant) are allowed; singular, NaN or infinite transforms are refused.
	 */
	double transform[3][4];
	bool override_material; /**< use `material` instead of the prototype's */
	uint32_t material; /**< id returned by rs_scene_add_material(), with override_material */
};

/** An instance as the scene keeps it (rs_scene_instances). */
struct rs_scene_instance {
	uint32_t mesh;           /**< prototype id */
	double transform[3][4];  /**< object -> world, resolved (never all zero) */
	double inverse[3][4];    /**< world -> object */
	uint32_t material;       /**< material of its triangles (the override or the prototype's) */
	uint32_t first_triangle; /**< its triangles are [first_triangle, + prototype's count) */
	uint32_t triangle_count;
};

/**
 * Copy a mesh in as a prototype for instances, in its own (object) space; it is not drawn by
 * itself, each of its instances is. Its id (0, 1, ...) is written to out_id. The
 * same checks and refusals as rs_scene_add_mesh() (the triangle limit applies to instances).
 */
enum rs_status rs_scene_add_prototype(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                      uint32_t *out_id, struct rs_error *err);

/**
 * Add an instance of a prototype; its id (0, 1, ...) is written to out_id (may be NULL).
 * Refuses (RS_ERR_BAD_DATA, nothing added, one-line message) a prototype or material id that
 * does not exist, a NaN or infinite transform, a singular one (|det A| <= 1e-12 * |A|^3 of its
 * 3x3 part A, max-norm), and vertices that would leave the float range. RS_ERR_LIMIT beyond
 * max_triangles.
 *
 * An instance is baked into the scene's world-space triangles when added (the scene's
 * triangle arrays, packing and both tracers see it as ordinary geometry): positions
 * transformed in double, normals by the inverse transpose and renormalised, and a mirrored
 * instance's triangles wound the other way (v1 <-> v2) so their geometric normals keep facing
 * out as the prototype's do. The instance records keep what a two-level (TLAS over
 * per-prototype BLAS) packing needs (rs_pack_instances(), docs/bvh.md "Instances").
 */
enum rs_status rs_scene_add_instance(struct rs_scene *scene, const struct rs_instance_desc *desc,
                                     uint32_t *out_id, struct rs_error *err);

/**
 * Move instance `id` (rs_scene_add_instance's id) for the next frame: `transform` (object ->
 * world, as rs_instance_desc.transform; all zero: the identity) replaces its transform, and
 * its baked world triangles are baked again from the prototype exactly as add_instance bakes
 * them (positions, normals by the inverse transpose; rs_scene_bounds() follows). Triangle
 * ids, indices and materials stay, so the scene keeps the topology that
 * rs_render_scene_same_topology() compares, and rs_renderer_update_instances() (or
 * update_vertices) takes it. Refuses (RS_ERR_BAD_DATA, one line, nothing changed) an unknown
 * id, the transforms add_instance refuses (NaN, infinite, singular, vertices out of float
 * range), and a change of mirroring (the sign of the determinant): a mirrored instance's
 * baked triangles are wound the other way, which is another topology (add a mirrored
 * instance instead). O(the instance's vertices); the scene's bounds are formed again from
 * per-instance boxes when asked (O(instances)).
 */
enum rs_status rs_scene_set_instance_transform(struct rs_scene *scene, uint32_t id,
                                               const double transform[3][4], struct rs_error *err);

/** Prototype `id` (< rs_scene_prototype_count) as a mesh description pointing into the scene
 * (double positions, normals, indices, material): valid until the scene changes. */
void rs_scene_prototype_mesh(const struct rs_scene *scene, uint32_t id, struct rs_mesh_desc *out);
size_t rs_scene_prototype_count(const struct rs_scene *scene);
size_t rs_scene_instance_count(const struct rs_scene *scene);
/** The instances in the order they were added (rs_scene_instance_count() of them). */
const struct rs_scene_instance *rs_scene_instances(const struct rs_scene *scene);

/** Set the camera (rejects eye == target, zero/parallel up, fov outside (0, 180)). */
enum rs_status rs_scene_set_camera(struct rs_scene *scene, const struct rs_camera *camera,
                                   struct rs_error *err);
/** Add a point light (rejects non-finite values or negative colour). */
enum rs_status rs_scene_add_light(struct rs_scene *scene, const struct rs_light *light,
                                  struct rs_error *err);
/** Set the environment cube (rejects non-finite values). */
enum rs_status rs_scene_set_environment(struct rs_scene *scene,
                                        const struct rs_environment *environment,
                                        struct rs_error *err);
/** Ambient term added to every lit surface (scaled by its diffuse colour); default 0.1. */
enum rs_status rs_scene_set_ambient(struct rs_scene *scene, double ambient, struct rs_error *err);

/* Read access. Pointers stay valid until the scene is changed or destroyed. */
size_t rs_scene_triangle_count(const struct rs_scene *scene);
size_t rs_scene_vertex_count(const struct rs_scene *scene);
/** xyz per vertex, tightly packed (the double positions rounded to float). */
const float *rs_scene_positions(const struct rs_scene *scene);
/** xyz per vertex in double: as given (positions_f64) or widened from float, exactly. */
const double *rs_scene_positions_f64(const struct rs_scene *scene);
/** Unit xyz per vertex (computed or given, renormalised), tightly packed. */
const float *rs_scene_normals(const struct rs_scene *scene);
/** Three vertex indices per triangle. */
const uint32_t *rs_scene_indices(const struct rs_scene *scene);
/** Material id per triangle. */
const uint32_t *rs_scene_triangle_materials(const struct rs_scene *scene);
size_t rs_scene_material_count(const struct rs_scene *scene);
const struct rs_material *rs_scene_materials(const struct rs_scene *scene);
size_t rs_scene_light_count(const struct rs_scene *scene);
const struct rs_light *rs_scene_lights(const struct rs_scene *scene);
const struct rs_camera *rs_scene_camera(const struct rs_scene *scene);
double rs_scene_ambient(const struct rs_scene *scene);
/** The environment with defaults resolved (centre/half-size from the bounds if unset). */
void rs_scene_environment(const struct rs_scene *scene, struct rs_environment *out);
/** Bounds of all vertices, from the double positions (lo > hi when the scene is empty). */
void rs_scene_bounds(const struct rs_scene *scene, struct rs_bounds *out);

/** A reflective object (rs_scene_reflective_objects): a connected group of mirror triangles
 * and a sphere that holds them, the capture point of its own cube map in inter-reflection
 * environment mapping (DIGEST.md 4.2). */
struct rs_scene_object {
	double center[3];        /**< centre of the group's bounding box */
	double radius;           /**< largest distance from `center` to one of its vertices */
	uint32_t material;       /**< material of its first triangle */
	uint32_t triangle_count; /**< triangles in the group */
};

/** rs_scene_reflective_objects: the object id of a triangle that reflects nothing. */
#define RS_SCENE_NO_OBJECT UINT32_MAX

/**
 * Group the triangles whose material has reflectance > 0 into objects: two such triangles
 * with the same material belong to one object when they share a vertex position (exactly,
 * so seams of duplicated vertices do not split a mesh). Objects are numbered in the order
 * of their lowest triangle. Writes the object of every triangle (RS_SCENE_NO_OBJECT for
 * the rest) to object_of_triangle (rs_scene_triangle_count() entries; may be NULL) and
 * the first `capacity` objects to `objects` (may be NULL when capacity is 0); *count gets
 * the number of objects. RS_ERR_LIMIT when there are more than `capacity` (object_of_triangle
 * and *count are still written), RS_ERR_NO_MEMORY when the scratch space cannot be had.
 */
enum rs_status rs_scene_reflective_objects(const struct rs_scene *scene,
                                           uint32_t *object_of_triangle,
                                           struct rs_scene_object *objects, size_t capacity,
                                           size_t *count, struct rs_error *err);

/**
 * Frame the camera the way the benchmark scenes do: look at the centre of `focus` from
 * `elevation_deg` above the horizontal on the +z side, at distance r / sin(fov_y / 2), with
 * r = half the box's diagonal, up +y. Writes *camera (fov/size fields are kept, 0 = default).
 */
void rs_camera_frame(const struct rs_bounds *focus, double elevation_deg, struct rs_camera *camera);

/** Check a camera as rs_scene_set_camera() does: RS_ERR_BAD_DATA for non-finite values,
 * eye == target, zero or parallel up, fov outside [0, 180); RS_ERR_LIMIT for a size > 16384. */
enum rs_status rs_camera_check(const struct rs_camera *camera, struct rs_error *err);

/** Resolved camera values: fov 45 and 512x512 where zero. */
void rs_camera_resolve(const struct rs_camera *in, struct rs_camera *out);

#ifdef __cplusplus
}
#endif
#endif
