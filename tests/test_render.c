/* rs_render: the renderer object and its CPU backend against rs_trace_render() itself:
 * same pixels and counts, per-frame cameras, RGBA8, threads, descriptor defaults and
 * errors, and the life-cycle rules (no frame before a scene, none after a failed upload). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_image.h"
#include "raystream/rs_render.h"
#include "test_trace_render_fixture.h"

#define SIZE 24u

/* A floor, a mirror wall and a box on the floor, two lights. */
static struct fx room(void)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material grey = {
	    .diffuse = {0.6f, 0.5f, 0.4f}, .specular = 0.3f, .shininess = 16};
	struct rs_material mirror = {.diffuse = {0.1f, 0.1f, 0.1f}, .reflectance = 0.8f};
	uint32_t g = fx_material(fx.scene, grey), m = fx_material(fx.scene, mirror);
	fx_quad(fx.scene, 1, 0.0, -3, 3, 0, g);
	fx_rect(fx.scene, 2, -2.0, -3, 3, 0, 3, 0, m);
	const double lo[3] = {-0.5, 0, -0.5}, hi[3] = {0.5, 1, 0.5};
	fx_box(fx.scene, lo, hi, g);
	const double eye[3] = {1.5, 2.0, 4.0}, target[3] = {0, 0.5, 0};
	fx_camera(fx.scene, eye, target, SIZE);
	fx_light(fx.scene, 2, 3, 2, 1, 1, 1);
	fx_light(fx.scene, -2, 2, 1, 0.5, 0.4, 0.3);
	fx_pack(&fx, RS_BVH_SAH);
	return fx;
}

static struct rs_renderer *cpu(const struct rs_render_desc *desc, const struct rs_scene *scene)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(desc, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	return r;
}

static void cpu_backend_matches_the_reference_tracer(void **state)
{
	struct fx fx = room();
	float want[SIZE * SIZE * 3], got[SIZE * SIZE * 3], dwant[SIZE * SIZE], dgot[SIZE * SIZE];
	struct rs_trace_stats ts;
	struct rs_trace_desc td = {.passes = 3};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &td, want, dwant, &ts, NULL), RS_OK);
	struct rs_render_desc rd = {.passes = 3, .threads = 3};
	struct rs_renderer *r = cpu(&rd, fx.scene);
	struct rs_frame frame = {.rgb = got, .depth = dgot};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, NULL), RS_OK);
	assert_memory_equal(want, got, sizeof want);
	assert_memory_equal(dwant, dgot, sizeof dwant);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	assert_string_equal(s->backend, "cpu");
	assert_true(s->counters_valid);
	assert_int_equal(s->pixels, SIZE * SIZE);
	assert_int_equal(s->primary_rays, SIZE * SIZE);
	assert_int_equal(s->primary_rays + s->secondary_rays, ts.rays);
	assert_true(s->secondary_rays > 0); /* the mirror is in view */
	assert_int_equal(s->shadow_rays, ts.shadow_rays);
	assert_int_equal(s->box_tests, ts.box_tests);
	assert_int_equal(s->triangle_tests, ts.triangle_tests);
	assert_true(fabs(s->total_per_pixel - ts.total_per_pixel) < 1e-9);
	rs_renderer_destroy(&r);
	assert_null(r);
	fx_free(&fx);
}

static void per_frame_camera_renders_as_the_scene_camera_would(void **state)
{
	struct fx fx = room();
	struct rs_camera moved = *rs_scene_camera(fx.scene);
	moved.eye[0] = -2.0;
	moved.eye[1] = 1.0;
	moved.fov_y_deg = 60;
	moved.width = 7; /* ignored: the size was fixed at set_scene */
	struct rs_renderer *r = cpu(NULL, fx.scene);
	float got[SIZE * SIZE * 3], first[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = got};
	assert_int_equal(rs_renderer_render(r, &moved, &frame, NULL), RS_OK);
	memcpy(first, got, sizeof got);
	moved.width = moved.height = SIZE;
	assert_int_equal(rs_scene_set_camera(fx.scene, &moved, NULL), RS_OK);
	struct rs_trace_desc td = {0};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &td, want, NULL, NULL, NULL), RS_OK);
	assert_memory_equal(first, want, sizeof want);
	rs_renderer_destroy(&r);
	fx_free(&fx);
}

static void rgba8_is_the_quantized_float_image(void **state)
{
	struct fx fx = room();
	struct rs_renderer *r = cpu(NULL, fx.scene);
	float rgb[SIZE * SIZE * 3];
	uint8_t rgba[SIZE * SIZE * 4];
	struct rs_frame both = {.rgb = rgb, .rgba8 = rgba};
	assert_int_equal(rs_renderer_render(r, NULL, &both, NULL), RS_OK);
	for (size_t i = 0; i < SIZE * SIZE; ++i) {
		for (int c = 0; c < 3; ++c)
			assert_int_equal(rgba[4 * i + c], rs_image_quantize_value(rgb[3 * i + c]));
		assert_int_equal(rgba[4 * i + 3], 255);
	}
	/* RGBA8 alone (no float buffer from the caller) gives the same bytes. */
	uint8_t alone[SIZE * SIZE * 4];
	struct rs_frame only = {.rgba8 = alone};
	assert_int_equal(rs_renderer_render(r, NULL, &only, NULL), RS_OK);
	assert_memory_equal(alone, rgba, sizeof rgba);
	rs_renderer_destroy(&r);
	fx_free(&fx);
}

static void thread_counts_give_identical_images(void **state)
{
	struct fx fx = room();
	float one[SIZE * SIZE * 3], many[SIZE * SIZE * 3];
	struct rs_render_desc d1 = {.threads = 1}, d7 = {.threads = 7};
	struct rs_renderer *a = cpu(&d1, fx.scene), *b = cpu(&d7, fx.scene);
	struct rs_frame fa = {.rgb = one}, fb = {.rgb = many};
	assert_int_equal(rs_renderer_render(a, NULL, &fa, NULL), RS_OK);
	assert_int_equal(rs_renderer_render(b, NULL, &fb, NULL), RS_OK);
	assert_memory_equal(one, many, sizeof one);
	assert_int_equal(rs_renderer_stats(a)->box_tests, rs_renderer_stats(b)->box_tests);
	rs_renderer_destroy(&a);
	rs_renderer_destroy(&b);
	fx_free(&fx);
}

static void bvh_build_uses_the_renderer_threads(void **state)
{
	struct rs_render_desc d = {.threads = 3};
	assert_int_equal(rs_render_bvh_desc(&d).threads, 3);
	d.bvh.threads = 5; /* asked for explicitly: kept */
	assert_int_equal(rs_render_bvh_desc(&d).threads, 5);
	d = (struct rs_render_desc){.bvh.builder = RS_BVH_PAPER, .threads = 2};
	assert_int_equal(rs_render_bvh_desc(&d).builder, RS_BVH_PAPER);
	d.threads = 0; /* the machine's cores, as for rendering */
	assert_true(rs_render_bvh_desc(&d).threads >= 1);
}

static void descriptor_defaults_are_resolved_in_one_place(void **state)
{
	struct rs_render_desc d;
	assert_int_equal(rs_render_desc_resolve(NULL, &d, NULL), RS_OK);
	assert_int_equal(d.passes, 2);
	assert_int_equal(d.shadow_map_size, 512);
	assert_int_equal(d.shadow_filter, 3);
	assert_int_equal(d.width, 0);
	struct fx fx = room();
	struct rs_renderer *r = cpu(NULL, fx.scene);
	assert_int_equal(rs_renderer_desc(r)->width, SIZE); /* the camera's, at set_scene */
	assert_int_equal(rs_renderer_desc(r)->height, SIZE);
	rs_renderer_destroy(&r);
	fx_free(&fx);
}

static void bad_descriptors_are_refused_with_a_message(void **state)
{
	const struct rs_render_desc bad[] = {
	    {.width = 16},
	    {.passes = RS_TRACE_MAX_PASSES + 1},
	    {.triangle_test = (enum rs_triangle_test)7},
	    {.ray_epsilon = -1.0},
	    {.ray_epsilon = NAN},
	    {.primary = (enum rs_primary_mode)9},
	    {.shadows = (enum rs_shadow_mode)9},
	    {.chain = (enum rs_kernel_chain)9},
	    {.chain = (enum rs_kernel_chain)(RS_CHAIN_PAPER + 1)},
	    {.shadow_map_size = 4, .shadow_filter = 5},
	    {.threads = RS_RENDER_MAX_THREADS + 1},
	    {.width = 20000, .height = 20000},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
		struct rs_renderer *r = (struct rs_renderer *)&bad[i]; /* must be cleared */
		struct rs_error err = {0};
		assert_true(rs_renderer_create_cpu(&bad[i], &r, &err) < 0);
		assert_null(r);
		assert_true(err.message[0] != '\0');
		assert_null(strchr(err.message, '\n'));
	}
}

static void cpu_backend_refuses_raster_and_shadow_maps(void **state)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	struct rs_render_desc raster = {.primary = RS_PRIMARY_RASTER};
	struct rs_render_desc maps = {.shadows = RS_SHADOW_MAP};
	assert_int_equal(rs_renderer_create_cpu(&raster, &r, &err), RS_ERR_UNSUPPORTED);
	assert_non_null(strstr(err.message, "raster"));
	assert_int_equal(rs_renderer_create_cpu(&maps, &r, &err), RS_ERR_UNSUPPORTED);
	assert_null(r);
}

static void no_frame_without_a_scene(void **state)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(NULL, &r, &err), RS_OK);
	float rgb[3];
	struct rs_frame frame = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "no scene"));
	assert_string_equal(rs_renderer_last_error(r), err.message);
	rs_renderer_destroy(&r);
}

static void failed_set_scene_leaves_no_scene_behind(void **state)
{
	struct fx fx = room();
	struct rs_render_desc three = {.lights = 3};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&three, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, fx.scene, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "3 lights"));
	float rgb[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
	rs_renderer_destroy(&r);
	fx_free(&fx);
}

static void bad_cameras_are_refused_per_frame(void **state)
{
	struct fx fx = room();
	struct rs_renderer *r = cpu(NULL, fx.scene);
	float rgb[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = rgb};
	struct rs_camera c = *rs_scene_camera(fx.scene);
	c.eye[1] = NAN;
	struct rs_error err;
	assert_int_equal(rs_renderer_render(r, &c, &frame, &err), RS_ERR_BAD_DATA);
	c = *rs_scene_camera(fx.scene);
	memcpy(c.target, c.eye, sizeof c.eye);
	assert_int_equal(rs_renderer_render(r, &c, &frame, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "eye equals"));
	c = *rs_scene_camera(fx.scene);
	c.shift[0] = NAN;
	assert_int_equal(rs_renderer_render(r, &c, &frame, &err), RS_ERR_BAD_DATA);
	c.shift[0] = 1e9;
	assert_int_equal(rs_renderer_render(r, &c, &frame, &err), RS_ERR_BAD_DATA);
	/* The renderer still works afterwards. */
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	assert_string_equal(rs_renderer_last_error(r), "");
	rs_renderer_destroy(&r);
	fx_free(&fx);
}

static void destroy_accepts_null(void **state)
{
	struct rs_renderer *r = NULL;
	rs_renderer_destroy(&r);
	rs_renderer_destroy(NULL);
	rs_render_accel_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cpu_backend_matches_the_reference_tracer),
	    cmocka_unit_test(per_frame_camera_renders_as_the_scene_camera_would),
	    cmocka_unit_test(rgba8_is_the_quantized_float_image),
	    cmocka_unit_test(thread_counts_give_identical_images),
	    cmocka_unit_test(descriptor_defaults_are_resolved_in_one_place),
	    cmocka_unit_test(bad_descriptors_are_refused_with_a_message),
	    cmocka_unit_test(cpu_backend_refuses_raster_and_shadow_maps),
	    cmocka_unit_test(no_frame_without_a_scene),
	    cmocka_unit_test(failed_set_scene_leaves_no_scene_behind),
	    cmocka_unit_test(bad_cameras_are_refused_per_frame),
	    cmocka_unit_test(destroy_accepts_null),
	    cmocka_unit_test(bvh_build_uses_the_renderer_threads),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
