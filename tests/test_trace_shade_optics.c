/* rs_trace: reflection, Snell refraction, total internal reflection and Schlick Fresnel. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_trace.h"

/* Directions are unit vectors built from sines and cosines: 1e-12 covers their rounding. */
#define TOL 1e-12

static void unit_dir(double angle_deg, double out[3])
{
	/* in the xz plane, angle from -z (the downward normal direction) towards +x */
	double a = angle_deg * RS_PI / 180.0;
	out[0] = sin(a);
	out[1] = 0.0;
	out[2] = -cos(a);
}

static void reflect_mirrors_the_normal_component(void **state)
{
	double d[3], n[3] = {0, 0, 1}, r[3];
	unit_dir(30, d);
	rs_trace_reflect(d, n, r);
	assert_true(fabs(r[0] - d[0]) < TOL);
	assert_true(fabs(r[1] - d[1]) < TOL);
	assert_true(fabs(r[2] + d[2]) < TOL);
}

static void refract_follows_snell(void **state)
{
	double n[3] = {0, 0, 1}, t[3];
	for (int deg = 0; deg < 90; deg += 7) {
		double d[3];
		unit_dir(deg, d);
		assert_true(rs_trace_refract(d, n, 1.0 / 1.5, t));
		/* n1 sin(i) = n2 sin(t), and the ray keeps going down, in the plane of incidence */
		assert_true(fabs(1.0 * d[0] - 1.5 * t[0]) < TOL);
		assert_true(t[2] < 0.0);
		assert_true(fabs(t[1]) < TOL);
		assert_true(fabs(t[0] * t[0] + t[1] * t[1] + t[2] * t[2] - 1.0) < TOL);
	}
}

static void refract_with_equal_indices_goes_straight(void **state)
{
	double d[3], n[3] = {0, 0, 1}, t[3];
	unit_dir(40, d);
	assert_true(rs_trace_refract(d, n, 1.0, t));
	for (int a = 0; a < 3; ++a)
		assert_true(fabs(t[a] - d[a]) < TOL);
}

static void refract_beyond_critical_angle_is_total_internal_reflection(void **state)
{
	/* glass to air: critical angle asin(1 / 1.5) = 41.81 degrees */
	double d[3], n[3] = {0, 0, 1}, t[3] = {7, 7, 7};
	unit_dir(42, d);
	assert_false(rs_trace_refract(d, n, 1.5, t));
	assert_true(t[0] == 7.0); /* untouched */
	unit_dir(41.5, d);
	assert_true(rs_trace_refract(d, n, 1.5, t));
}

static void fresnel_at_normal_incidence_is_r0(void **state)
{
	/* ((n - 1) / (n + 1))^2 = 0.04 for n = 1.5, either way through the surface */
	assert_true(fabs(rs_trace_fresnel_schlick(1.0, 1.0, 1.5) - 0.04) < TOL);
	assert_true(fabs(rs_trace_fresnel_schlick(1.0, 1.5, 1.0) - 0.04) < TOL);
	assert_true(fabs(rs_trace_fresnel_schlick(1.0, 1.0, 2.0) - 1.0 / 9.0) < TOL);
}

static void fresnel_grows_to_one_at_grazing_incidence(void **state)
{
	assert_true(fabs(rs_trace_fresnel_schlick(0.0, 1.0, 1.5) - 1.0) < TOL);
	double prev = 0.0;
	for (int i = 10; i >= 0; --i) {
		double f = rs_trace_fresnel_schlick(i / 10.0, 1.0, 1.5);
		assert_true(f >= prev);
		prev = f;
	}
}

static void fresnel_is_one_under_total_internal_reflection(void **state)
{
	double cos_i = cos(50.0 * RS_PI / 180.0);
	assert_true(rs_trace_fresnel_schlick(cos_i, 1.5, 1.0) == 1.0);
}

static void fresnel_equal_indices_is_zero_and_bad_indices_are_finite(void **state)
{
	assert_true(rs_trace_fresnel_schlick(0.3, 1.3, 1.3) == 0.0);
	double f = rs_trace_fresnel_schlick(NAN, 0.0, -1.0);
	assert_true(f >= 0.0 && f <= 1.0);
	f = rs_trace_fresnel_schlick(2.0, 1.0, 1.5); /* |cos| > 1 is clamped */
	assert_true(fabs(f - 0.04) < TOL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(reflect_mirrors_the_normal_component),
	    cmocka_unit_test(refract_follows_snell),
	    cmocka_unit_test(refract_with_equal_indices_goes_straight),
	    cmocka_unit_test(refract_beyond_critical_angle_is_total_internal_reflection),
	    cmocka_unit_test(fresnel_at_normal_incidence_is_r0),
	    cmocka_unit_test(fresnel_grows_to_one_at_grazing_incidence),
	    cmocka_unit_test(fresnel_is_one_under_total_internal_reflection),
	    cmocka_unit_test(fresnel_equal_indices_is_zero_and_bad_indices_are_finite),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
