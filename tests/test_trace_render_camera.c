/* rs_trace: primary ray generation (pinhole, pixel centres, row 0 = top, vertical fov). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_trace.h"

/* Unit directions from a handful of double operations: 1e-12 covers their rounding. */
#define TOL 1e-12

static const struct rs_camera cam = {.eye = {1, 2, 3},
                                     .target = {1, 2, -7},
                                     .up = {0, 1, 0},
                                     .fov_y_deg = 60,
                                     .width = 64,
                                     .height = 32};

static double angle_between(const double a[3], const double b[3])
{
	double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
	return acos(fmin(fmax(d, -1.0), 1.0));
}

static void image_centre_looks_at_the_target(void **state)
{
	struct rs_ray ray;
	rs_trace_camera_ray(&cam, 0, 0, 32.0, 16.0, &ray);
	assert_true(fabs(ray.dir[0]) < TOL && fabs(ray.dir[1]) < TOL);
	assert_true(fabs(ray.dir[2] + 1.0) < TOL);
	for (int a = 0; a < 3; ++a)
		assert_true(ray.origin[a] == cam.eye[a]);
	assert_true(ray.tmin == 0.0 && isinf(ray.tmax) && ray.skip_slot == RS_NO_SLOT);
}

static void top_and_bottom_edges_span_the_vertical_fov(void **state)
{
	struct rs_ray top, bottom;
	rs_trace_camera_ray(&cam, 0, 0, 32.0, 0.0, &top);
	rs_trace_camera_ray(&cam, 0, 0, 32.0, 32.0, &bottom);
	assert_true(fabs(angle_between(top.dir, bottom.dir) - 60.0 * RS_PI / 180.0) < 1e-9);
	assert_true(top.dir[1] > 0.0); /* row 0 is the top of the image */
	assert_true(bottom.dir[1] < 0.0);
}

static void pixels_are_square_and_x_grows_to_the_right(void **state)
{
	/* half width in the image plane = tan(30 deg) * 64 / 32 */
	struct rs_ray left, right;
	rs_trace_camera_ray(&cam, 0, 0, 0.0, 16.0, &left);
	rs_trace_camera_ray(&cam, 0, 0, 64.0, 16.0, &right);
	double half = tan(30.0 * RS_PI / 180.0) * 2.0;
	assert_true(fabs(right.dir[0] / -right.dir[2] - half) < 1e-12);
	assert_true(fabs(left.dir[0] / -left.dir[2] + half) < 1e-12);
}

static void pixel_centres_are_at_half_offsets(void **state)
{
	/* pixel (x, y) is traced through (x + 0.5, y + 0.5): rs_trace_render's contract */
	struct rs_ray ray;
	rs_trace_camera_ray(&cam, 0, 0, 0.5, 0.5, &ray);
	double b = tan(30.0 * RS_PI / 180.0);
	double sx = (2.0 * 0.5 / 64.0 - 1.0) * b * 2.0;
	double sy = (1.0 - 2.0 * 0.5 / 32.0) * b;
	double len = sqrt(1.0 + sx * sx + sy * sy);
	assert_true(fabs(ray.dir[0] - sx / len) < TOL);
	assert_true(fabs(ray.dir[1] - sy / len) < TOL);
	assert_true(fabs(ray.dir[2] + 1.0 / len) < TOL);
}

static void lens_shift_moves_the_window_off_axis(void **state)
{
	/* A shift of (0.5, -0.25) half-heights moves the image centre's ray to the point
	 * (0.5 b, -0.25 b) of the image plane at distance 1, b = tan(30 deg); the eye and the
	 * view direction stay, and a zero shift changes no bit. */
	struct rs_camera shifted = cam;
	shifted.shift[0] = 0.5;
	shifted.shift[1] = -0.25;
	struct rs_ray ray, plain, zero;
	rs_trace_camera_ray(&shifted, 0, 0, 32.0, 16.0, &ray);
	double b = tan(30.0 * RS_PI / 180.0);
	assert_true(fabs(ray.dir[0] / -ray.dir[2] - 0.5 * b) < TOL);
	assert_true(fabs(ray.dir[1] / -ray.dir[2] + 0.25 * b) < TOL);
	for (int a = 0; a < 3; ++a)
		assert_true(ray.origin[a] == cam.eye[a]);
	struct rs_camera unshifted = cam;
	unshifted.shift[0] = unshifted.shift[1] = 0.0;
	rs_trace_camera_ray(&cam, 0, 0, 5.5, 7.5, &plain);
	rs_trace_camera_ray(&unshifted, 0, 0, 5.5, 7.5, &zero);
	assert_memory_equal(plain.dir, zero.dir, sizeof plain.dir);
}

static void explicit_size_overrides_the_camera_size(void **state)
{
	/* a 32x32 image of the same camera: aspect 1, so the right edge is at tan(30 deg) */
	struct rs_ray right;
	rs_trace_camera_ray(&cam, 32, 32, 32.0, 16.0, &right);
	assert_true(fabs(right.dir[0] / -right.dir[2] - tan(30.0 * RS_PI / 180.0)) < 1e-12);
}

static void zero_fov_means_45_degrees(void **state)
{
	struct rs_camera c = cam;
	c.fov_y_deg = 0.0;
	struct rs_ray top, bottom;
	rs_trace_camera_ray(&c, 0, 0, 32.0, 0.0, &top);
	rs_trace_camera_ray(&c, 0, 0, 32.0, 32.0, &bottom);
	assert_true(fabs(angle_between(top.dir, bottom.dir) - 45.0 * RS_PI / 180.0) < 1e-9);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(image_centre_looks_at_the_target),
	    cmocka_unit_test(top_and_bottom_edges_span_the_vertical_fov),
	    cmocka_unit_test(pixels_are_square_and_x_grows_to_the_right),
	    cmocka_unit_test(pixel_centres_are_at_half_offsets),
	    cmocka_unit_test(lens_shift_moves_the_window_off_axis),
	    cmocka_unit_test(explicit_size_overrides_the_camera_size),
	    cmocka_unit_test(zero_fov_means_45_degrees),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
