/* rs_pose 1-euro filter and prediction: convergence, jitter reduction, lag on a ramp,
 * quaternion sign flips, capped prediction, timestamps and bad input. The expected
 * figures follow from the first-order low-pass the filter is (docs/pose.md, "Filter"). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "contract.h"
#include "private/rs_vec.h"
#include "raystream/rs_pose.h"
#include "test_pose_fixture.h"

/* Rotation by `angle` about z as a pose with position p. */
static struct rs_pose pose_z(double t, double px, double angle)
{
	struct rs_pose p = {.time_s = t,
	                    .position = {px, 0.2, -0.3},
	                    .orientation = {0.0, 0.0, sin(0.5 * angle), cos(0.5 * angle)}};
	return p;
}

/* Small rotation vector v applied to q (world frame), for orientation noise. */
static void perturb(double q[4], const double v[3])
{
	double d[4];
	rs_q_exp(v, d);
	rs_q_mul(d, q, q);
}

static struct rs_pose_filter *make(const struct rs_pose_filter_desc *d)
{
	struct rs_pose_filter *f = NULL;
	assert_int_equal(rs_pose_filter_create(d, &f, NULL), RS_OK);
	return f;
}

static void test_defaults_are_vrpn(void **state)
{
	(void)state;
	struct rs_pose_filter_desc d;
	rs_pose_filter_desc_resolve(NULL, &d);
	assert_true(d.position_min_cutoff_hz == 1.15 && d.position_beta == 0.5 &&
	            d.position_d_cutoff_hz == 1.2);
	assert_true(d.orientation_min_cutoff_hz == 1.5 && d.orientation_beta == 0.5 &&
	            d.orientation_d_cutoff_hz == 1.2);
	assert_true(d.max_prediction_s == 0.03);
}

/* After a step the output decays like exp(-t / tau), tau <= 1 / (2 pi 1.15 Hz) = 0.138 s;
 * 3 s is > 21 tau, so a 0.1 m / 0.5 rad step is left at < 1e-10 of itself: 1e-9 bound. */
static void test_converges_to_constant(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rs_pose in = pose_z(0.0, 0.0, 0.0), out;
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	struct rs_pose target = pose_z(0.0, 0.1, 0.5);
	for (int i = 1; i <= 300; ++i) {
		target.time_s = 0.01 * i;
		assert_int_equal(rs_pose_filter_update(f, &target, &out, NULL), RS_OK);
	}
	assert_true(fabs(out.position[0] - 0.1) < 1e-9);
	assert_true(rs_pose_angle_between(&out, &target) < 1e-9);
	assert_true(out.time_s == target.time_s);
	rs_pose_filter_destroy(&f);
	assert_null(f);
}

/* A still pose with 0.5 mm / 0.5 deg noise at 200 Hz. The filter is then a first-order
 * low-pass with alpha = dt / (dt + tau): output/input standard deviation
 * sqrt(alpha / (2 - alpha)) = 0.133 for position (1.15 Hz, 7.5x less jitter) and 0.152
 * for orientation (1.5 Hz, 6.6x). Asserted: position 6x..9.5x, orientation 5x..8.5x; the
 * margin covers beta raising the cutoff slightly on noise-driven speed and the sampling
 * error of a standard deviation over ~100 correlation times (~7 %). */
static void test_reduces_jitter_of_still_signal(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rng r = {11};
	const double sp = 0.0005, sa = 0.5 * RS_PI / 180.0;
	double in_p = 0, out_p = 0, in_a = 0, out_a = 0;
	int n = 0;
	struct rs_pose truth = pose_z(0.0, 0.3, 0.7);
	for (int i = 0; i < 4000; ++i) {
		struct rs_pose in = truth, out;
		in.time_s = 0.005 * i;
		double v[3];
		for (int k = 0; k < 3; ++k) {
			in.position[k] += sp * gauss(&r);
			v[k] = sa * gauss(&r);
		}
		perturb(in.orientation, v);
		assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
		if (i < 400)
			continue; /* let the start-up transient pass */
		for (int k = 0; k < 3; ++k) {
			double di = in.position[k] - truth.position[k];
			double dout = out.position[k] - truth.position[k];
			in_p += di * di;
			out_p += dout * dout;
		}
		double ai = rs_pose_angle_between(&in, &truth),
		       ao = rs_pose_angle_between(&out, &truth);
		in_a += ai * ai;
		out_a += ao * ao;
		++n;
	}
	double fp = sqrt(in_p / out_p), fa = sqrt(in_a / out_a);
	print_message("jitter reduction: position %.2fx, orientation %.2fx\n", fp, fa);
	assert_true(fp > 6.0 && fp < 9.5);
	assert_true(fa > 5.0 && fa < 8.5);
	rs_pose_filter_destroy(&f);
}

/* On a ramp the smoothed speed converges to the true speed v, so the cutoff is
 * fc = min_cutoff + beta v and the steady-state lag of the discrete low-pass is exactly
 * v tau = v / (2 pi fc): 0.5 m/s -> 56.8 mm; 1 rad/s -> 0.0796 rad. After 3 s every
 * transient is below 1e-9 of itself, so 0.5 % is rounding margin only. The lag is also
 * bounded by v / (2 pi min_cutoff), what a plain low-pass would give. */
static void test_lag_bounded_on_ramp(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	const double v = 0.5, w = 1.0;
	struct rs_pose in, out;
	for (int i = 0; i <= 600; ++i) {
		double t = 0.005 * i;
		in = pose_z(t, v * t, w * t);
		assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	}
	double lag = in.position[0] - out.position[0];
	double expect = v / (2.0 * RS_PI * (1.15 + 0.5 * v));
	assert_true(fabs(lag - expect) < 0.005 * expect);
	assert_true(lag < v / (2.0 * RS_PI * 1.15));
	double alag = rs_pose_angle_between(&in, &out);
	double aexpect = w / (2.0 * RS_PI * (1.5 + 0.5 * w));
	assert_true(fabs(alag - aexpect) < 0.005 * aexpect);
	rs_pose_filter_destroy(&f);
}

/* The same rotating input, once with canonical quaternions and once with the sign of
 * every other sample (and of random ones) flipped: q and -q are one rotation, so the
 * outputs must agree to rounding (1e-12), and no output step may exceed the input step
 * (15 mrad) by more than 10 %: while the speed estimate and so the cutoff rise at the
 * start the output catches up slightly faster than the input moves (3.3 % measured),
 * whereas a mishandled flip (slerp the long way round) would step by up to pi rad. */
static void test_quaternion_sign_flip_no_jump(void **state)
{
	(void)state;
	struct rs_pose_filter *a = make(NULL), *b = make(NULL);
	struct rng r = {5};
	struct rs_pose prev_out = {0};
	for (int i = 0; i < 1000; ++i) {
		double t = 0.005 * i;
		struct rs_pose in = pose_z(t, 0.0, 3.0 * t), flipped = in, oa, ob;
		if (i % 2 || uniform01(&r) < 0.3)
			for (int k = 0; k < 4; ++k)
				flipped.orientation[k] = -flipped.orientation[k];
		assert_int_equal(rs_pose_filter_update(a, &in, &oa, NULL), RS_OK);
		assert_int_equal(rs_pose_filter_update(b, &flipped, &ob, NULL), RS_OK);
		assert_true(rs_pose_angle_between(&oa, &ob) < 1e-12);
		assert_true(ob.orientation[3] >= 0.0);
		if (i > 0)
			assert_true(rs_pose_angle_between(&prev_out, &ob) <= 1.1 * 3.0 * 0.005);
		prev_out = ob;
	}
	rs_pose_filter_destroy(&a);
	rs_pose_filter_destroy(&b);
}

/* Prediction extrapolates the converged state with the converged velocity (1 m/s,
 * 2 rad/s) by the requested horizon, clamped to [0, 30 ms]. 1e-9: rounding only. */
static void test_prediction_capped(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rs_pose in, out, pred;
	for (int i = 0; i <= 600; ++i) {
		in = pose_z(0.005 * i, 1.0 * 0.005 * i, 2.0 * 0.005 * i);
		rs_pose_filter_update(f, &in, &out, NULL);
	}
	const double horizon[] = {0.01, 1.0, -1.0};
	const double used[] = {0.01, 0.03, 0.0};
	for (int j = 0; j < 3; ++j) {
		assert_int_equal(rs_pose_filter_predict(f, out.time_s + horizon[j], &pred, NULL),
		                 RS_OK);
		assert_true(fabs(pred.position[0] - out.position[0] - used[j]) < 1e-9);
		assert_true(fabs(rs_pose_angle_between(&pred, &out) - 2.0 * used[j]) < 1e-9);
		assert_true(fabs(pred.time_s - (out.time_s + used[j])) < 1e-12);
	}
	rs_pose_filter_destroy(&f);
}

/* disable_filter passes poses through unchanged; prediction then extrapolates the raw
 * pose, which on a ramp lands exactly on the future input (1e-9: rounding). */
static void test_disabled_filter_passes_through(void **state)
{
	(void)state;
	struct rs_pose_filter_desc d = {.disable_filter = 1};
	struct rs_pose_filter *f = make(&d);
	struct rs_pose in, out, pred;
	for (int i = 0; i <= 600; ++i) {
		in = pose_z(0.005 * i, 0.7 * 0.005 * i, 0.0);
		assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
		assert_true(fabs(out.position[0] - in.position[0]) < 1e-15);
	}
	assert_int_equal(rs_pose_filter_predict(f, in.time_s + 0.02, &pred, NULL), RS_OK);
	assert_true(fabs(pred.position[0] - (in.position[0] + 0.7 * 0.02)) < 1e-9);
	rs_pose_filter_destroy(&f);
}

static void test_nonpositive_dt_and_gaps(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rs_pose in = pose_z(1.0, 0.0, 0.0), out, held;
	rs_pose_filter_update(f, &in, &out, NULL);
	in = pose_z(1.01, 0.05, 0.2);
	rs_pose_filter_update(f, &in, &held, NULL);
	/* repeated and backwards timestamps: state unchanged */
	in = pose_z(1.01, 9.0, 1.0);
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	assert_memory_equal(&out, &held, sizeof out);
	in = pose_z(0.5, 9.0, 1.0);
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	assert_memory_equal(&out, &held, sizeof out);
	/* a 1 s gap (> reset_gap_s 0.25): the filter restarts at the new sample */
	in = pose_z(2.01, 3.0, 1.0);
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	assert_true(out.position[0] == 3.0 && rs_pose_angle_between(&out, &in) < 1e-12);
	/* and its velocity restarts at zero: prediction does not fly off */
	assert_int_equal(rs_pose_filter_predict(f, 2.04, &held, NULL), RS_OK);
	assert_true(held.position[0] == 3.0);
	rs_pose_filter_destroy(&f);
}

/* Samples a denormal time apart (1e-310 s) with a 1 m jump: the speed estimate must not
 * overflow (1 m / 1e-310 s is infinite) and turn the state into NaN. With dt ~ 0 the
 * jump barely moves the output (alpha ~ dt / tau ~ 1e-309), so the state stays at the
 * first pose (1e-9: rounding) and predictions stay finite. */
static void test_denormal_dt_stays_finite(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rs_pose in = pose_z(0.0, 0.0, 0.0), out, pred;
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	for (int i = 1; i <= 3; ++i) {
		in = pose_z(1e-310 * i, (double)(i % 2), 3.0 * (i % 2));
		assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
		assert_true(isfinite(out.position[0]) && isfinite(out.orientation[3]));
		assert_true(fabs(out.position[0]) < 1e-9);
	}
	assert_int_equal(rs_pose_filter_predict(f, 0.02, &pred, NULL), RS_OK);
	for (int k = 0; k < 3; ++k)
		assert_true(isfinite(pred.position[k]));
	assert_true(isfinite(pred.orientation[3]) && pred.orientation[3] >= 0.0);
	rs_pose_filter_destroy(&f);
}

/* Positions beyond RS_POSE_MAX_COORD_M are refused like non-finite ones (their differences
 * could overflow); the state is unchanged. */
static void test_huge_position_refused(void **state)
{
	(void)state;
	struct rs_pose_filter *f = make(NULL);
	struct rs_pose in = pose_z(0.0, 1.0, 0.0), out, p;
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	in = pose_z(0.01, -1.7e308, 0.0);
	assert_int_equal(rs_pose_filter_update(f, &in, &p, NULL), RS_ERR_BAD_DATA);
	assert_memory_equal(&p, &out, sizeof p);
	in = pose_z(0.02, 1.7e308, 0.0);
	assert_int_equal(rs_pose_filter_update(f, &in, &p, NULL), RS_ERR_BAD_DATA);
	assert_memory_equal(&p, &out, sizeof p);
	rs_pose_filter_destroy(&f);
}

/* The prediction horizon is capped at RS_POSE_MAX_PREDICTION_S (30 ms: prediction further
 * ahead mostly amplifies jitter); a descriptor asking for more is refused, not obeyed. A
 * prediction at the cap from a fast ramp stays finite and exactly v * 30 ms ahead. */
static void test_prediction_cap_above_30ms_refused(void **state)
{
	(void)state;
	struct rs_pose_filter *f = NULL;
	struct rs_error err;
	struct rs_pose_filter_desc d = {.max_prediction_s = 1e308};
	assert_int_equal(rs_pose_filter_create(&d, &f, &err), RS_ERR_INVALID);
	assert_null(f);
	assert_non_null(strstr(err.message, "max_prediction_s"));
	d.max_prediction_s = RS_POSE_MAX_PREDICTION_S * 1.001;
	assert_int_equal(rs_pose_filter_create(&d, &f, NULL), RS_ERR_INVALID);
	d.max_prediction_s = RS_POSE_MAX_PREDICTION_S;
	f = make(&d);
	struct rs_pose in, out, pred;
	for (int i = 0; i <= 100; ++i) {
		in = pose_z(0.005 * i, 5.0 * 0.005 * i, 0.0);
		assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_OK);
	}
	assert_int_equal(rs_pose_filter_predict(f, 1e308, &pred, NULL), RS_OK);
	assert_true(isfinite(pred.position[0]));
	assert_float_equal(pred.time_s, out.time_s + RS_POSE_MAX_PREDICTION_S, 1e-12);
	rs_pose_filter_destroy(&f);
}

static void test_bad_input(void **state)
{
	(void)state;
	struct rs_pose_filter *f = NULL;
	struct rs_pose_filter_desc neg = {.position_beta = -1.0};
	assert_int_equal(rs_pose_filter_create(&neg, &f, NULL), RS_ERR_INVALID);
	assert_null(f);
	f = make(NULL);
	struct rs_pose in = pose_z(0.0, 0.0, 0.0), out, p;
	assert_int_equal(rs_pose_filter_predict(f, 1.0, &p, NULL), RS_END);
	assert_true(p.orientation[3] == 1.0 && p.position[0] == 0.0);
	in.position[1] = NAN;
	assert_int_equal(rs_pose_filter_update(f, &in, &out, NULL), RS_ERR_BAD_DATA);
	assert_true(isfinite(out.position[1]) && out.orientation[3] == 1.0);
	in = pose_z(0.0, 0.4, 0.3);
	rs_pose_filter_update(f, &in, &out, NULL);
	struct rs_pose bad = pose_z(0.01, 0.0, 0.0);
	memset(bad.orientation, 0, sizeof bad.orientation);
	assert_int_equal(rs_pose_filter_update(f, &bad, &p, NULL), RS_ERR_BAD_DATA);
	assert_memory_equal(&p, &out, sizeof p);
	assert_true(strlen(rs_pose_filter_last_error(f)) > 0);
	bad = pose_z(INFINITY, 0.0, 0.0);
	assert_int_equal(rs_pose_filter_update(f, &bad, &p, NULL), RS_ERR_BAD_DATA);
	assert_memory_equal(&p, &out, sizeof p);
	assert_int_equal(rs_pose_filter_predict(f, NAN, &p, NULL), RS_ERR_INVALID);
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_filter_update(NULL, &in, &out, NULL));
	rs_pose_filter_reset(f);
	assert_int_equal(rs_pose_filter_predict(f, 1.0, &p, NULL), RS_END);
	rs_pose_filter_destroy(&f);
	rs_pose_filter_destroy(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_defaults_are_vrpn),
	    cmocka_unit_test(test_converges_to_constant),
	    cmocka_unit_test(test_reduces_jitter_of_still_signal),
	    cmocka_unit_test(test_lag_bounded_on_ramp),
	    cmocka_unit_test(test_quaternion_sign_flip_no_jump),
	    cmocka_unit_test(test_prediction_capped),
	    cmocka_unit_test(test_disabled_filter_passes_through),
	    cmocka_unit_test(test_nonpositive_dt_and_gaps),
	    cmocka_unit_test(test_denormal_dt_stays_finite),
	    cmocka_unit_test(test_huge_position_refused),
	    cmocka_unit_test(test_prediction_cap_above_30ms_refused),
	    cmocka_unit_test(test_bad_input),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
