/* The pose solver's consistency gate and temporal label prior (issue 19): on a moving
 * sequence the predicted pose settles marker ids the side lengths cannot (2 mm of marker
 * noise: >= 90 % solved, none beyond 5x its stated error), the residual and step gates
 * refuse few clean samples (<= 0.1 %), and a marker displaced out of the display's plane
 * or a swapped labelling is held with the reason, never reported good. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "test_pose_fixture.h"

#define RATE_HZ 120.0

/* A handheld display's motion: 1 m in front of the tracker, swaying 10 cm and turning up
 * to ~40 degrees about two axes at fractions of a hertz, with a 4 Hz shake. */
static void motion(double t, struct rs_pose *T)
{
	double ax = 0.5 * sin(2 * RS_PI * 0.23 * t) + 0.03 * sin(2 * RS_PI * 4.0 * t);
	double ay = 0.7 * sin(2 * RS_PI * 0.17 * t + 1.0);
	double qx[4] = {sin(ax / 2), 0, 0, cos(ax / 2)}, qy[4] = {0, sin(ay / 2), 0, cos(ay / 2)};
	T->orientation[0] = qy[3] * qx[0];
	T->orientation[1] = qy[1] * qx[3];
	T->orientation[2] = -qy[1] * qx[0];
	T->orientation[3] = qy[3] * qx[3];
	T->position[0] = 0.1 * sin(2 * RS_PI * 0.31 * t);
	T->position[1] = 0.05 * sin(2 * RS_PI * 0.13 * t + 2.0);
	T->position[2] = 1.0 + 0.1 * sin(2 * RS_PI * 0.07 * t);
	T->time_s = t;
}

struct tally {
	int n, good, beyond, gated, ambiguous;
	double worst;
};

static struct tally run_sequence(double sigma, int n, uint64_t seed)
{
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver_desc d = {.noise_sigma_m = sigma};
	struct rs_pose_solver *s = NULL;
	assert_int_equal(rs_pose_solver_create(&d, &L, &s, NULL), RS_OK);
	struct rng r = {.s = seed};
	struct tally t = {0};
	for (int i = 0; i < n; ++i) {
		struct rs_pose T, out;
		struct rs_marker_sample smp;
		struct rs_pose_quality q;
		motion(i / RATE_HZ, &T);
		make_sample(&L, &T, sigma, &r, T.time_s, &smp);
		assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
		t.n++;
		const char *why = rs_pose_solver_last_error(s);
		if (q.status != RS_POSE_OK && q.status != RS_POSE_RELABELED) {
			assert_true(why[0]); /* every held sample says why */
			t.gated += strstr(why, "residual") || strstr(why, "step");
			t.ambiguous += strstr(why, "ambiguous") != NULL;
			continue;
		}
		t.good++;
		double ra = rs_pose_angle_between(&out, &T) / q.rotation_rms_rad;
		double rp = pos_error(&out, &T) / q.position_rms_m;
		double ratio = ra > rp ? ra : rp;
		t.worst = ratio > t.worst ? ratio : t.worst;
		t.beyond += ratio > 5.0;
	}
	rs_pose_solver_destroy(&s);
	return t;
}

/* 2 mm of marker noise: side lengths alone label 11 % of samples (docs/pose.md); with the
 * predicted pose >= 90 %, and no good pose beyond 5x its stated error. */
static void test_prior_labels_a_moving_sequence_at_2mm(void **state)
{
	(void)state;
	struct tally t = run_sequence(0.002, 6000, 7);
	printf("# 2 mm, %d samples at %.0f Hz: %.1f %% solved, worst error/stated %.2f, %d "
	       "beyond 5x, %d gated, %d ambiguous\n",
	       t.n, RATE_HZ, 100.0 * t.good / t.n, t.worst, t.beyond, t.gated, t.ambiguous);
	assert_true(t.good >= 0.9 * t.n);
	assert_int_equal(t.beyond, 0);
}

/* Clean data at the documented noise: the residual and step gates refuse <= 0.1 %. */
static void test_gate_false_alarms_on_clean_data(void **state)
{
	(void)state;
	const double sigmas[] = {0.0001, 0.0005, 0.001};
	for (size_t k = 0; k < sizeof sigmas / sizeof sigmas[0]; ++k) {
		struct tally t = run_sequence(sigmas[k], 12000, 11 + k);
		printf("# %.1f mm: %d of %d clean samples refused by the gate (%.3f %%), worst "
		       "error/stated %.2f\n",
		       sigmas[k] * 1e3, t.gated, t.n, 100.0 * t.gated / t.n, t.worst);
		assert_true(t.gated <= 0.001 * t.n);
		assert_int_equal(t.beyond, 0);
	}
}

/* While tracked: one marker moved 12 mm out of the display's plane (a stray spot on a
 * hidden marker's line of sight) jumps the pose ~7 degrees: held, with the reason. */
static void test_step_gate_holds_a_jump(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver_desc d = {.noise_sigma_m = 0.0002};
	struct rs_pose_solver *s = NULL;
	assert_int_equal(rs_pose_solver_create(&d, &L, &s, NULL), RS_OK);
	struct rng r = {.s = 5};
	struct rs_pose T, out;
	struct rs_marker_sample smp;
	struct rs_pose_quality q;
	for (int i = 0; i < 20; ++i) {
		motion(i / RATE_HZ, &T);
		make_sample(&L, &T, 0.0002, &r, T.time_s, &smp);
		assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
		assert_int_equal(q.status, RS_POSE_OK);
	}
	motion(20 / RATE_HZ, &T);
	make_sample(&L, &T, 0.0, &r, T.time_s, &smp);
	/* marker 2 pushed 12 mm along the display normal (the marker frame's z axis) */
	double n[3], z[3] = {0, 0, 0.012}, o[3] = {0, 0, 0};
	rs_pose_transform_point(&T, z, n);
	rs_pose_transform_point(&T, o, o);
	for (int k = 0; k < 3; ++k)
		smp.markers[2].position[k] += n[k] - o[k];
	assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
	assert_int_equal(q.status, RS_POSE_HELD);
	assert_non_null(strstr(rs_pose_solver_last_error(s), "step"));
	/* without history the same sample is solved (the side lengths barely change) */
	rs_pose_solver_reset(s);
	assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
	assert_int_equal(q.status, RS_POSE_OK);
	rs_pose_solver_destroy(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_prior_labels_a_moving_sequence_at_2mm),
	    cmocka_unit_test(test_gate_false_alarms_on_clean_data),
	    cmocka_unit_test(test_step_gate_holds_a_jump),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
