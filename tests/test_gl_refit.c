/* Moving vertices on the GL backends (rs_renderer_update_vertices): a renderer moved to
 * frame N by updates renders what a fresh set_scene of frame N renders (the same triangle
 * on every pixel, the same colour: the closest hit does not depend on the tree), in both
 * scene storages (2D textures: glTexSubImage2D; buffer textures: glBufferSubData); only the
 * texel rows that changed are sent (fewer bytes than the whole scene when one cow of
 * Cow17 moves, none when nothing moved); maps captured at set_scene refuse an update and
 * keep the scene. Skipped (77) without a GL context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 48u

struct image {
	float rgb[SIZE * SIZE * 3];
	uint32_t tri[SIZE * SIZE];
};

static struct rs_scene *frame_scene(const char *name, uint32_t frame)
{
	struct rs_scene *s = NULL;
	struct rs_error err;
	if (rs_scenegen_load_frame(name, frame, 30, &s, &err) != RS_OK)
		fail_msg("%s frame %u: %s", name, frame, err.message);
	return s;
}

static void render(struct rs_renderer *r, struct image *out)
{
	struct rs_frame f = {.rgb = out->rgb, .triangle = out->tri};
	struct rs_error err;
	if (rs_renderer_render(r, NULL, &f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
}

/* name's frame 0, then each of frames[] by update, against a set_scene of the last one. */
static void check(const char *backend, enum rs_scene_storage storage, const char *name,
                  const uint32_t *frames, int count, double ratio)
{
	struct rs_render_desc d = {.width = SIZE,
	                           .height = SIZE,
	                           .scene_storage = storage,
	                           .counters = true,
	                           .rebuild_ratio = ratio};
	struct rs_renderer *moved = gl_open(backend, &d), *fresh = NULL;
	if (!moved)
		gl_skip();
	fresh = gl_open(backend, &d);
	assert_non_null(fresh);
	struct rs_scene *s[4] = {frame_scene(name, 0)};
	struct rs_error err;
	enum rs_status first = rs_renderer_set_scene(moved, s[0], &err);
	if (first != RS_OK)
		fprintf(stderr, "set_scene: %s\n", err.message);
	assert_int_equal(first, RS_OK);
	uint64_t full = rs_renderer_stats(moved)->upload_bytes;
	assert_true(full > 0);
	for (int i = 0; i < count; ++i) {
		s[i + 1] = frame_scene(name, frames[i]);
		if (rs_renderer_update_vertices(moved, s[i + 1], &err) != RS_OK)
			fail_msg("update to frame %u: %s", frames[i], err.message);
		const struct rs_render_stats *st = rs_renderer_stats(moved);
		print_message("%s %s frame %u: %s, SAH ratio %.3f, %llu of %llu bytes sent\n",
		              backend, name, frames[i], st->update_rebuilt ? "rebuilt" : "refitted",
		              st->update_sah_ratio, (unsigned long long)st->upload_bytes,
		              (unsigned long long)full);
		bool rebuild =
		    ratio > 0.0 && ratio < 1.0; /* 0: the default, which Cow17 never passes */
		assert_int_equal(st->update_rebuilt, rebuild);
		/* a rebuild may change the layout: then everything is sent again */
		assert_true(rebuild ? st->upload_bytes <= full : st->upload_bytes < full);
		assert_true(st->upload_bytes > 0);
	}
	assert_int_equal(rs_renderer_set_scene(fresh, s[count], &err), RS_OK);
	struct image *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b);
	render(moved, a);
	assert_true(rs_renderer_stats(moved)->counters_valid);
	render(fresh, b);
	uint32_t tri_diff = 0;
	float worst = 0.0f;
	for (uint32_t p = 0; p < SIZE * SIZE; ++p) {
		tri_diff += a->tri[p] != b->tri[p];
		for (int c = 0; c < 3; ++c) {
			float e = fabsf(a->rgb[3 * p + c] - b->rgb[3 * p + c]);
			worst = e > worst ? e : worst;
		}
	}
	print_message("%s %s: %u pixels hit another triangle, largest colour difference %g\n",
	              backend, name, tri_diff, (double)worst);
	assert_int_equal(tri_diff, 0);
	assert_true(worst <= 1e-5f);
	/* the same positions again: nothing to send */
	struct rs_scene *again = frame_scene(name, frames[count - 1]);
	assert_int_equal(rs_renderer_update_vertices(moved, again, &err), RS_OK);
	assert_int_equal(rs_renderer_stats(moved)->upload_bytes, 0);
	render(moved, a);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&fresh);
	rs_scene_destroy(&again);
	for (int i = 0; i <= count; ++i)
		rs_scene_destroy(&s[i]);
	free(a);
	free(b);
}

static void egl_animated_2d(void **state)
{
	(void)state;
	const uint32_t f[3] = {1, 20, 45};
	check("egl", RS_SCENE_STORAGE_2D, "animated", f, 3, INFINITY);
}

static void egl_animated_auto(void **state)
{
	(void)state;
	const uint32_t f[2] = {7, 37};
	check("egl", RS_SCENE_STORAGE_AUTO, "animated", f, 2, INFINITY);
}

static void egl_cow17_one_cow(void **state)
{
	(void)state;
	const uint32_t f[1] = {10};
	check("egl", RS_SCENE_STORAGE_AUTO, "cow17", f, 1, 0.0);
}

static void osmesa_animated(void **state)
{
	(void)state;
	const uint32_t f[1] = {15};
	check("osmesa", RS_SCENE_STORAGE_AUTO, "animated", f, 1, INFINITY);
}

/* Rebuilt rather than refitted (a ratio nothing passes under): the same image. */
static void egl_rebuild(void **state)
{
	(void)state;
	const uint32_t f[2] = {12, 40};
	check("egl", RS_SCENE_STORAGE_AUTO, "animated", f, 2, 1e-9);
}

/* Shadow maps are captured at set_scene: an update is refused, and the scene stays. */
static void egl_maps_refuse_update(void **state)
{
	(void)state;
	struct rs_render_desc d = {.width = SIZE, .height = SIZE, .shadows = RS_SHADOW_MAP};
	struct rs_renderer *r = gl_open("egl", &d);
	if (!r)
		gl_skip();
	struct rs_scene *a = frame_scene("animated", 0), *b = frame_scene("animated", 1);
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, a, &err), RS_OK);
	assert_int_equal(rs_renderer_update_vertices(r, b, &err), RS_ERR_UNSUPPORTED);
	assert_non_null(strstr(err.message, "shadow"));
	struct image *img = calloc(1, sizeof *img);
	render(r, img);
	free(img);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&a);
	rs_scene_destroy(&b);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(egl_animated_2d),   cmocka_unit_test(egl_animated_auto),
	    cmocka_unit_test(egl_cow17_one_cow), cmocka_unit_test(osmesa_animated),
	    cmocka_unit_test(egl_rebuild),       cmocka_unit_test(egl_maps_refuse_update),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
