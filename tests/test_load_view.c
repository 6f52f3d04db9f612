/* rs_load view files (JSON camera/lights/environment/ambient) and rs_load_scene's sidecar
 * handling and default framing. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"
#include "test_load_fixture.h"

static const char tri_obj[] = "v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n";

static struct rs_scene *new_scene(void)
{
	struct rs_scene *s = NULL;

	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	return s;
}

/* A scene with awkward doubles everywhere, so bit-exact round trips are meaningful. */
static struct rs_scene *decorated_scene(void)
{
	struct rs_scene *s = new_scene();
	struct rs_camera cam = {.eye = {0.1, 1.0 / 3.0, 7.25e-3},
	                        .target = {-2.5, 1e-9, 3.14159265358979},
	                        .up = {0.0, 1.0, 0.0},
	                        .fov_y_deg = 38.5,
	                        .width = 640,
	                        .height = 480};
	struct rs_light l1 = {{-10.0, 25.0, 1.0 / 7.0}, {1.0, 1.0, 1.0}};
	struct rs_light l2 = {{15.0, 2e10, -0.3}, {0.25, 0.5, 2.0}};
	struct rs_environment env = {.center = {1.0 / 3.0, 2.0, -4.0},
	                             .half_size = 33.3,
	                             .grid = 8,
	                             .line_width = 0.1f,
	                             .line_scale = 0.3f};

	for (int f = 0; f < 6; f++)
		for (int k = 0; k < 3; k++)
			env.face_color[f][k] = 0.1f * (float)(f + 1) + 0.01f * (float)k;
	assert_int_equal(rs_scene_set_camera(s, &cam, NULL), RS_OK);
	assert_int_equal(rs_scene_add_light(s, &l1, NULL), RS_OK);
	assert_int_equal(rs_scene_add_light(s, &l2, NULL), RS_OK);
	assert_int_equal(rs_scene_set_environment(s, &env, NULL), RS_OK);
	assert_int_equal(rs_scene_set_ambient(s, 0.123456789, NULL), RS_OK);
	return s;
}

static enum rs_status load_view_text(const char *text, struct rs_scene *s, struct rs_error *err)
{
	struct fx fx;
	enum rs_status st;

	fx_init(&fx);
	rs_error_clear(err);
	st = rs_load_view_file(fx_write(&fx, "v.json", text), s, err);
	fx_cleanup(&fx);
	return st;
}

static void view_round_trip_is_bit_exact(void **state)
{
	struct rs_scene *a = decorated_scene(), *b = new_scene();
	struct rs_environment ea, eb;
	char *text = NULL;

	assert_int_equal(rs_load_view_format(a, &text, NULL), RS_OK);
	assert_int_equal(load_view_text(text, b, &(struct rs_error){0}), RS_OK);
	rs_free(text);
	assert_memory_equal(rs_scene_camera(a), rs_scene_camera(b), sizeof(struct rs_camera));
	assert_int_equal(rs_scene_light_count(b), 2);
	assert_memory_equal(rs_scene_lights(a), rs_scene_lights(b), 2 * sizeof(struct rs_light));
	rs_scene_environment(a, &ea);
	rs_scene_environment(b, &eb);
	assert_memory_equal(&ea, &eb, sizeof(ea));
	assert_true(rs_scene_ambient(a) == rs_scene_ambient(b));
	rs_scene_destroy(&a);
	rs_scene_destroy(&b);
}

static void members_are_optional(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_camera before = *rs_scene_camera(s);
	struct rs_error err;

	assert_int_equal(load_view_text("{\"ambient\": 0.5}", s, &err), RS_OK);
	assert_true(rs_scene_ambient(s) == 0.5);
	assert_memory_equal(&before, rs_scene_camera(s), sizeof(before));
	assert_int_equal(rs_scene_light_count(s), 0);
	rs_scene_destroy(&s);
}

static void light_colour_defaults_to_white(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(load_view_text("{\"lights\": [{\"position\": [1, 2, 3]}]}", s, &err),
	                 RS_OK);
	assert_int_equal(rs_scene_light_count(s), 1);
	assert_true(rs_scene_lights(s)[0].color[0] == 1.0 && rs_scene_lights(s)[0].color[2] == 1.0);
	rs_scene_destroy(&s);
}

static void malformed_json_is_parse_error(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(load_view_text("{\"camera\": {\"eye\": [1, 2,", s, &err), RS_ERR_PARSE);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "malformed JSON"));
	rs_scene_destroy(&s);
}

static void wrong_shape_names_the_member(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(
	    load_view_text("{\"camera\": {\"eye\": [1, 2], \"target\": [0, 0, 0]}}", s, &err),
	    RS_ERR_PARSE);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "camera.eye"));
	rs_scene_destroy(&s);
}

/* 1e999 parses to infinity: refused like any non-finite number. */
static void infinite_number_is_parse_error(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(load_view_text("{\"ambient\": 1e999}", s, &err), RS_ERR_PARSE);
	assert_non_null(strstr(err.message, "ambient"));
	rs_scene_destroy(&s);
}

static void unknown_version_is_unsupported(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(
	    load_view_text("{\"format\": \"raystream-view\", \"version\": 9}", s, &err),
	    RS_ERR_UNSUPPORTED);
	assert_one_line(&err);
	rs_scene_destroy(&s);
}

/* The camera is valid but the light is not: nothing may be applied (no partial view). */
static void rejected_value_changes_nothing(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_camera before = *rs_scene_camera(s);
	struct rs_error err;

	assert_int_not_equal(
	    load_view_text("{\"camera\": {\"eye\": [0, 0, 9], \"target\": [0, 0, 0]},"
	                   " \"lights\": [{\"position\": [0, 5, 0], \"color\": [-1, 0, 0]}]}",
	                   s, &err),
	    RS_OK);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "lights"));
	assert_memory_equal(&before, rs_scene_camera(s), sizeof(before));
	assert_int_equal(rs_scene_light_count(s), 0);
	rs_scene_destroy(&s);
}

static void missing_view_file_is_not_found(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(rs_load_view_file("/nonexistent/v.json", s, &err), RS_ERR_NOT_FOUND);
	assert_one_line(&err);
	rs_scene_destroy(&s);
}

static void sidecar_path_replaces_the_extension(void **state)
{
	char out[64];

	assert_int_equal(rs_load_sidecar_path("a/b.obj", out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, "a/b.json");
	assert_int_equal(rs_load_sidecar_path("dir.d/mesh", out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, "dir.d/mesh.json");
	assert_int_equal(rs_load_sidecar_path(".hidden", out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, ".hidden.json");
	assert_int_equal(rs_load_sidecar_path("abc.ply", out, 8, NULL), RS_ERR_LIMIT);
}

static void load_scene_reads_the_sidecar(void **state)
{
	struct fx fx;
	struct rs_scene *s = NULL;

	fx_init(&fx);
	fx_write(&fx, "m.json",
	         "{\"camera\": {\"eye\": [0, 0, 9], \"target\": [0, 0, 0], \"fov_y_deg\": 30},"
	         " \"lights\": [{\"position\": [4, 5, 6]}]}");
	assert_int_equal(rs_load_scene(NULL, fx_write(&fx, "m.obj", tri_obj), &s, NULL), RS_OK);
	fx_cleanup(&fx);
	assert_int_equal(rs_scene_triangle_count(s), 1);
	assert_true(rs_scene_camera(s)->eye[2] == 9.0 && rs_scene_camera(s)->fov_y_deg == 30.0);
	assert_int_equal(rs_scene_light_count(s), 1);
	assert_true(rs_scene_lights(s)[0].position[1] == 5.0);
	rs_scene_destroy(&s);
}

/* Without a sidecar: rs_camera_frame(bounds, 30) and one light at centre + L1's offset
 * (the triangle's diagonal, ~2.2, is far below |L1 offset| ~ 33.5: no stretching). */
static void load_scene_frames_without_sidecar(void **state)
{
	struct fx fx;
	struct rs_scene *s = NULL;
	struct rs_camera want = {.fov_y_deg = 45.0, .width = 512, .height = 512};
	struct rs_bounds b;

	fx_init(&fx);
	assert_int_equal(rs_load_scene(NULL, fx_write(&fx, "m.obj", tri_obj), &s, NULL), RS_OK);
	fx_cleanup(&fx);
	rs_scene_bounds(s, &b);
	rs_camera_frame(&b, 30.0, &want);
	assert_memory_equal(rs_scene_camera(s)->eye, want.eye, sizeof(want.eye));
	assert_memory_equal(rs_scene_camera(s)->target, want.target, sizeof(want.target));
	assert_int_equal(rs_scene_light_count(s), 1);
	assert_near(rs_scene_lights(s)[0].position[0], 1.0 - 10.0, 1e-12);
	assert_near(rs_scene_lights(s)[0].position[1], 0.5 + 25.0, 1e-12);
	assert_near(rs_scene_lights(s)[0].position[2], 0.0 + 20.0, 1e-12);
	rs_scene_destroy(&s);
}

static void bad_sidecar_fails_the_load(void **state)
{
	struct fx fx;
	struct rs_scene *s = (struct rs_scene *)&fx; /* must be reset to NULL */
	struct rs_error err;

	fx_init(&fx);
	fx_write(&fx, "m.json", "{not json");
	assert_int_equal(rs_load_scene(NULL, fx_write(&fx, "m.obj", tri_obj), &s, &err),
	                 RS_ERR_PARSE);
	fx_cleanup(&fx);
	assert_null(s);
	assert_non_null(strstr(err.message, "m.json"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(view_round_trip_is_bit_exact),
	    cmocka_unit_test(members_are_optional),
	    cmocka_unit_test(light_colour_defaults_to_white),
	    cmocka_unit_test(malformed_json_is_parse_error),
	    cmocka_unit_test(wrong_shape_names_the_member),
	    cmocka_unit_test(infinite_number_is_parse_error),
	    cmocka_unit_test(unknown_version_is_unsupported),
	    cmocka_unit_test(rejected_value_changes_nothing),
	    cmocka_unit_test(missing_view_file_is_not_found),
	    cmocka_unit_test(sidecar_path_replaces_the_extension),
	    cmocka_unit_test(load_scene_reads_the_sidecar),
	    cmocka_unit_test(load_scene_frames_without_sidecar),
	    cmocka_unit_test(bad_sidecar_fails_the_load),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
