/* Per-frame instance transforms on the GL backends (rs_renderer_update_instances): a
 * renderer whose instances moved (the scene changed in place by
 * rs_scene_set_instance_transform, then updated) renders what a fresh set_scene of the moved
 * scene renders: the same triangle on every pixel and the same colour. Until the GLES
 * backend has its own update_instances op, the update goes through update_vertices (the
 * baked triangles moved), which the stats say. Skipped (77) without a GL context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_instances_fixture.h"

#define SIZE 48u

struct image {
	float rgb[SIZE * SIZE * 3];
	uint32_t tri[SIZE * SIZE];
};

static void render(struct rs_renderer *r, struct image *out)
{
	struct rs_frame f = {.rgb = out->rgb, .triangle = out->tri};
	struct rs_error err;
	if (rs_renderer_render(r, NULL, &f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
}

static void check(const char *backend, enum rs_scene_storage storage)
{
	struct rs_render_desc d = {.width = SIZE, .height = SIZE, .scene_storage = storage};
	struct rs_renderer *moved = gl_open(backend, &d), *fresh = NULL;
	if (!moved)
		gl_skip();
	fresh = gl_open(backend, &d);
	assert_non_null(fresh);
	struct rs_scene *scene = fix_scene(0), *target = fix_scene(3);
	assert_non_null(scene);
	assert_non_null(target);
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(moved, scene, &err), RS_OK);
	for (uint32_t k = 1; k <= 3; k++) {
		assert_int_equal(fix_move(scene, k), RS_OK);
		if (rs_renderer_update_instances(moved, scene, &err) != RS_OK)
			fail_msg("update to frame %u: %s", k, err.message);
	}
	const struct rs_render_stats *st = rs_renderer_stats(moved);
	print_message("%s: %u instance updates, %s, %llu bytes sent last\n", backend,
	              st->instance_updates, st->instance_update_baked ? "baked" : "two-level",
	              (unsigned long long)st->upload_bytes);
	assert_int_equal(st->instance_updates, 3);
	assert_true(st->upload_bytes > 0);
	assert_int_equal(rs_renderer_set_scene(fresh, target, &err), RS_OK);
	struct image *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b);
	assert_non_null(a);
	assert_non_null(b);
	render(moved, a);
	render(fresh, b);
	uint32_t tri_diff = 0, hits = 0;
	float worst = 0.0f;
	for (uint32_t p = 0; p < SIZE * SIZE; ++p) {
		tri_diff += a->tri[p] != b->tri[p];
		hits += a->tri[p] != RS_NO_SLOT;
		for (int c = 0; c < 3; ++c) {
			float e = fabsf(a->rgb[3 * p + c] - b->rgb[3 * p + c]);
			worst = e > worst ? e : worst;
		}
	}
	print_message("%s: %u of %u pixels hit another triangle, largest colour difference %g\n",
	              backend, tri_diff, hits, (double)worst);
	assert_true(hits > SIZE * SIZE / 4);
	assert_int_equal(tri_diff, 0);
	assert_true(worst <= 1e-5f);
	free(a);
	free(b);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&fresh);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&target);
}

static void egl_moved_instances_render_as_set_scene(void **state)
{
	(void)state;
	check("egl", RS_SCENE_STORAGE_AUTO);
}

static void egl_moved_instances_render_as_set_scene_2d(void **state)
{
	(void)state;
	check("egl", RS_SCENE_STORAGE_2D);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(egl_moved_instances_render_as_set_scene),
	    cmocka_unit_test(egl_moved_instances_render_as_set_scene_2d),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
