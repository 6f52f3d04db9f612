/* Where the GL backends hold the packed scene (rs_scene_storage): buffer textures and GLES
 * 3.0's 2D textures hold the same texels in the same order, so every setting renders the
 * same image, depth, triangle ids and hit counts bit for bit either way; AUTO takes buffer
 * textures where the context has them and the scene fits, and falls back to 2D where it
 * does not; BUFFER is refused, naming the limit, where they cannot be had. EGL and OSMesa
 * (llvmpipe in CI: GLES 3.2 and desktop GL with ARB_ES3_2_compatibility); skipped without a
 * context. CI runs it twice more with Mesa's GLES version override (tests/gl_versions.cmake):
 * GLES 3.1, where buffer textures come from OES/EXT_texture_buffer (`#version 310 es` with
 * the extension), and GLES 3.0, which has none: AUTO must take 2D there and BUFFER be
 * refused (the identity tests then skip on EGL). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 48u

struct image {
	float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	uint32_t triangle[SIZE * SIZE];
	uint64_t boxes, triangles;
	enum rs_scene_storage storage;
};

enum outcome { RENDERED, NO_CONTEXT, NO_BUFFERS };

/* One frame of `scene` on `backend` under desc with the given storage. NO_BUFFERS: BUFFER
 * asked for on a context without buffer textures (refused as it must be: never on GLES
 * 3.2, whose core has them). */
static enum outcome render(const char *backend, struct rs_render_desc desc,
                           enum rs_scene_storage storage, const struct rs_scene *scene,
                           struct image *out)
{
	desc.scene_storage = storage;
	struct rs_renderer *r = gl_open(backend, &desc);
	if (!r)
		return NO_CONTEXT;
	struct rs_error err;
	enum rs_status st = rs_renderer_set_scene(r, scene, &err);
	if (st == RS_ERR_UNSUPPORTED && storage == RS_SCENE_STORAGE_BUFFER) {
		const char *gl = rs_renderer_stats(r)->renderer;
		print_message("%s: %s (%s)\n", backend, err.message, gl);
		assert_null(strstr(gl, "OpenGL ES 3.2"));
		assert_non_null(strstr(err.message, "no buffer textures"));
		rs_renderer_destroy(&r);
		return NO_BUFFERS;
	}
	if (st != RS_OK)
		fail_msg("%s set_scene: %s", backend, err.message);
	struct rs_frame frame = {.rgb = out->rgb, .depth = out->depth, .triangle = out->triangle};
	if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("%s render: %s", backend, err.message);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	out->boxes = s->box_tests;
	out->triangles = s->triangle_tests;
	out->storage = s->scene_storage;
	rs_renderer_destroy(&r);
	return RENDERED;
}

static void same_either_way(const char *backend, const char *scene_name,
                            const struct rs_render_desc *desc)
{
	static struct image buffers, rows;
	struct rs_scene *scene = gl_scene(scene_name);
	enum outcome got = render(backend, *desc, RS_SCENE_STORAGE_BUFFER, scene, &buffers);
	if (got != RENDERED) {
		rs_scene_destroy(&scene);
		if (got == NO_CONTEXT)
			gl_skip();
		skip(); /* GLES 3.0 (tests/gl_versions.cmake): no buffer textures to compare */
	}
	assert_int_equal(render(backend, *desc, RS_SCENE_STORAGE_2D, scene, &rows), RENDERED);
	assert_int_equal(buffers.storage, RS_SCENE_STORAGE_BUFFER);
	assert_int_equal(rows.storage, RS_SCENE_STORAGE_2D);
	assert_memory_equal(buffers.rgb, rows.rgb, sizeof rows.rgb);
	assert_memory_equal(buffers.depth, rows.depth, sizeof rows.depth);
	assert_memory_equal(buffers.triangle, rows.triangle, sizeof rows.triangle);
	if (desc->counters)
		assert_true(rows.boxes > 0);
	assert_true(buffers.boxes == rows.boxes && buffers.triangles == rows.triangles);
	rs_scene_destroy(&scene);
}

static void traced_frames_are_the_same_in_buffers_and_2d_textures(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 2};
	same_either_way("egl", "cow1", &desc);
	desc.counters = true; /* the separate chain */
	same_either_way("egl", "box", &desc);
}

static void raster_shadow_maps_and_paper_nodes_are_the_same_in_buffers_and_2d(void **state)
{
	/* the vertex kernels fetch triangles too; the paper's nodes take three texels each */
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 2,
	                              .primary = RS_PRIMARY_RASTER,
	                              .shadows = RS_SHADOW_MAP,
	                              .shadow_map_size = 64,
	                              .chain = RS_CHAIN_PAPER,
	                              .pack = {.nodes = RS_PACK_NODES_PAPER}};
	same_either_way("egl", "cow1", &desc);
}

static void osmesa_frames_are_the_same_in_buffers_and_2d_textures(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 1};
	same_either_way("osmesa", "cow1", &desc);
}

/* RS_GLES_MAX_TEXTURE_BUFFER_SIZE lowers the limit as a small device's would be. */
static void auto_falls_back_to_2d_and_buffer_is_refused_over_the_buffer_limit(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 1, .lights = 1};
	struct rs_scene *scene = gl_scene("cow1");
	static struct image img;
	if (render("egl", desc, RS_SCENE_STORAGE_AUTO, scene, &img) != RENDERED) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	enum rs_scene_storage unlimited = img.storage;
	assert_true(unlimited == RS_SCENE_STORAGE_BUFFER || unlimited == RS_SCENE_STORAGE_2D);
	/* AUTO takes buffers wherever BUFFER would be accepted */
	assert_int_equal(render("egl", desc, RS_SCENE_STORAGE_BUFFER, scene, &img),
	                 unlimited == RS_SCENE_STORAGE_BUFFER ? RENDERED : NO_BUFFERS);
	setenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE", "4096", 1); /* cow1 needs ~17,500 */
	assert_int_equal(render("egl", desc, RS_SCENE_STORAGE_AUTO, scene, &img), RENDERED);
	assert_int_equal(img.storage, RS_SCENE_STORAGE_2D);
	desc.scene_storage = RS_SCENE_STORAGE_BUFFER;
	struct rs_renderer *r = gl_open("egl", &desc);
	assert_non_null(r);
	struct rs_error err;
	if (unlimited == RS_SCENE_STORAGE_BUFFER) {
		assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_LIMIT);
		assert_non_null(strstr(err.message, "GL_MAX_TEXTURE_BUFFER_SIZE of 4096"));
		assert_null(strchr(err.message, '\n'));
	}
	rs_renderer_destroy(&r);
	/* a limit of 0: as a context without buffer textures */
	setenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE", "0", 1);
	r = gl_open("egl", &desc);
	assert_non_null(r);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_UNSUPPORTED);
	assert_non_null(strstr(err.message, "no buffer textures"));
	rs_renderer_destroy(&r);
	unsetenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE");
	rs_scene_destroy(&scene);
}

static void an_unknown_storage_is_refused(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE};
	desc.scene_storage = (enum rs_scene_storage)7;
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&desc, &r, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "unknown scene storage 7"));
	assert_null(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(traced_frames_are_the_same_in_buffers_and_2d_textures),
	    cmocka_unit_test(raster_shadow_maps_and_paper_nodes_are_the_same_in_buffers_and_2d),
	    cmocka_unit_test(osmesa_frames_are_the_same_in_buffers_and_2d_textures),
	    cmocka_unit_test(auto_falls_back_to_2d_and_buffer_is_refused_over_the_buffer_limit),
	    cmocka_unit_test(an_unknown_storage_is_refused),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
