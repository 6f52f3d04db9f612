/* Shared by the instance-update tests: a scene of instances of one squashed sphere (curved
 * silhouettes, so rotations show) over a plain floor, with a light and a framed camera, and
 * the transforms of its frame k (a pure function of k: each instance turns and slides; the
 * fourth is mirrored at every frame). */
#ifndef TEST_INSTANCES_FIXTURE_H
#define TEST_INSTANCES_FIXTURE_H

#include <math.h>
#include <string.h>

#include "raystream/rs_scene.h"
#include "test_instances_shapes.h"

#define FIX_INSTANCES 6u

/* Instance i's transform at frame k: a turn about a tilted axis, a scale, a slide. */
static inline void fix_transform(uint32_t i, uint32_t k, double m[3][4])
{
	double ax[3] = {0.3 * i, 1.0, 0.2}, l = sqrt(ax[0] * ax[0] + 1.0 + 0.04);
	double x = ax[0] / l, y = ax[1] / l, z = ax[2] / l;
	double a = 0.4 * i + 0.3 * k, c = cos(a), s = sin(a), t = 1.0 - c;
	const double r[3][3] = {{c + x * x * t, x * y * t - z * s, x * z * t + y * s},
	                        {y * x * t + z * s, c + y * y * t, y * z * t - x * s},
	                        {z * x * t - y * s, z * y * t + x * s, c + z * z * t}};
	double scale[3] = {1.0, 0.6 + 0.1 * i, 1.0};
	if (i == 3)
		scale[0] = -1.0; /* mirrored, every frame */
	for (int row = 0; row < 3; row++) {
		for (int col = 0; col < 3; col++)
			m[row][col] = r[row][col] * scale[col];
	}
	m[0][3] = -5.0 + 2.0 * i + 0.5 * sin(0.7 * k + i);
	m[1][3] = 1.0 + 0.25 * k * (i % 2);
	m[2][3] = -1.0 + 0.4 * cos(0.5 * k + i);
}

/* The scene at frame k with n instances (baked by rs_scene_add_instance), its floor at y. */
static inline struct rs_scene *fix_scene_with(uint32_t k, double y, uint32_t n)
{
	struct rs_scene *scene = NULL;
	if (rs_scene_create(NULL, &scene, NULL) != RS_OK)
		return NULL;
	const struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}, .specular = 0.3f};
	const struct rs_material red = {.diffuse = {0.8f, 0.2f, 0.1f}, .reflectance = 0.3f};
	rs_scene_add_material(scene, &grey, NULL, NULL);
	rs_scene_add_material(scene, &red, NULL, NULL);
	double pos[SPHERE_VERTICES * 3];
	uint32_t idx[SPHERE_TRIANGLES * 3];
	sphere_arrays(pos, idx);
	size_t nv = SPHERE_VERTICES, nt = SPHERE_TRIANGLES;
	struct rs_mesh_desc sphere = {.positions_f64 = pos,
	                              .vertex_count = nv,
	                              .indices = idx,
	                              .triangle_count = nt,
	                              .material = 1};
	uint32_t proto = 0;
	rs_scene_add_prototype(scene, &sphere, &proto, NULL);
	const double fp[4 * 3] = {-8, y, -5, 8, y, -5, 8, y, 5, -8, y, 5};
	const uint32_t fi[6] = {0, 2, 1, 0, 3, 2};
	struct rs_mesh_desc floor = {
	    .positions_f64 = fp, .vertex_count = 4, .indices = fi, .triangle_count = 2};
	for (uint32_t i = 0; i < n; i++) {
		if (i == 2) /* plain triangles between instances */
			rs_scene_add_mesh(scene, &floor, NULL);
		struct rs_instance_desc d = {.mesh = proto, .override_material = i == 1};
		fix_transform(i, k, d.transform);
		if (rs_scene_add_instance(scene, &d, NULL, NULL) != RS_OK) {
			rs_scene_destroy(&scene);
			return NULL;
		}
	}
	const struct rs_light light = {.position = {2.0, 9.0, 6.0}, .color = {1.0, 1.0, 1.0}};
	rs_scene_add_light(scene, &light, NULL);
	struct rs_camera cam = {.eye = {0.0, 4.0, 14.0}, .up = {0.0, 1.0, 0.0}, .fov_y_deg = 50.0};
	rs_scene_set_camera(scene, &cam, NULL);
	return scene;
}

/* The scene at frame k with its floor at y. */
static inline struct rs_scene *fix_scene_floor(uint32_t k, double y)
{
	return fix_scene_with(k, y, FIX_INSTANCES);
}

/* The scene at frame k with its floor at y = -1. */
static inline struct rs_scene *fix_scene(uint32_t k)
{
	return fix_scene_floor(k, -1.0);
}

/* Move every instance of `scene` (made by fix_scene) to frame k in place. */
static inline enum rs_status fix_move(struct rs_scene *scene, uint32_t k)
{
	for (uint32_t i = 0; i < FIX_INSTANCES; i++) {
		double m[3][4];
		fix_transform(i, k, m);
		enum rs_status st = rs_scene_set_instance_transform(scene, i, m, NULL);
		if (st != RS_OK)
			return st;
	}
	return RS_OK;
}

#endif
