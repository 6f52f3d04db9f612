/* Out of GPU memory (issue 8 item 11): through the private fault seam of gles_seams.h, every
 * GL allocation the renderer makes (textures, renderbuffers, the buffer objects of buffer
 * texture storage, framebuffer and vertex array objects, shadow and environment maps, the
 * inter-reflection maps captured per frame) is made to fail in turn. Each failure must give
 * RS_ERR_NO_MEMORY with one line naming what was being allocated and its size, delete every GL
 * object the failed call made (the seam tracks live names; ASan tracks host memory), and leave a
 * renderer that renders once memory is back. EGL (llvmpipe in CI); skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../backends/gles/gles_seams.h"
#include "test_gl_common.h"

#define SIZE 16u

static void message_names_the_allocation(const struct rs_error *err, bool sized)
{
	assert_non_null(strstr(err->message, "gles: out of GPU memory for "));
	assert_null(strchr(err->message, '\n'));
	if (sized) /* "(WxH[xL] FORMAT, N.N KiB|MiB)" */
		assert_true(strstr(err->message, " KiB)") || strstr(err->message, " MiB)"));
}

static void assert_live(const struct rs__gl_fault_counts *want)
{
	struct rs__gl_fault_counts got;
	rs__gl_fault_counts(&got);
	assert_false(got.overflow);
	assert_int_equal(got.textures, want->textures);
	assert_int_equal(got.renderbuffers, want->renderbuffers);
	assert_int_equal(got.buffers, want->buffers);
	assert_int_equal(got.framebuffers, want->framebuffers);
	assert_int_equal(got.vertex_arrays, want->vertex_arrays);
}

/* Fail allocation 1, 2, ... of set_scene + one frame of `scene` under `desc` until none is
 * left; returns how many there were. */
static long fail_each_allocation(const struct rs_render_desc *desc, const char *scene_name)
{
	rs__gl_fault_wrap(true);
	struct rs_renderer *r = gl_open("egl", desc);
	if (!r) {
		rs__gl_fault_wrap(false);
		gl_skip();
	}
	struct rs__gl_fault_counts base;
	rs__gl_fault_counts(&base); /* what the renderer holds without a scene */
	assert_int_equal(base.framebuffers, 1);
	struct rs_scene *scene = gl_scene(scene_name);
	static float want[SIZE * SIZE * 3], got[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = want};
	struct rs_error err;
	rs__gl_fault_fail_at(0);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	struct rs__gl_fault_counts c;
	rs__gl_fault_counts(&c);
	long total = c.allocations;
	frame.rgb = got;
	for (long n = 1; n <= total; ++n) {
		rs__gl_fault_fail_at(n);
		enum rs_status st = rs_renderer_set_scene(r, scene, &err);
		bool in_frame = st == RS_OK;
		if (in_frame)
			st = rs_renderer_render(r, NULL, &frame, &err);
		rs__gl_fault_counts(&c);
		assert_true(c.fired);
		if (st != RS_ERR_NO_MEMORY)
			fail_msg("allocation %ld of %ld: status %d, '%s'", n, total, (int)st,
			         err.message);
		message_names_the_allocation(&err, true);
		assert_string_equal(rs_renderer_last_error(r), err.message);
		if (n == 1 || n == total)
			print_message("%s, allocation %ld of %ld: %s\n", scene_name, n, total,
			              err.message);
		if (!in_frame) {
			/* nothing of the scene is left: not on the GPU, not to render */
			assert_live(&base);
			assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
		} else {
			/* a frame that failed leaves the scene: the next one renders */
			rs__gl_fault_fail_at(0);
			assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
			assert_memory_equal(got, want, sizeof want);
		}
	}
	/* memory is back: the same renderer renders the same image */
	rs__gl_fault_fail_at(0);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	assert_memory_equal(got, want, sizeof want);
	rs_renderer_destroy(&r);
	struct rs__gl_fault_counts none = {0};
	assert_live(&none);
	rs__gl_fault_wrap(false);
	rs_scene_destroy(&scene);
	return total;
}

static void every_allocation_of_the_traced_chain_with_counters_fails_cleanly(void **state)
{
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 1, .counters = true};
	/* 4 scene textures, 2 x (3 state, hit, counters), display */
	assert_true(fail_each_allocation(&desc, "box") >= 15);
}

static void every_allocation_with_raster_primary_and_shadow_maps_fails_cleanly(void **state)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 2,
	                              .primary = RS_PRIMARY_RASTER,
	                              .shadows = RS_SHADOW_MAP,
	                              .shadow_map_size = 64,
	                              .chain = RS_CHAIN_PAPER,
	                              .scene_storage = RS_SCENE_STORAGE_2D};
	/* ... and the raster depth buffer, the shadow maps and their depth buffer (and the
	 * scene in GLES 3.0's 2D textures; the other settings take buffer textures here) */
	assert_true(fail_each_allocation(&desc, "box") >= 16);
}

static void every_allocation_of_an_environment_map_fails_cleanly(void **state)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 1,
	                              .reflections = RS_REFLECT_ENVMAP};
	/* ... and the cube map (its six RGBA16F faces are one immutable allocation) */
	assert_true(fail_each_allocation(&desc, "box") >= 14);
}

static void every_allocation_of_inter_reflection_maps_fails_cleanly(void **state)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 1,
	                              .reflections = RS_REFLECT_INTERREFLECT};
	/* ... the object texture and two sets of the 4 objects' cube maps, made at set_scene
	 * (the frames only render into them) */
	assert_true(fail_each_allocation(&desc, "mirrors") >= 14 + 1 + 2 * 4);
}

/* Creating the renderer allocates its vertex array and framebuffer objects. */
static void a_renderer_that_cannot_allocate_its_objects_is_not_made(void **state)
{
	for (long n = 1; n <= 2; ++n) {
		rs__gl_fault_wrap(true);
		rs__gl_fault_fail_at(n);
		struct rs_render_desc desc = {.width = SIZE, .height = SIZE};
		struct rs_renderer *r = NULL;
		struct rs_error err;
		if (!rs_renderer_has_backend("egl")) {
			rs__gl_fault_wrap(false);
			gl_skip();
		}
		enum rs_status st = rs_renderer_open("egl", &desc, &r, &err);
		struct rs__gl_fault_counts c;
		rs__gl_fault_counts(&c);
		if (!c.fired) { /* no context here: the table was never loaded */
			rs__gl_fault_wrap(false);
			gl_skip();
		}
		assert_int_equal(st, RS_ERR_NO_MEMORY);
		assert_null(r);
		message_names_the_allocation(&err, false);
		assert_non_null(strstr(err.message, n == 1 ? "vertex array" : "framebuffer"));
		struct rs__gl_fault_counts none = {0};
		assert_live(&none);
		rs__gl_fault_wrap(false);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(every_allocation_of_the_traced_chain_with_counters_fails_cleanly),
	    cmocka_unit_test(every_allocation_with_raster_primary_and_shadow_maps_fails_cleanly),
	    cmocka_unit_test(every_allocation_of_an_environment_map_fails_cleanly),
	    cmocka_unit_test(every_allocation_of_inter_reflection_maps_fails_cleanly),
	    cmocka_unit_test(a_renderer_that_cannot_allocate_its_objects_is_not_made),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
