/* rs_scene: validation of caller geometry, computed normals, camera and environment. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_scene.h"

/* Unit cube, each face split into two triangles; corner 0 is (0,0,0). */
static const float cube_pos[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                      0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_idx[12 * 3] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                          3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static struct rs_scene *make_scene(void)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	struct rs_material m = {.diffuse = {0.5f, 0.5f, 0.5f}};
	uint32_t id = 99;
	assert_int_equal(rs_scene_add_material(scene, &m, &id, NULL), RS_OK);
	assert_int_equal(id, 0);
	return scene;
}

static struct rs_mesh_desc cube_mesh(void)
{
	return (struct rs_mesh_desc){
	    .positions = cube_pos, .vertex_count = 8, .indices = cube_idx, .triangle_count = 12};
}

static void mesh_is_copied(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_mesh_desc mesh = cube_mesh();
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	assert_int_equal(rs_scene_triangle_count(scene), 24);
	assert_int_equal(rs_scene_vertex_count(scene), 16);
	/* The second copy's indices are offset to its own vertices. */
	assert_int_equal(rs_scene_indices(scene)[12 * 3], 8 + cube_idx[0]);
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	assert_true(b.lo[0] == 0.0 && b.hi[2] == 1.0);
	rs_scene_destroy(&scene);
	assert_null(scene);
}

/* Angle weighting: each cube face meets a corner at 90 degrees in total, whatever its
 * triangulation, so the corner normal is exactly the diagonal. */
static void normals_are_angle_weighted(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_mesh_desc mesh = cube_mesh();
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	const float *n = rs_scene_normals(scene);
	const double k = -1.0 / sqrt(3.0);
	for (int a = 0; a < 3; ++a)
		assert_true(fabs(n[a] - k) < 1e-6); /* vertex 0 at (0,0,0) points outwards */
	rs_scene_destroy(&scene);
}

/* Computed normals come from the double positions: a 1 mm cube 1e5 units from the origin
 * collapses in float (spacing 2^-10 there), so normals from the float rounding would point
 * anywhere; the doubles give each corner the exact diagonal, for a mesh and a prototype. */
static void computed_normals_use_double_positions(void **state)
{
	struct rs_scene *scene = make_scene();
	double pos[8 * 3];
	for (int i = 0; i < 8 * 3; ++i)
		pos[i] = 1e5 + 1e-3 * cube_pos[i];
	struct rs_mesh_desc mesh = cube_mesh();
	mesh.positions = NULL;
	mesh.positions_f64 = pos;
	uint32_t proto = 0;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, &proto, NULL), RS_OK);
	struct rs_mesh_desc copy;
	rs_scene_prototype_mesh(scene, proto, &copy);
	const float *normals[2] = {rs_scene_normals(scene), copy.normals};
	for (int m = 0; m < 2; ++m)
		for (int v = 0; v < 8; ++v)
			for (int a = 0; a < 3; ++a) { /* outwards: -1 on a side at 0, +1 at 1 */
				double k = (cube_pos[3 * v + a] > 0.5f ? 1.0 : -1.0) / sqrt(3.0);
				assert_true(fabs(normals[m][3 * v + a] - k) < 1e-6);
			}
	rs_scene_destroy(&scene);
}

/* positions_f64 are kept exactly (with a stride), their float rounding is what
 * rs_scene_positions() shows, and the bounds come from the doubles. */
static void double_positions_are_kept_exactly(void **state)
{
	struct rs_scene *scene = make_scene();
	double pos[8 * 4]; /* xyz plus one unused double per vertex: stride 32 bytes */
	for (int v = 0; v < 8; ++v) {
		for (int a = 0; a < 3; ++a)
			pos[4 * v + a] = 1e6 + cube_pos[3 * v + a] * (1.0 + 1e-9);
		pos[4 * v + 3] = NAN; /* never read */
	}
	struct rs_mesh_desc mesh = cube_mesh();
	mesh.positions = NULL;
	mesh.positions_f64 = pos;
	mesh.position_stride = 4 * sizeof(double);
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	const double *p = rs_scene_positions_f64(scene);
	const float *f = rs_scene_positions(scene);
	for (int v = 0; v < 8; ++v)
		for (int a = 0; a < 3; ++a) {
			assert_true(p[3 * v + a] == pos[4 * v + a]);
			assert_true(f[3 * v + a] == (float)pos[4 * v + a]);
		}
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	assert_true(b.lo[0] == 1e6 && b.hi[0] == 1e6 + (1.0 + 1e-9));
	/* float input is widened exactly */
	mesh = cube_mesh();
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	p = rs_scene_positions_f64(scene);
	for (int i = 0; i < 8 * 3; ++i)
		assert_true(p[8 * 3 + i] == (double)cube_pos[i]);
	rs_scene_destroy(&scene);
}

/* Exactly one of positions / positions_f64; a double beyond float range is bad data. */
static void double_positions_are_validated(void **state)
{
	struct rs_scene *scene = make_scene();
	double pos[8 * 3];
	for (int i = 0; i < 8 * 3; ++i)
		pos[i] = cube_pos[i];
	struct rs_mesh_desc mesh = cube_mesh();
	mesh.positions_f64 = pos; /* and positions: both given */
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_ERR_INVALID);
	mesh.positions = NULL;
	mesh.positions_f64 = NULL; /* neither */
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_ERR_INVALID);
	pos[7] = 1e39; /* vertex 2 would round to an infinite float */
	mesh.positions_f64 = pos;
	struct rs_error err;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "vertex 2"));
	pos[7] = NAN;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_ERR_BAD_DATA);
	assert_int_equal(rs_scene_triangle_count(scene), 0);
	rs_scene_destroy(&scene);
}

static void nan_vertex_is_rejected(void **state)
{
	struct rs_scene *scene = make_scene();
	float pos[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
	uint32_t idx[3] = {0, 1, 2};
	struct rs_mesh_desc mesh = {
	    .positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};
	struct rs_error err;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, &err), RS_ERR_BAD_DATA);
	assert_int_equal(err.status, RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "vertex 2"));
	assert_int_equal(rs_scene_triangle_count(scene), 0);
	rs_scene_destroy(&scene);
}

static void index_out_of_range_is_rejected(void **state)
{
	struct rs_scene *scene = make_scene();
	float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	uint32_t idx[3] = {0, 1, 3};
	struct rs_mesh_desc mesh = {
	    .positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};
	struct rs_error err;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "triangle 0"));
	rs_scene_destroy(&scene);
}

static void zero_triangles_and_unknown_material_are_rejected(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_mesh_desc mesh = cube_mesh();
	mesh.triangle_count = 0;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_ERR_BAD_DATA);
	mesh = cube_mesh();
	mesh.material = 5;
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_ERR_BAD_DATA);
	rs_scene_destroy(&scene);
}

static void degenerate_triangle_gets_finite_normals(void **state)
{
	struct rs_scene *scene = make_scene();
	float pos[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1};
	uint32_t idx[3] = {0, 1, 2};
	struct rs_mesh_desc mesh = {
	    .positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	for (int i = 0; i < 9; ++i)
		assert_true(isfinite(rs_scene_normals(scene)[i]));
	rs_scene_destroy(&scene);
}

static void bad_camera_is_rejected(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_camera cam = {.eye = {0, 0, 5}, .target = {0, 0, 0}, .up = {0, 0, 1}};
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_ERR_BAD_DATA); /* up parallel */
	cam.up[1] = 1;
	cam.up[2] = 0;
	cam.fov_y_deg = 200;
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_ERR_BAD_DATA);
	cam.fov_y_deg = 0;
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_OK);
	rs_scene_destroy(&scene);
}

/* eye 1e308 and target -1e308 are finite but their difference is not: the up/parallel
 * checks then compared NaN and let the camera through. */
static void camera_with_infinite_view_vector_is_rejected(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_camera cam = {.eye = {1e308, 0, 5}, .target = {-1e308, 0, 0}, .up = {0, 1, 0}};
	struct rs_error err;
	assert_int_equal(rs_scene_set_camera(scene, &cam, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "too large"));
	rs_scene_destroy(&scene);
}

/* The bounds of an empty scene (lo = +inf, hi = -inf) must not put NaN into the camera. */
static void camera_frame_of_empty_bounds_is_finite(void **state)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	struct rs_bounds empty;
	rs_scene_bounds(scene, &empty);
	struct rs_camera cam = {0};
	rs_camera_frame(&empty, 30.0, &cam);
	for (int a = 0; a < 3; ++a)
		assert_true(isfinite(cam.eye[a]) && isfinite(cam.target[a]));
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_OK);
	rs_scene_destroy(&scene);
}

/* The view cone of half-angle fov/2 touches the bounding sphere: distance r / sin(fov/2). */
static void camera_frame_touches_bounding_sphere(void **state)
{
	struct rs_bounds box = {.lo = {-1, -2, -3}, .hi = {3, 2, 1}};
	struct rs_camera cam = {.fov_y_deg = 45};
	rs_camera_frame(&box, 30.0, &cam);
	double r = 0.5 * sqrt(16.0 + 16.0 + 16.0);
	double d = sqrt(pow(cam.eye[0] - 1, 2) + pow(cam.eye[1] - 0, 2) + pow(cam.eye[2] + 1, 2));
	assert_true(fabs(d - r / sin(22.5 * RS_PI / 180.0)) < 1e-12);
	assert_true(fabs(atan2(cam.eye[1], cam.eye[2] + 1) - RS_PI / 6) < 1e-12);
}

static void environment_defaults_follow_bounds(void **state)
{
	struct rs_scene *scene = make_scene();
	struct rs_mesh_desc mesh = cube_mesh();
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	struct rs_environment env;
	rs_scene_environment(scene, &env);
	assert_true(env.center[0] == 0.5 && env.half_size == 2.0 && env.grid == 16);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(mesh_is_copied),
	    cmocka_unit_test(normals_are_angle_weighted),
	    cmocka_unit_test(computed_normals_use_double_positions),
	    cmocka_unit_test(double_positions_are_kept_exactly),
	    cmocka_unit_test(double_positions_are_validated),
	    cmocka_unit_test(nan_vertex_is_rejected),
	    cmocka_unit_test(index_out_of_range_is_rejected),
	    cmocka_unit_test(zero_triangles_and_unknown_material_are_rejected),
	    cmocka_unit_test(degenerate_triangle_gets_finite_normals),
	    cmocka_unit_test(bad_camera_is_rejected),
	    cmocka_unit_test(camera_with_infinite_view_vector_is_rejected),
	    cmocka_unit_test(camera_frame_of_empty_bounds_is_finite),
	    cmocka_unit_test(camera_frame_touches_bounding_sphere),
	    cmocka_unit_test(environment_defaults_follow_bounds),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
