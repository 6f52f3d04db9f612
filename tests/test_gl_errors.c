/* GL backend errors: one line each and a clean failure (no scene left behind): a kernel
 * that does not compile (file, line, driver log and source line), a scene over the
 * texture limit (named) and a scene that fits GLES 3.0's 2048 in narrower rows, an unknown
 * or unavailable EGL platform. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <unistd.h>
#include <cmocka.h>

#include "../backends/gles/gles_seams.h"
#include "test_gl_common.h"

static void a_kernel_that_does_not_compile_names_file_line_and_source(void **state)
{
	struct rs_render_desc desc = {.width = 16, .height = 16};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene("box");
	rs__gles_override_kernel("display.glsl", "uniform sampler2D u_acc;\n"
	                                         "out vec4 o_color;\n"
	                                         "void main() { o_color = undefined_thing; }\n");
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_DEVICE);
	rs__gles_override_kernel(NULL, NULL);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "display.glsl line 3"));
	assert_non_null(strstr(err.message, "undefined_thing"));
	assert_null(strchr(err.message, '\n'));
	assert_string_equal(rs_renderer_last_error(r), err.message);
	/* no scene is left behind to render */
	float rgb[16 * 16 * 3];
	struct rs_frame frame = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
	/* and the renderer still works once the kernels do */
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

/* A renderer whose GL reports `limit` texels a side (0: the device's own). */
static struct rs_renderer *gl_open_limited(const char *limit, const struct rs_render_desc *desc)
{
	if (limit)
		setenv("RS_GLES_MAX_TEXTURE_SIZE", limit, 1);
	struct rs_renderer *r = gl_open("egl", desc);
	unsetenv("RS_GLES_MAX_TEXTURE_SIZE");
	return r;
}

/* GLES 3.0 guarantees 2048 texels a side. Cow1 (over 1024 nodes, which used to make a
 * 3072-texel row and be refused there) fits such a device, in 2D textures as GLES 3.0 holds
 * them, and renders exactly as with rows half as wide. Both limits are lowered below what
 * the device has (every GLES 3 device has at least 2048, and 1024 is lowered on each), so
 * the two layouts differ wherever this runs: rows read wrongly at either width show. */
static void a_gles3_minimum_device_holds_cow1_in_narrower_rows(void **state)
{
	enum { S = 32 };
	struct rs_render_desc desc = {
	    .width = S, .height = S, .scene_storage = RS_SCENE_STORAGE_2D};
	struct rs_renderer *gles3 = gl_open_limited("2048", &desc);
	struct rs_renderer *narrow = gl_open_limited("1024", &desc);
	if (!gles3 || !narrow) {
		rs_renderer_destroy(&gles3);
		rs_renderer_destroy(&narrow);
		gl_skip();
	}
	struct rs_scene *scene = gl_scene("cow1");
	struct rs_error err;
	static float a[S * S * 3], b[S * S * 3], da[S * S], db[S * S];
	static uint32_t ta[S * S], tb[S * S];
	struct rs_frame fa = {.rgb = a, .depth = da, .triangle = ta};
	struct rs_frame fb = {.rgb = b, .depth = db, .triangle = tb};
	assert_int_equal(rs_renderer_set_scene(gles3, scene, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(narrow, scene, &err), RS_OK);
	assert_int_equal(rs_renderer_stats(narrow)->scene_storage, RS_SCENE_STORAGE_2D);
	assert_int_equal(rs_renderer_render(gles3, NULL, &fa, &err), RS_OK);
	assert_int_equal(rs_renderer_render(narrow, NULL, &fb, &err), RS_OK);
	assert_memory_equal(a, b, sizeof a);
	assert_memory_equal(da, db, sizeof da);
	assert_memory_equal(ta, tb, sizeof ta);
	uint32_t hit = 0;
	for (uint32_t i = 0; i < S * S; ++i)
		hit += ta[i] != RS_NO_SLOT;
	assert_true(hit > S * S / 8); /* the cow is in the picture */
	rs_renderer_destroy(&gles3);
	rs_renderer_destroy(&narrow);
	/* the narrow renderer did have the lowered limit: a layout for 2048 is refused there */
	desc.pack.max_texture_size = 2048;
	narrow = gl_open_limited("1024", &desc);
	assert_non_null(narrow);
	assert_int_equal(rs_renderer_set_scene(narrow, scene, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "GL_MAX_TEXTURE_SIZE of 1024"));
	rs_renderer_destroy(&narrow);
	rs_scene_destroy(&scene);
}

static void a_scene_over_the_texture_limit_is_refused_naming_it(void **state)
{
	struct rs_render_desc desc = {.width = 16, .height = 16};
	struct rs_renderer *r = gl_open_limited("64", &desc);
	if (!r)
		gl_skip();
	/* 64 texels: 16 items a row, 64 rows: 1024 items, and Cow1 has 5837 triangles */
	struct rs_scene *scene = gl_scene("cow1");
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_LIMIT);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "texture size limit of 64 texels"));
	rs_renderer_destroy(&r);
	/* asking for more than the device has is refused too */
	struct rs_render_desc wide = {.width = 16, .height = 16, .pack.max_texture_size = 4096};
	r = gl_open_limited("2048", &wide);
	assert_non_null(r);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "GL_MAX_TEXTURE_SIZE of 2048"));
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void an_image_over_the_limit_is_refused(void **state)
{
	setenv("RS_GLES_MAX_TEXTURE_SIZE", "2048", 1);
	struct rs_render_desc desc = {.width = 4096, .height = 16};
	struct rs_renderer *r = gl_open("egl", &desc);
	unsetenv("RS_GLES_MAX_TEXTURE_SIZE");
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene("box");
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "4096x16"));
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void an_unknown_egl_platform_is_invalid(void **state)
{
	if (!rs_renderer_has_backend("egl"))
		gl_skip();
	struct rs_render_desc desc = {.egl_platform = "wayland"};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_open("egl", &desc, &r, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "wayland"));
	assert_null(r);
}

static void an_egl_platform_without_a_device_fails_cleanly(void **state)
{
	if (!rs_renderer_has_backend("egl") || access("/dev/dri/renderD128", F_OK) == 0)
		skip(); /* a render node exists: GBM may well work here */
	struct rs_render_desc desc = {.egl_platform = "gbm"};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_open("egl", &desc, &r, &err), RS_ERR_DEVICE);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "gbm"));
	assert_null(r);
}

static void the_platform_is_named_in_the_renderer_string(void **state)
{
	struct rs_render_desc desc = {.egl_platform = "surfaceless"};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	const struct rs_render_stats *s = rs_renderer_stats(r);
	assert_string_equal(s->backend, "egl");
	assert_non_null(strstr(s->renderer, "EGL surfaceless"));
	rs_renderer_destroy(&r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(a_kernel_that_does_not_compile_names_file_line_and_source),
	    cmocka_unit_test(a_gles3_minimum_device_holds_cow1_in_narrower_rows),
	    cmocka_unit_test(a_scene_over_the_texture_limit_is_refused_naming_it),
	    cmocka_unit_test(an_image_over_the_limit_is_refused),
	    cmocka_unit_test(an_unknown_egl_platform_is_invalid),
	    cmocka_unit_test(an_egl_platform_without_a_device_fails_cleanly),
	    cmocka_unit_test(the_platform_is_named_in_the_renderer_string),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
