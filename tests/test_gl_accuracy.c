/* GL backends (EGL, OSMesa) against the CPU double reference on the paper's scenes: Box,
 * Cow1, Cow5 at 2 passes, 4 lights, exact shadow feelers. The bars sit just under what
 * llvmpipe reaches (docs/gles.md): what differences remain are fp32 against double (ray
 * directions, hit points, environment coordinates), far below one display step. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 96u
/* The issue asks for >= 40 dB and <= 0.1%; llvmpipe reaches 117-137 dB and no pixel off
 * by more than 8/255 (docs/gles.md), so the bars sit just under that. */
#define PSNR_MIN_DB 100.0
#define BAD_SHARE_MAX 0.0005 /* pixels off by more than 8/255 */

static void compare_scene(const char *backend, const char *name, enum rs_triangle_test test)
{
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 4, .triangle_test = test};
	struct rs_renderer *r = gl_open(backend, &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene(name);
	static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	static float dgot[SIZE * SIZE], dwant[SIZE * SIZE];
	gl_render(r, scene, got, dgot);
	gl_reference(&desc, scene, want, dwant);
	struct rs_image_diff diff, ddiff;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	rs_image_compare(dgot, dwant, SIZE, SIZE, 1, 1.0, 1e-3, &ddiff);
	print_message("%s %s %s: PSNR %.2f dB, %.4f%% pixels off by > 8/255, max %.4f; depth "
	              "mismatched %zu\n",
	              backend, name, test == RS_TRIANGLE_WATERTIGHT ? "watertight" : "mt",
	              diff.psnr_db, 100.0 * diff.bad_share, diff.max_abs_error, ddiff.mismatched);
	double mean = 0.0;
	for (size_t i = 0; i < SIZE * SIZE * 3; ++i)
		mean += want[i];
	mean /= SIZE * SIZE * 3;
	assert_true(mean > 0.1); /* a picture, not a blank frame that would match trivially */
	assert_true(diff.psnr_db >= PSNR_MIN_DB);
	assert_true(diff.bad_share <= BAD_SHARE_MAX);
	assert_true(ddiff.mismatched <= SIZE * SIZE / 1000);
	assert_string_equal(rs_renderer_stats(r)->backend, backend);
	rs_scene_destroy(&scene);
	rs_renderer_destroy(&r);
}

static void egl_box(void **state)
{
	compare_scene("egl", "box", RS_TRIANGLE_MOLLER_TRUMBORE);
}
static void egl_cow1(void **state)
{
	compare_scene("egl", "cow1", RS_TRIANGLE_MOLLER_TRUMBORE);
}
static void egl_cow5(void **state)
{
	compare_scene("egl", "cow5", RS_TRIANGLE_MOLLER_TRUMBORE);
}
static void egl_cow1_watertight(void **state)
{
	compare_scene("egl", "cow1", RS_TRIANGLE_WATERTIGHT);
}
static void osmesa_box(void **state)
{
	compare_scene("osmesa", "box", RS_TRIANGLE_MOLLER_TRUMBORE);
}
static void osmesa_cow1(void **state)
{
	compare_scene("osmesa", "cow1", RS_TRIANGLE_MOLLER_TRUMBORE);
}
static void osmesa_cow5(void **state)
{
	compare_scene("osmesa", "cow5", RS_TRIANGLE_MOLLER_TRUMBORE);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(egl_box),     cmocka_unit_test(egl_cow1),
	    cmocka_unit_test(egl_cow5),    cmocka_unit_test(egl_cow1_watertight),
	    cmocka_unit_test(osmesa_box),  cmocka_unit_test(osmesa_cow1),
	    cmocka_unit_test(osmesa_cow5),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
