/* Cube shadow maps with a box filter against exact shadow feelers (the CPU reference):
 * the error of a few map settings on Box and Cow1, bars just under what llvmpipe reaches
 * (docs/gles.md has the full table); no feelers are cast in map mode. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 128u

static void map_error(const char *name, uint32_t map, uint32_t filter, double psnr_min,
                      double bad_max)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .lights = 4,
	                              .shadows = RS_SHADOW_MAP,
	                              .shadow_map_size = map,
	                              .shadow_filter = filter,
	                              .counters = true};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		skip();
	struct rs_scene *scene = gl_scene(name);
	static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	gl_render(r, scene, got, NULL);
	assert_int_equal(rs_renderer_stats(r)->shadow_rays, 0);
	desc.shadows = RS_SHADOW_RAYS;
	gl_reference(&desc, scene, want, NULL);
	/* Compared as displayed (clamped to [0, 1]): with 4 lights most lit pixels exceed 1,
	 * where a light more or less changes nothing on screen. */
	for (size_t i = 0; i < SIZE * SIZE * 3; ++i) {
		got[i] = fminf(fmaxf(got[i], 0.0f), 1.0f);
		want[i] = fminf(fmaxf(want[i], 0.0f), 1.0f);
	}
	struct rs_image_diff diff;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	print_message("%s map %u filter %u: PSNR %.2f dB, %.3f%% pixels off by > 8/255\n", name,
	              map, filter, diff.psnr_db, 100.0 * diff.bad_share);
	assert_true(diff.psnr_db >= psnr_min);
	assert_true(diff.bad_share <= bad_max);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void box_map_1024_unfiltered(void **state)
{
	map_error("box", 1024, 1, 40.0, 0.001);
}
static void box_map_512_box3(void **state)
{
	map_error("box", 512, 3, 36.0, 0.007);
}
static void cow1_map_1024_unfiltered(void **state)
{
	map_error("cow1", 1024, 1, 36.0, 0.007);
}
static void cow1_map_256_box5(void **state)
{
	map_error("cow1", 256, 5, 27.5, 0.06);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(box_map_1024_unfiltered),
	    cmocka_unit_test(box_map_512_box3),
	    cmocka_unit_test(cow1_map_1024_unfiltered),
	    cmocka_unit_test(cow1_map_256_box5),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
