/* docs/tracer.md R5's floor in the GL kernels: the spawn offset's magnitude is
 * max(|coordinates|, F) with F = max(R / 16, 2^-64), R the scene's half-size. A scene where
 * the floor decides the outcome: a square of side 4e-6 at the centre of a scene 2 wide
 * (two specks at opposite corners make the bounds), lit from 3e-6 above. With the floor,
 * delta = 2^-16 * 1/16 ~ 9.5e-7, so both triangles are less than 12 delta high and every
 * spawn point goes to the triangle's centroid: each triangle is one flat colour. Without
 * it (delta = 2^-16 * 2e-6) the point stays where the ray hit and N.L sweeps across the
 * square. The kernels once applied only the 2^-64 floor, and this test failed on them
 * (docs/tracer.md, R5). EGL; skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_trace_render_fixture.h"

#define SIZE 64u
#define HALF 2e-6 /* the square's half side */

static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3];

static struct rs_scene *speck_scene(void)
{
	struct rs_scene *scene = fx_scene();
	struct rs_material m = {.diffuse = {0.8f, 0.8f, 0.8f}};
	uint32_t mat = fx_material(scene, m);
	fx_rect(scene, 2, 0.0, -HALF, HALF, -HALF, HALF, 0, mat);
	/* far specks at two opposite corners: bounds [-1, 1]^3, centre 0 (the packed origin) */
	fx_rect(scene, 2, 1.0, 0.99, 1.0, 0.99, 1.0, 0, mat);
	fx_rect(scene, 2, -1.0, -1.0, -0.99, -1.0, -0.99, 1, mat);
	const double eye[3] = {0.0, -1.5 * HALF, 4.0 * HALF}, target[3] = {0.0, 0.0, 0.0};
	fx_camera(scene, eye, target, SIZE);
	fx_light(scene, 0.3 * HALF, 0.2 * HALF, 1.5 * HALF, 1, 1, 1);
	return scene;
}

static void floor_decides_the_spawn_point(void **state)
{
	(void)state;
	struct rs_scene *scene = speck_scene();
	struct rs_render_desc desc = {.passes = 1};
	if (!gl_frame("egl", &desc, scene, got, NULL, NULL)) {
		rs_scene_destroy(&scene);
		skip();
	}
	gl_reference(&desc, scene, want, NULL);
	/* The square is grey (lit white), the default environment coloured. */
	size_t square = 0;
	for (size_t i = 0; i < SIZE * SIZE; ++i)
		square += want[3 * i] == want[3 * i + 2] && want[3 * i + 1] > 0.2f;
	assert_true(square > SIZE * SIZE / 4);
	struct rs_image_diff diff;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 2.0 / 255.0, &diff);
	size_t off = (size_t)(diff.bad_share * SIZE * SIZE + 0.5);
	print_message("GL against the CPU: %zu of the square's %zu pixels off by > 2/255, max "
	              "%.4f, PSNR %.1f dB\n",
	              off, square, diff.max_abs_error, diff.psnr_db);
	/* Pixels on the diagonal may see either triangle in fp32 and in double. */
	assert_true(off <= 8);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(floor_decides_the_spawn_point),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
