/* The scene's private layout, shared by the files of lib/scene only. */
#ifndef RS_SCENE_INTERNAL_H
#define RS_SCENE_INTERNAL_H

#include "raystream/rs_scene.h"

/* A prototype mesh as copied in: double positions, unit normals, local indices. */
struct rs_scene_prototype {
	double *positions;
	float *normals;
	uint32_t *indices;
	size_t vertex_count, triangle_count;
	uint32_t material;
};

struct rs_scene {
	size_t max_triangles;

	float *positions;
	double *positions_f64; /* the positions as given; packing subtracts the centre from these */
	float *normals;
	uint32_t *indices;
	uint32_t *triangle_materials;
	size_t vertex_count, triangle_count;
	size_t position_capacity, position_f64_capacity, normal_capacity, index_capacity,
	    triangle_material_capacity;
	struct rs_bounds bounds;

	struct rs_material *materials;
	size_t material_count, material_capacity;
	struct rs_light *lights;
	size_t light_count, light_capacity;

	/* Prototypes (object space) and the instances baked from them (rs_scene_add_instance). */
	struct rs_scene_prototype *prototypes;
	size_t prototype_count, prototype_capacity;
	struct rs_scene_instance *instances;
	size_t instance_count, instance_capacity;
	/* Bounds kept apart so moving an instance (rs_scene_set_instance_transform) costs its own
	 * vertices, not the scene's: instance_bounds[i] is instance i's baked world box,
	 * mesh_bounds those of every vertex added by rs_scene_add_mesh() itself. `bounds` is
	 * their union, stale while bounds_stale (rs_scene_bounds() then forms it, O(instances)). */
	struct rs_bounds *instance_bounds;
	size_t instance_bounds_capacity;
	struct rs_bounds mesh_bounds;
	bool bounds_stale;

	struct rs_camera camera;
	struct rs_environment environment;
	double ambient;
};

/*
 * Angle-weighted vertex normals (Thuermer & Wuethrich) for `triangle_count` triangles whose
 * global indices point into `positions`; vertices [first_vertex, first_vertex + count)
 * get their normals written to out (count * 3 floats). Returns 0 when out of scratch memory.
 */
int rs_scene_angle_weighted_normals(const double *positions, const uint32_t *indices,
                                    size_t triangle_count, size_t first_vertex, size_t vertex_count,
                                    float *out);

/* Shared by scene.c and scene_instances.c: vertex i of a mesh description in double, the
 * checks of rs_scene_add_mesh(), and growing an array to `count` elements (0: no memory). */
void rs__scene_mesh_position(const struct rs_mesh_desc *mesh, size_t i, double out[3]);
enum rs_status rs__scene_validate_mesh(const struct rs_scene *scene,
                                       const struct rs_mesh_desc *mesh, struct rs_error *err);
int rs__scene_grow(void **array, size_t *capacity, size_t count, size_t size);
/* rs_scene_add_mesh() without touching mesh_bounds: the box of the added vertices goes to
 * *added instead (the whole-scene bounds are kept either way). */
enum rs_status rs__scene_append_mesh(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                     struct rs_bounds *added, struct rs_error *err);
/* Grow `b` to hold p (an empty box has lo > hi). */
void rs__scene_bounds_add(struct rs_bounds *b, const double p[3]);

/* Renormalise normals in place; zero-length ones become (0, 1, 0) so none is NaN. */
void rs_scene_normalize_normals(float *normals, size_t count);

#endif
