/* rs_scene_reflective_objects: mirror triangles grouped into objects by shared positions
 * (inter-reflection environment mapping captures one cube map per object). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_scene.h"

static const double cube_pos[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                       0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_idx[12 * 3] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                          3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

/* A unit cube moved by `dx` along x. */
static void add_cube(struct rs_scene *s, double dx, uint32_t material)
{
	double pos[8 * 3];
	memcpy(pos, cube_pos, sizeof(pos));
	for (int v = 0; v < 8; ++v)
		pos[3 * v] += dx;
	struct rs_mesh_desc m = {.positions_f64 = pos,
	                         .vertex_count = 8,
	                         .indices = cube_idx,
	                         .triangle_count = 12,
	                         .material = material};
	assert_int_equal(rs_scene_add_mesh(s, &m, NULL), RS_OK);
}

/* Scene: diffuse cube at 0, mirror cube at 3, mirror cube at 6 (triangles 0-11, 12-23,
 * 24-35). */
static struct rs_scene *two_mirrors(void)
{
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}}, mirror = {.reflectance = 0.8f};
	uint32_t g, m;
	assert_int_equal(rs_scene_add_material(s, &grey, &g, NULL), RS_OK);
	assert_int_equal(rs_scene_add_material(s, &mirror, &m, NULL), RS_OK);
	add_cube(s, 0.0, g);
	add_cube(s, 3.0, m);
	add_cube(s, 6.0, m);
	return s;
}

static void mirrors_become_one_object_each(void **state)
{
	(void)state;
	struct rs_scene *s = two_mirrors();
	uint32_t of[36];
	struct rs_scene_object o[4];
	size_t n = 0;
	assert_int_equal(rs_scene_reflective_objects(s, of, o, 4, &n, NULL), RS_OK);
	assert_int_equal(n, 2);
	for (int t = 0; t < 36; ++t)
		assert_int_equal(of[t], t < 12 ? RS_SCENE_NO_OBJECT : (uint32_t)(t / 12 - 1));
	for (int i = 0; i < 2; ++i) {
		assert_int_equal(o[i].triangle_count, 12);
		assert_int_equal(o[i].material, 1);
		assert_true(fabs(o[i].center[0] - (3.5 + 3.0 * i)) < 1e-12);
		assert_true(fabs(o[i].center[1] - 0.5) < 1e-12 &&
		            fabs(o[i].center[2] - 0.5) < 1e-12);
		assert_true(fabs(o[i].radius - sqrt(0.75)) < 1e-12);
	}
	rs_scene_destroy(&s);
}

/* Two triangles that share an edge by position only (a seam of repeated vertices) are one
 * object; moved apart by 1e-9 they are two. */
static void seams_of_repeated_vertices_do_not_split(void **state)
{
	(void)state;
	for (int apart = 0; apart < 2; ++apart) {
		struct rs_scene *s = NULL;
		assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
		struct rs_material mirror = {.reflectance = 1.0f};
		uint32_t m;
		assert_int_equal(rs_scene_add_material(s, &mirror, &m, NULL), RS_OK);
		double e = apart ? 1e-9 : 0.0;
		/* The second triangle's first and third corners repeat the first's second and
		 * third (new vertices, same positions, unless moved by e). */
		double pos[6 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1 + e, 0, 0, 1, 1, 0, 0, 1 + e, 0};
		uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
		struct rs_mesh_desc d = {
		    .positions_f64 = pos, .vertex_count = 6, .indices = idx, .triangle_count = 2};
		assert_int_equal(rs_scene_add_mesh(s, &d, NULL), RS_OK);
		size_t n = 0;
		uint32_t of[2];
		struct rs_scene_object o[2];
		assert_int_equal(rs_scene_reflective_objects(s, of, o, 2, &n, NULL), RS_OK);
		assert_int_equal(n, apart ? 2 : 1);
		assert_int_equal(of[0], 0);
		assert_int_equal(of[1], apart ? 1 : 0);
		rs_scene_destroy(&s);
	}
}

static void too_many_objects_is_a_limit(void **state)
{
	(void)state;
	struct rs_scene *s = two_mirrors();
	uint32_t of[36];
	struct rs_scene_object o[1];
	size_t n = 0;
	struct rs_error err = {0};
	assert_int_equal(rs_scene_reflective_objects(s, of, o, 1, &n, &err), RS_ERR_LIMIT);
	assert_int_equal(n, 2);
	assert_non_null(strstr(err.message, "2 reflective objects"));
	assert_int_equal(o[0].triangle_count, 12);
	assert_int_equal(of[35], 1);
	rs_scene_destroy(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(mirrors_become_one_object_each),
	    cmocka_unit_test(seams_of_repeated_vertices_do_not_split),
	    cmocka_unit_test(too_many_objects_is_a_limit),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
