/* Instanced test scenes shared by test_trace_instances.c and test_gl_two_level.c: a squashed
 * UV sphere prototype, plain floors (the loose BLAS's triangles), a scene with one material
 * and a rotation * scale + translation transform. Included by tests only, after cmocka.h. */
#ifndef TEST_INSTANCES_SHAPES_H
#define TEST_INSTANCES_SHAPES_H

#include <math.h>
#include <string.h>

#include "raystream/rs_scene.h"

#define SPHERE_RINGS 8
#define SPHERE_SEGMENTS 12

/* The UV sphere's vertex and index arrays (curved silhouettes), wound outward, slightly
 * squashed so rotations show; sizes SPHERE_VERTICES and SPHERE_TRIANGLES. */
#define SPHERE_VERTICES ((SPHERE_RINGS + 1) * SPHERE_SEGMENTS)
#define SPHERE_TRIANGLES (SPHERE_RINGS * SPHERE_SEGMENTS * 2)
static inline void sphere_arrays(double pos[SPHERE_VERTICES * 3],
                                 uint32_t idx[SPHERE_TRIANGLES * 3])
{
	size_t nv = 0, nt = 0;
	for (int r = 0; r <= SPHERE_RINGS; r++)
		for (int s = 0; s < SPHERE_SEGMENTS; s++) {
			double th = RS_PI * r / SPHERE_RINGS,
			       ph = 2.0 * RS_PI * s / SPHERE_SEGMENTS;
			pos[nv * 3] = sin(th) * cos(ph);
			pos[nv * 3 + 1] = 0.7 * cos(th);
			pos[nv * 3 + 2] = sin(th) * sin(ph) + 0.2 * sin(th);
			nv++;
		}
	for (uint32_t r = 0; r < SPHERE_RINGS; r++)
		for (uint32_t s = 0; s < SPHERE_SEGMENTS; s++) {
			uint32_t a = r * SPHERE_SEGMENTS + s,
			         b = r * SPHERE_SEGMENTS + (s + 1) % SPHERE_SEGMENTS,
			         c = a + SPHERE_SEGMENTS, d = b + SPHERE_SEGMENTS;
			const uint32_t t[6] = {a, b, c, b, d, c};
			memcpy(idx + nt * 3, t, sizeof t);
			nt += 2;
		}
}

/* The sphere as a prototype of `scene`. */
static inline uint32_t add_sphere(struct rs_scene *scene)
{
	double pos[SPHERE_VERTICES * 3];
	uint32_t idx[SPHERE_TRIANGLES * 3];
	sphere_arrays(pos, idx);
	size_t nv = SPHERE_VERTICES, nt = SPHERE_TRIANGLES;
	struct rs_mesh_desc mesh = {
	    .positions_f64 = pos, .vertex_count = nv, .indices = idx, .triangle_count = nt};
	uint32_t id;
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, &id, NULL), RS_OK);
	return id;
}

/* A plain (not instanced) quad at height y, x and z in [-6, 6]: the loose BLAS's. */
static inline void add_floor(struct rs_scene *scene, double y, uint32_t material)
{
	const double p[4 * 3] = {-6, y, -6, 6, y, -6, 6, y, 6, -6, y, 6};
	const uint32_t i[6] = {0, 2, 1, 0, 3, 2};
	struct rs_mesh_desc mesh = {.positions_f64 = p,
	                            .vertex_count = 4,
	                            .indices = i,
	                            .triangle_count = 2,
	                            .material = material};
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
}

static inline struct rs_scene *new_scene(void)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	struct rs_material m = {.diffuse = {0.5f, 0.5f, 0.5f}};
	assert_int_equal(rs_scene_add_material(scene, &m, NULL, NULL), RS_OK);
	return scene;
}

/* Rotation about axis (normalised here) by angle, times per-axis scale, plus translation. */
static inline void make_transform(const double axis[3], double angle, const double scale[3],
                                  const double move[3], double m[3][4])
{
	double l = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
	double x = axis[0] / l, y = axis[1] / l, z = axis[2] / l, c = cos(angle), s = sin(angle),
	       k = 1.0 - c;
	const double r[3][3] = {{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
	                        {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
	                        {z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			m[i][j] = r[i][j] * scale[j];
		m[i][3] = move[i];
	}
}

#endif
