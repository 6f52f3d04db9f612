/* Cube map captures rendered on the GPU (RS_REFLECT_ENVMAP, _INTERREFLECT, docs/gles.md):
 * every face of the classic map holds what the tracer sees in its direction (a face left
 * black, turned or swapped fails), the GPU path gives the same images as the readback path
 * it replaced (the fallback, forced through the test seam) at the same face size, the face
 * size is an option with a range, and on the mirrors scene a second bounce changes the
 * image (the bounces ping-pong between two sets of maps). */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../backends/gles/gles_seams.h"
#include "test_gl_common.h"

#define SIZE 32u
#define PIXELS (SIZE * SIZE * 3)

/* A mirror sphere (radius 0.5 at the origin) and a tiny grey triangle near (3.5, 3.5, 3.5),
 * which puts the capture point (the bounds' centre) at about (1.5, 1.5, 1.5): off every
 * axis through the sphere, so the map sees the environment in each axis direction. The
 * environment's six faces are plain colours centred on the capture point. */
static struct rs_scene *axis_sphere(void)
{
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	static const struct rs_material mirror = {.reflectance = 1.0f};
	static const struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}};
	uint32_t m_mirror, m_grey;
	assert_int_equal(rs_scene_add_material(s, &mirror, &m_mirror, NULL), RS_OK);
	assert_int_equal(rs_scene_add_material(s, &grey, &m_grey, NULL), RS_OK);
	static const double origin[3] = {0, 0, 0};
	gl_add_sphere(s, origin, 0.5, m_mirror);
	static const double dot[9] = {3.5, 3.5, 3.5, 3.51, 3.5, 3.5, 3.5, 3.51, 3.5};
	static const uint32_t dot_idx[3] = {0, 1, 2};
	struct rs_mesh_desc tiny = {.positions_f64 = dot,
	                            .vertex_count = 3,
	                            .indices = dot_idx,
	                            .triangle_count = 1,
	                            .material = m_grey};
	assert_int_equal(rs_scene_add_mesh(s, &tiny, NULL), RS_OK);
	struct rs_environment env = {.center = {1.5, 1.5, 1.5},
	                             .half_size = 100.0,
	                             .grid = 1,
	                             .line_width = 0.01f,
	                             .face_color = {{0.9f, 0.1f, 0.1f},
	                                            {0.1f, 0.9f, 0.1f},
	                                            {0.1f, 0.1f, 0.9f},
	                                            {0.9f, 0.9f, 0.1f},
	                                            {0.1f, 0.9f, 0.9f},
	                                            {0.9f, 0.1f, 0.9f}}};
	assert_int_equal(rs_scene_set_environment(s, &env, NULL), RS_OK);
	struct rs_light light = {{5, 5, 5}, {1, 1, 1}};
	assert_int_equal(rs_scene_add_light(s, &light, NULL), RS_OK);
	return s;
}

static void frame(const struct rs_scene *s, const struct rs_camera *cam,
                  enum rs_reflection_mode mode, uint32_t bounces, uint32_t face, float *rgb)
{
	struct rs_render_desc desc = {.width = cam->width,
	                              .height = cam->height,
	                              .passes = 2,
	                              .reflections = mode,
	                              .reflection_bounces = bounces,
	                              .envmap_size = face};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_error err = {0};
	struct rs_frame f = {.rgb = rgb};
	assert_int_equal(rs_renderer_set_scene(r, s, &err), RS_OK);
	if (rs_renderer_render(r, cam, &f, &err) != RS_OK)
		fail_msg("%s", err.message);
	rs_renderer_destroy(&r);
}

/* Seen along each axis, the sphere's centre pixel reflects the ray straight back: the
 * classic map's face in that direction, at its centre, against the tracer's colour there. */
static void every_face_holds_its_direction(void **state)
{
	(void)state;
	struct rs_scene *s = axis_sphere();
	static float env[PIXELS], traced[PIXELS];
	for (int f = 0; f < 6; ++f) {
		int axis = f / 2;
		double sign = f % 2 ? -1.0 : 1.0;
		struct rs_camera cam = {.fov_y_deg = 20, .width = SIZE, .height = SIZE};
		cam.eye[axis] = 2.5 * sign;
		cam.up[axis == 1 ? 2 : 1] = 1.0;
		frame(s, &cam, RS_REFLECT_ENVMAP, 0, 16, env);
		frame(s, &cam, RS_REFLECT_TRACE, 0, 0, traced);
		size_t c = ((size_t)(SIZE / 2) * SIZE + SIZE / 2) * 3;
		print_message("face %d: envmap %.3f %.3f %.3f, traced %.3f %.3f %.3f\n", f, env[c],
		              env[c + 1], env[c + 2], traced[c], traced[c + 1], traced[c + 2]);
		for (int k = 0; k < 3; ++k)
			assert_true(fabs(env[c + k] - traced[c + k]) < 0.02);
		assert_true(traced[c] + traced[c + 1] + traced[c + 2] > 0.9);
	}
	rs_scene_destroy(&s);
}

/* The faces copied on the GPU against the same faces read back and uploaded: both convert
 * the same fp32 colour to half floats. */
static void gpu_faces_equal_the_readback_faces(void **state)
{
	(void)state;
	struct rs_scene *s = gl_scene("mirrors");
	struct rs_camera cam;
	rs_camera_resolve(rs_scene_camera(s), &cam);
	cam.width = cam.height = SIZE;
	static float gpu[PIXELS], readback[PIXELS];
	static const enum rs_reflection_mode modes[2] = {RS_REFLECT_ENVMAP,
	                                                 RS_REFLECT_INTERREFLECT};
	for (int m = 0; m < 2; ++m) {
		rs__gles_force_capture_readback(false);
		frame(s, &cam, modes[m], 2, 24, gpu);
		rs__gles_force_capture_readback(true);
		frame(s, &cam, modes[m], 2, 24, readback);
		rs__gles_force_capture_readback(false);
		struct rs_image_diff d;
		rs_image_compare(gpu, readback, SIZE, SIZE, 3, 1.0, 0.0, &d);
		print_message("mode %d: GPU faces vs readback: max error %g, %.2f %% differ\n",
		              (int)modes[m], d.max_abs_error, 100.0 * d.bad_share);
		assert_memory_equal(gpu, readback, sizeof gpu);
	}
	rs_scene_destroy(&s);
}

/* Table 3's scene: two bounces see the other mirrors' first-bounce maps, so the image
 * differs from one bounce's; a second bounce that read no maps, or the set it writes,
 * would not. */
static void mirrors_second_bounce_differs(void **state)
{
	(void)state;
	struct rs_scene *s = gl_scene("mirrors");
	struct rs_camera cam;
	rs_camera_resolve(rs_scene_camera(s), &cam);
	cam.width = cam.height = SIZE;
	static float b1[PIXELS], b2[PIXELS];
	frame(s, &cam, RS_REFLECT_INTERREFLECT, 1, 32, b1);
	frame(s, &cam, RS_REFLECT_INTERREFLECT, 2, 32, b2);
	struct rs_image_diff d;
	rs_image_compare(b1, b2, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &d);
	/* 0.88 % on llvmpipe; 0 with the second bounce reading no maps */
	print_message("mirrors: bounces 1 vs 2: %.2f %% differ by > 8/255\n", 100.0 * d.bad_share);
	assert_true(d.bad_share > 0.005);
	rs_scene_destroy(&s);
}

static void face_size_is_an_option_with_a_range(void **state)
{
	(void)state;
	struct rs_render_desc d = {0};
	struct rs_error err = {0};
	assert_int_equal(rs_render_desc_set(&d, "envmap-size", "64", &err), RS_OK);
	assert_int_equal(d.envmap_size, 64);
	assert_int_equal(rs_render_desc_set(&d, "envmap-size", "4", &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "envmap-size"));
	assert_int_equal(rs_render_desc_set(&d, "envmap-size", "16385", &err), RS_ERR_INVALID);
	assert_int_equal(d.envmap_size, 64);
	char out[16];
	assert_int_equal(rs_render_desc_get(&d, "envmap-size", out, sizeof out, &err), RS_OK);
	assert_string_equal(out, "64");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(face_size_is_an_option_with_a_range),
	    cmocka_unit_test(every_face_holds_its_direction),
	    cmocka_unit_test(gpu_faces_equal_the_readback_faces),
	    cmocka_unit_test(mirrors_second_bounce_differs),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
