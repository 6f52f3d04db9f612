/* rs_pose solver hard cases: degenerate, missing, swapped, far-away, non-finite markers and
 * quaternion hemispheres. Each must give a defined pose (never NaN) and the right status. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <string.h>

#include "contract.h"
#include "raystream/rs_pose.h"
#include "test_pose_fixture.h"

/* Finite, unit quaternion, canonical hemisphere. */
static int pose_sane(const struct rs_pose *p)
{
	double n = 0.0;
	for (int k = 0; k < 4; ++k) {
		if (!isfinite(p->orientation[k]))
			return 0;
		n += p->orientation[k] * p->orientation[k];
	}
	for (int k = 0; k < 3; ++k)
		if (!isfinite(p->position[k]))
			return 0;
	return isfinite(p->time_s) && fabs(n - 1.0) < 1e-9 && p->orientation[3] >= 0.0;
}

static int is_identity(const struct rs_pose *p)
{
	return p->position[0] == 0.0 && p->position[1] == 0.0 && p->position[2] == 0.0 &&
	       p->orientation[3] == 1.0;
}

struct fixture {
	struct rs_pose_layout L;
	struct rs_pose_solver *s;
	struct rng r;
	struct rs_pose truth;
};

static struct fixture *setup_with(const struct rs_pose_solver_desc *d)
{
	static struct fixture f;
	memset(&f, 0, sizeof f);
	rs_pose_layout_default(&f.L);
	/* These cases feed unrelated poses (and impossible jumps, for the velocity estimate's
	 * robustness): the step gate is tested in test_pose_gate.c. */
	struct rs_pose_solver_desc dd = {0};
	if (d)
		dd = *d;
	dd.independent_samples = 1;
	assert_int_equal(rs_pose_solver_create(&dd, &f.L, &f.s, NULL), RS_OK);
	f.r.s = 42;
	random_pose(&f.r, 1.0, &f.truth);
	return &f;
}

/* A solved sample at time t, so the solver has a pose to hold. */
static struct rs_pose solve_good(struct fixture *f, double t)
{
	struct rs_marker_sample smp;
	struct rs_pose out;
	struct rs_pose_quality q;
	make_sample(&f->L, &f->truth, 0.0, &f->r, t, &smp);
	assert_int_equal(rs_pose_solver_update(f->s, &smp, &out, &q), RS_OK);
	assert_int_equal(q.status, RS_POSE_OK);
	return out;
}

static enum rs_pose_status run(struct fixture *f, const struct rs_marker_sample *smp,
                               struct rs_pose *out)
{
	struct rs_pose_quality q;
	assert_int_equal(rs_pose_solver_update(f->s, smp, out, &q), RS_OK);
	assert_true(pose_sane(out));
	assert_true(isfinite(q.residual_rms_m) && isfinite(q.min_height_m));
	if (q.status >= RS_POSE_HELD)
		assert_true(strlen(rs_pose_solver_last_error(f->s)) > 0);
	return q.status;
}

static void teardown(struct fixture *f)
{
	rs_pose_solver_destroy(&f->s);
}

static void test_collinear_before_any_pose_is_none(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 1.0, &smp);
	for (int k = 0; k < 3; ++k) /* marker 2 onto the midpoint of 0 and 1 */
		smp.markers[2].position[k] =
		    0.5 * (smp.markers[0].position[k] + smp.markers[1].position[k]);
	assert_int_equal(run(f, &smp, &out), RS_POSE_NONE);
	assert_true(is_identity(&out));
	assert_true(out.time_s == 1.0);
	teardown(f);
}

static void test_collinear_and_coincident_hold_last_pose(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	struct rs_pose good = solve_good(f, 0.0);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.01, &smp);
	for (int k = 0; k < 3; ++k)
		smp.markers[2].position[k] =
		    2.0 * smp.markers[1].position[k] - smp.markers[0].position[k];
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	assert_true(memcmp(out.orientation, good.orientation, sizeof out.orientation) == 0);
	assert_true(pos_error(&out, &good) == 0.0);
	assert_true(out.time_s == 0.01);
	memcpy(smp.markers[1].position, smp.markers[0].position, sizeof smp.markers[0].position);
	memcpy(smp.markers[2].position, smp.markers[0].position, sizeof smp.markers[0].position);
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	assert_true(pos_error(&out, &good) == 0.0);
	teardown(f);
}

/* The gate compares the smallest height (0.0707 m here) with min_height_sigmas * sigma.
 * (At 1 mm the ids are still clear from the side lengths; at 7 mm they never are.) */
static void test_height_gate_threshold(void **state)
{
	(void)state;
	struct rs_pose_solver_desc below = {.noise_sigma_m = 0.001, .min_height_sigmas = 70};
	struct rs_pose_solver_desc above = {.noise_sigma_m = 0.001, .min_height_sigmas = 71};
	struct rs_marker_sample smp;
	struct rs_pose out;
	struct fixture *f = setup_with(&below);
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.0, &smp);
	assert_int_equal(run(f, &smp, &out), RS_POSE_OK);
	teardown(f);
	f = setup_with(&above);
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.0, &smp);
	assert_int_equal(run(f, &smp, &out), RS_POSE_NONE);
	teardown(f);
}

static void test_missing_invalid_occluded_marker_holds(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	solve_good(f, 0.0);
	struct rs_marker_sample smp;
	struct rs_pose out;
	struct rs_pose_quality q;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.01, &smp);
	smp.marker_count = 2;
	assert_int_equal(rs_pose_solver_update(f->s, &smp, &out, &q), RS_OK);
	assert_int_equal(q.status, RS_POSE_HELD);
	assert_int_equal(q.markers_used, 2);
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.02, &smp);
	smp.markers[1].flags = 0;
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.03, &smp);
	smp.markers[0].flags |= RS_MARKER_OCCLUDED;
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.04, &smp);
	smp.marker_count = 4;
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	teardown(f);
}

static const uint32_t k_perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                       {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

/* Every relabelling of the ids, and every order of the markers in the sample, at 0.5 mm
 * noise: the solved pose must be the true one (error far below a mislabel's tens of
 * degrees: 5 deg is > 7 RMS errors at this noise) and the status must say RELABELED
 * exactly when the reported ids were wrong. */
static void test_swapped_ids_relabeled(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	for (int trial = 0; trial < 600; ++trial) {
		const uint32_t *id_perm = k_perms[trial % 6];
		const uint32_t *order = k_perms[(trial / 6) % 6];
		struct rs_marker_sample smp, shuffled;
		struct rs_pose out;
		random_pose(&f->r, 1.0, &f->truth);
		make_sample(&f->L, &f->truth, 0.0005, &f->r, 0.001 * trial, &smp);
		shuffled = smp;
		for (int j = 0; j < 3; ++j) {
			shuffled.markers[j] = smp.markers[order[j]];
			shuffled.markers[j].id = id_perm[order[j]];
		}
		enum rs_pose_status st = run(f, &shuffled, &out);
		assert_int_equal(st, trial % 6 == 0 ? RS_POSE_OK : RS_POSE_RELABELED);
		assert_true(rs_pose_angle_between(&out, &f->truth) < 5.0 * RS_PI / 180.0);
		assert_true(pos_error(&out, &f->truth) < 0.01);
	}
	teardown(f);
}

static void test_duplicate_or_unknown_ids_relabeled(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.0, &smp);
	smp.markers[0].id = smp.markers[1].id = smp.markers[2].id = 0;
	assert_int_equal(run(f, &smp, &out), RS_POSE_RELABELED);
	assert_true(rs_pose_angle_between(&out, &f->truth) < 1e-9);
	smp.markers[0].id = 0;
	smp.markers[1].id = 77;
	smp.markers[2].id = 0xffffffffu;
	assert_int_equal(run(f, &smp, &out), RS_POSE_RELABELED);
	assert_true(pos_error(&out, &f->truth) < 1e-9);
	teardown(f);
}

/* Markers 10 km from the origin. Exact data: rounding of 1e4 m coordinates is ~2e-12 m,
 * so 1e-9 rad and 1e-9 m hold with margin. With 0.5 mm noise the RMS rotation error must
 * match the near-origin law (0.68 deg, test_pose_solver) within 10 %: without centring
 * first, the accumulated products (~1e8 m^2) would lose ~8 digits of the ~1e-3 m^2 signal. */
static void test_far_from_origin(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	double sum = 0.0;
	const int n = 3000;
	for (int trial = 0; trial < n; ++trial) {
		struct rs_marker_sample smp;
		struct rs_pose out;
		random_pose(&f->r, 1.0, &f->truth);
		f->truth.position[0] += 1e4;
		f->truth.position[1] -= 1e4;
		f->truth.position[2] += 1e4;
		make_sample(&f->L, &f->truth, 0.0, &f->r, 0.001 * trial, &smp);
		assert_int_equal(run(f, &smp, &out), RS_POSE_OK);
		assert_true(rs_pose_angle_between(&out, &f->truth) < 1e-9);
		assert_true(pos_error(&out, &f->truth) < 1e-9);
		make_sample(&f->L, &f->truth, 0.0005, &f->r, 0.001 * trial + 0.0005, &smp);
		assert_int_equal(run(f, &smp, &out), RS_POSE_OK);
		double a = rs_pose_angle_between(&out, &f->truth);
		sum += a * a;
	}
	double rms_deg = sqrt(sum / n) * 180.0 / RS_PI;
	assert_true(rms_deg > 0.9 * 0.680 && rms_deg < 1.1 * 0.680);
	teardown(f);
}

static void test_nan_inf_huge_markers_hold(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	struct rs_pose good = solve_good(f, 0.0);
	const double bad[] = {NAN, INFINITY, -INFINITY, 1e300, -2e6};
	for (int i = 0; i < 5; ++i) {
		struct rs_marker_sample smp;
		struct rs_pose out;
		struct rs_pose_quality q;
		make_sample(&f->L, &f->truth, 0.0, &f->r, 0.01 * (i + 1), &smp);
		smp.markers[i % 3].position[i % 3] = bad[i];
		assert_int_equal(rs_pose_solver_update(f->s, &smp, &out, &q), RS_OK);
		assert_int_equal(q.status, RS_POSE_HELD);
		assert_int_equal(q.markers_used, 2);
		assert_true(pose_sane(&out) && pos_error(&out, &good) == 0.0);
	}
	teardown(f);
}

static void test_nan_timestamp_holds_at_last_time(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	solve_good(f, 2.5);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, NAN, &smp);
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	assert_true(out.time_s == 2.5);
	teardown(f);
}

static void test_hold_timeout_gives_none(void **state)
{
	(void)state;
	struct rs_pose_solver_desc d = {.hold_timeout_s = 0.2};
	struct fixture *f = setup_with(&d);
	solve_good(f, 1.0);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 1.19, &smp);
	smp.marker_count = 1;
	assert_int_equal(run(f, &smp, &out), RS_POSE_HELD);
	smp.host_time_s = 1.21;
	assert_int_equal(run(f, &smp, &out), RS_POSE_NONE);
	assert_true(is_identity(&out));
	solve_good(f, 1.3); /* and it recovers */
	teardown(f);
}

/* Constant linear (1 m/s along x) and angular (1 rad/s about z) velocity at 100 Hz for
 * 2 s: the velocity estimate (time constant 0.05 s, so alpha = 1/6 per sample) has
 * converged to (5/6)^200 ~ 1e-16, so a lost sample 10 ms later is extrapolated by
 * 10 mm / 0.01 rad, and one 100 ms later only by the 30 ms cap. Tolerances 1e-6 m / rad
 * leave room for rounding only. */
static void test_predict_when_lost_is_capped(void **state)
{
	(void)state;
	struct rs_pose_solver_desc d = {.predict_when_lost = 1};
	struct fixture *f = setup_with(&d);
	struct rs_pose base = f->truth, last;
	for (int i = 0; i <= 200; ++i) {
		double t = 0.01 * i;
		f->truth = base;
		f->truth.position[0] += t;
		double rz[4] = {0, 0, sin(0.5 * t), cos(0.5 * t)}, q[4];
		const double *b = base.orientation;
		q[0] = rz[3] * b[0] - rz[2] * b[1];
		q[1] = rz[3] * b[1] + rz[2] * b[0];
		q[2] = rz[3] * b[2] + rz[2] * b[3];
		q[3] = rz[3] * b[3] - rz[2] * b[2];
		memcpy(f->truth.orientation, q, sizeof q);
		last = solve_good(f, t);
	}
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 2.01, &smp);
	smp.marker_count = 0;
	assert_int_equal(run(f, &smp, &out), RS_POSE_PREDICTED);
	assert_true(fabs(out.position[0] - last.position[0] - 0.01) < 1e-6);
	assert_true(fabs(rs_pose_angle_between(&out, &last) - 0.01) < 1e-6);
	smp.host_time_s = 2.1;
	assert_int_equal(run(f, &smp, &out), RS_POSE_PREDICTED);
	assert_true(fabs(out.position[0] - last.position[0] - 0.03) < 1e-6);
	assert_true(fabs(rs_pose_angle_between(&out, &last) - 0.03) < 1e-6);
	assert_true(out.time_s == 2.1);
	teardown(f);
}

/* Two solved samples a denormal time apart (1e-310 s) and 0.1 m apart: the velocity for
 * PREDICTED must stay finite (a naive 0.1 m / 1e-310 s overflows to infinity), so the
 * prediction of the next lost sample is a finite pose. */
static void test_tiny_dt_velocity_stays_finite(void **state)
{
	(void)state;
	struct rs_pose_solver_desc d = {.predict_when_lost = 1};
	struct fixture *f = setup_with(&d);
	solve_good(f, 0.0);
	f->truth.position[0] += 0.1;
	solve_good(f, 1e-310);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 0.01, &smp);
	smp.marker_count = 0;
	assert_int_equal(run(f, &smp, &out), RS_POSE_PREDICTED);
	/* The smoothed velocity is at most 0.1 m / 0.05 s (the time constant): 2 m/s, so the
	 * 10 ms extrapolation moves it by at most 20 mm. */
	assert_true(pos_error(&out, &f->truth) <= 0.02 + 1e-9);
	teardown(f);
}

/* max_prediction_s above RS_POSE_MAX_PREDICTION_S is refused; with the largest allowed cap
 * and an absurd hold_timeout_s a 100 m/s pose lost for 1e308 s is extrapolated by exactly
 * the 30 ms cap (3 m), finite. */
static void test_prediction_cap_above_30ms_refused(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver *s = NULL;
	struct rs_error err;
	struct rs_pose_solver_desc bad = {.predict_when_lost = 1, .max_prediction_s = 1e308};
	assert_int_equal(rs_pose_solver_create(&bad, &L, &s, &err), RS_ERR_INVALID);
	assert_null(s);
	assert_non_null(strstr(err.message, "max_prediction_s"));
	bad.max_prediction_s = 0.031;
	assert_int_equal(rs_pose_solver_create(&bad, &L, &s, NULL), RS_ERR_INVALID);
	struct rs_pose_solver_desc d = {.predict_when_lost = 1,
	                                .max_prediction_s = RS_POSE_MAX_PREDICTION_S,
	                                .hold_timeout_s = 1e308,
	                                .velocity_time_constant_s = 1e-9};
	struct fixture *f = setup_with(&d);
	solve_good(f, 0.0);
	f->truth.position[0] += 1.0; /* 100 m/s between the two samples */
	struct rs_pose good = solve_good(f, 0.01);
	struct rs_marker_sample smp;
	struct rs_pose out;
	make_sample(&f->L, &f->truth, 0.0, &f->r, 1e308, &smp);
	smp.marker_count = 0;
	assert_int_equal(run(f, &smp, &out), RS_POSE_PREDICTED);
	assert_float_equal(pos_error(&out, &good), 100.0 * RS_POSE_MAX_PREDICTION_S, 1e-6);
	teardown(f);
}

/* Rotations near 180 degrees (w ~ 0, either sign of the truth quaternion): the output is
 * always in the w >= 0 hemisphere, the same for q and -q, and the right rotation. */
static void test_output_hemisphere_canonical(void **state)
{
	(void)state;
	struct fixture *f = setup_with(NULL);
	for (int i = 0; i < 200; ++i) {
		double w = (i % 2 ? 1.0 : -1.0) * 1e-3 * (i / 2) / 100.0;
		double axis[3] = {gauss(&f->r), gauss(&f->r), gauss(&f->r)};
		double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
		double s = sqrt(1.0 - w * w);
		for (int k = 0; k < 3; ++k)
			f->truth.orientation[k] = s * axis[k] / n;
		f->truth.orientation[3] = w;
		struct rs_marker_sample smp;
		struct rs_pose out;
		make_sample(&f->L, &f->truth, 0.0, &f->r, 0.001 * i, &smp);
		assert_int_equal(run(f, &smp, &out), RS_POSE_OK);
		assert_true(rs_pose_angle_between(&out, &f->truth) < 1e-9);
	}
	teardown(f);
}

/* 2 x 51100 x 49/50 > 10^5 random degenerate samples (exactly or nearly collinear, coincident,
 * NaN/Inf/huge coordinates, too few or invalid markers; garbage ids on the collinear ones),
 * interleaved with a good sample every 50: never NaN, and exactly HELD/PREDICTED once a
 * pose exists, NONE before. */
static void test_random_degenerate_configurations(void **state)
{
	(void)state;
	for (int predict = 0; predict < 2; ++predict) {
		struct rs_pose_solver_desc d = {.predict_when_lost = predict};
		struct fixture *f = setup_with(&d);
		f->r.s = 7 + (uint64_t)predict;
		const double gate = 10 * 0.0005;
		int have_pose = 0;
		for (int i = 0; i < 51100; ++i) {
			double t = 0.001 * i;
			if (i % 50 == 49) {
				random_pose(&f->r, 5.0, &f->truth);
				solve_good(f, t);
				have_pose = 1;
				continue;
			}
			struct rs_marker_sample smp;
			struct rs_pose out;
			memset(&smp, 0, sizeof smp);
			smp.host_time_s = t;
			smp.marker_count = 3;
			double scale =
			    pow(10.0, 8.0 * uniform01(&f->r) - 4.0); /* 0.1 mm .. 10 km */
			double a[3], dir[3], perp[3];
			for (int k = 0; k < 3; ++k) {
				a[k] = scale * gauss(&f->r);
				dir[k] = gauss(&f->r);
				perp[k] = gauss(&f->r);
			}
			int kind = (int)(uniform01(&f->r) * 6.0);
			/* Kinds 2..5 damage an otherwise solvable sample (the layout at a random
			 * pose up to 10 km out), so the fault itself must be what stops the fit. */
			struct rs_pose T;
			random_pose(&f->r, scale, &T);
			if (kind >= 2)
				make_sample(&f->L, &T, 0.0, &f->r, t, &smp);
			for (int j = 0; j < 3 && kind < 2; ++j) {
				struct rs_marker *m = &smp.markers[j];
				m->id = (uint32_t)(uniform01(&f->r) * 5.0);
				m->flags = RS_MARKER_VALID;
				double s = 0.2 * gauss(&f->r);
				/* nearly collinear: off the line by at most 0.9 of the gate */
				double off =
				    kind == 1 && j == 2 ? 0.9 * gate * uniform01(&f->r) : 0.0;
				double pn =
				    sqrt(perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]);
				for (int k = 0; k < 3; ++k)
					m->position[k] = a[k] + s * dir[k] + off * perp[k] / pn;
			}
			int victim = (int)(uniform01(&f->r) * 3.0);
			switch (kind) {
			case 0: /* exactly collinear (as exact as rounding allows) */
			case 1: /* nearly collinear; height < 0.9 gate + rounding */
				break;
			case 2: /* coincident pair or triple */
				memcpy(smp.markers[(victim + 1) % 3].position,
				       smp.markers[victim].position,
				       sizeof smp.markers[0].position);
				if (uniform01(&f->r) < 0.5)
					memcpy(smp.markers[(victim + 2) % 3].position,
					       smp.markers[victim].position,
					       sizeof smp.markers[0].position);
				break;
			case 3: {
				const double bad[] = {NAN, INFINITY, -INFINITY, 1e300, DBL_MAX};
				smp.markers[victim].position[i % 3] = bad[i % 5];
				break;
			}
			case 4:
				smp.marker_count = (uint32_t)(uniform01(&f->r) * 3.0);
				break;
			default:
				smp.markers[victim].flags =
				    uniform01(&f->r) < 0.5 ? 0u
				                           : RS_MARKER_VALID | RS_MARKER_OCCLUDED;
				break;
			}
			enum rs_pose_status expect = !have_pose ? RS_POSE_NONE
			                             : predict  ? RS_POSE_PREDICTED
			                                        : RS_POSE_HELD;
			assert_int_equal(run(f, &smp, &out), expect);
		}
		teardown(f);
	}
}

static void test_bad_arguments(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver *s = NULL;
	struct rs_error err;
	struct rs_pose_solver_desc neg = {.noise_sigma_m = -1.0};
	assert_int_equal(rs_pose_solver_create(&neg, &L, &s, &err), RS_ERR_INVALID);
	assert_null(s);
	L.markers[2][0] = 0.05;
	assert_int_equal(rs_pose_solver_create(NULL, &L, &s, &err), RS_ERR_DEGENERATE);
	rs_pose_layout_default(&L);
	assert_int_equal(rs_pose_solver_create(NULL, &L, &s, &err), RS_OK);
	struct rs_pose out;
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_solver_update(s, NULL, &out, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_solver_update(NULL, NULL, &out, NULL));
	assert_string_equal(rs_pose_status_name(RS_POSE_RELABELED), "RS_POSE_RELABELED");
	rs_pose_solver_destroy(&s);
	rs_pose_solver_destroy(&s); /* NULL is fine */
	rs_pose_solver_destroy(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_collinear_before_any_pose_is_none),
	    cmocka_unit_test(test_collinear_and_coincident_hold_last_pose),
	    cmocka_unit_test(test_height_gate_threshold),
	    cmocka_unit_test(test_missing_invalid_occluded_marker_holds),
	    cmocka_unit_test(test_swapped_ids_relabeled),
	    cmocka_unit_test(test_duplicate_or_unknown_ids_relabeled),
	    cmocka_unit_test(test_far_from_origin),
	    cmocka_unit_test(test_nan_inf_huge_markers_hold),
	    cmocka_unit_test(test_nan_timestamp_holds_at_last_time),
	    cmocka_unit_test(test_hold_timeout_gives_none),
	    cmocka_unit_test(test_predict_when_lost_is_capped),
	    cmocka_unit_test(test_tiny_dt_velocity_stays_finite),
	    cmocka_unit_test(test_prediction_cap_above_30ms_refused),
	    cmocka_unit_test(test_output_hemisphere_canonical),
	    cmocka_unit_test(test_random_degenerate_configurations),
	    cmocka_unit_test(test_bad_arguments),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
