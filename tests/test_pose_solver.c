/* rs_pose fit and solver against synthetic ground truth: exact recovery, the calibration
 * offset, layout loading, and Monte Carlo pose error versus marker noise (bounds derived in
 * docs/pose.md, "Expected error"). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "raystream/rs_pose.h"
#include "test_pose_fixture.h"

#define DEG (180.0 / RS_PI)

/* ---- rs_pose_fit ---- */

static void test_fit_exact_recovers_pose(void **state)
{
	(void)state;
	struct rng r = {1};
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	for (int trial = 0; trial < 1000; ++trial) {
		struct rs_pose T, fit;
		random_pose(&r, 3.0, &T);
		double meas[3][3], rms = -1.0;
		for (int i = 0; i < 3; ++i)
			rs_pose_transform_point(&T, L.markers[i], meas[i]);
		assert_int_equal(rs_pose_fit((const double(*)[3])L.markers,
		                             (const double(*)[3])meas, 3, &fit, &rms, NULL),
		                 RS_OK);
		/* sigma = 0: only rounding (~1e-15 of metre-sized numbers) remains; 1e-9 is the
		 * issue's "recovers to ~1e-9" with six orders of margin to spare. */
		assert_true(rs_pose_angle_between(&fit, &T) < 1e-9);
		assert_true(pos_error(&fit, &T) < 1e-9);
		assert_true(rms < 1e-9);
		assert_true(fit.orientation[3] >= 0.0);
	}
}

static void test_fit_many_points_exact(void **state)
{
	(void)state;
	struct rng r = {2};
	double model[10][3], meas[10][3];
	for (int trial = 0; trial < 200; ++trial) {
		struct rs_pose T, fit;
		random_pose(&r, 1.0, &T);
		for (int i = 0; i < 10; ++i) {
			for (int k = 0; k < 3; ++k)
				model[i][k] = 0.2 * gauss(&r);
			rs_pose_transform_point(&T, model[i], meas[i]);
		}
		size_t n = 3 + (size_t)(trial % 8);
		assert_int_equal(rs_pose_fit((const double(*)[3])model, (const double(*)[3])meas, n,
		                             &fit, NULL, NULL),
		                 RS_OK);
		assert_true(rs_pose_angle_between(&fit, &T) < 1e-9);
		assert_true(pos_error(&fit, &T) < 1e-9);
	}
}

/* A planar triangle and its mirror image are related by a proper rotation (turn it over):
 * the fit must find that rotation exactly. This is the case an SVD fit with the
 * "flip if det(H) < 0" rule gets wrong, since det(H) of rank-2 H is only rounding noise. */
static void test_fit_mirrored_triangle_is_rotation(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	double mirrored[3][3];
	for (int i = 0; i < 3; ++i) {
		mirrored[i][0] = -L.markers[i][0];
		mirrored[i][1] = L.markers[i][1];
		mirrored[i][2] = L.markers[i][2];
	}
	struct rs_pose fit;
	double rms = 1.0;
	assert_int_equal(rs_pose_fit((const double(*)[3])L.markers, (const double(*)[3])mirrored, 3,
	                             &fit, &rms, NULL),
	                 RS_OK);
	assert_true(rms < 1e-12);
	double n = 0.0;
	for (int k = 0; k < 4; ++k)
		n += fit.orientation[k] * fit.orientation[k];
	assert_true(fabs(n - 1.0) < 1e-12);
}

static void test_fit_rejects_bad_input(void **state)
{
	(void)state;
	double model[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
	double line[3][3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
	double same[3][3] = {{5, 5, 5}, {5, 5, 5}, {5, 5, 5}};
	double bad[3][3] = {{0, 0, 0}, {1, NAN, 0}, {0, 1, 0}};
	struct rs_pose fit;
	struct rs_error err;
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])model, 2, &fit, NULL, &err),
	    RS_ERR_INVALID);
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])line, 3, &fit, NULL, &err),
	    RS_ERR_DEGENERATE);
	assert_true(fit.orientation[3] == 1.0 && fit.position[0] == 0.0);
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])same, 3, &fit, NULL, &err),
	    RS_ERR_DEGENERATE);
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])bad, 3, &fit, NULL, &err),
	    RS_ERR_BAD_DATA);
	assert_true(strlen(err.message) > 0);
}

/* ---- layout ---- */

static void test_layout_default_is_valid(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	assert_int_equal(rs_pose_layout_check(&L, NULL), RS_OK);
	assert_true(L.markers[1][0] == 0.10 && L.markers[2][1] == 0.08);
}

/* A zero-initialised calibration (all-zero quaternion) is the identity, like every zero
 * default: the solver then returns T_tracker_markers itself. */
static void test_layout_zero_calibration_is_identity(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	memset(&L.T_markers_display, 0, sizeof L.T_markers_display);
	assert_int_equal(rs_pose_layout_check(&L, NULL), RS_OK);
	struct rs_pose_solver *s = NULL;
	assert_int_equal(rs_pose_solver_create(NULL, &L, &s, NULL), RS_OK);
	struct rng r = {9};
	struct rs_pose T, out;
	struct rs_marker_sample smp;
	random_pose(&r, 1.0, &T);
	make_sample(&L, &T, 0.0, &r, 0.0, &smp);
	assert_int_equal(rs_pose_solver_update(s, &smp, &out, NULL), RS_OK);
	assert_true(rs_pose_angle_between(&out, &T) < 1e-9 && pos_error(&out, &T) < 1e-9);
	rs_pose_solver_destroy(&s);
}

static void test_layout_check_rejects_isosceles(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	L.markers[2][0] = 0.05; /* apex over the middle of the base: two equal sides */
	struct rs_error err;
	assert_int_equal(rs_pose_layout_check(&L, &err), RS_ERR_DEGENERATE);
	rs_pose_layout_default(&L);
	L.markers[2][1] = 0.001; /* flat triangle */
	assert_int_equal(rs_pose_layout_check(&L, &err), RS_ERR_DEGENERATE);
	rs_pose_layout_default(&L);
	L.T_markers_display.orientation[3] = 2.0;
	assert_int_equal(rs_pose_layout_check(&L, &err), RS_ERR_BAD_DATA);
	/* A finite but huge calibration offset would overflow the composed pose. */
	rs_pose_layout_default(&L);
	L.T_markers_display.position[1] = 1e307;
	assert_int_equal(rs_pose_layout_check(&L, &err), RS_ERR_BAD_DATA);
}

static const char *write_tmp(const char *name, const char *text)
{
	static char path[256];
	snprintf(path, sizeof path, "%s", name);
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	return path;
}

static void test_layout_load_json(void **state)
{
	(void)state;
	const char *p = write_tmp("test_pose_layout_ok.json",
	                          "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]],"
	                          " \"T_markers_display\": {\"position\": [0.01,0.02,0.03],"
	                          " \"orientation\": [0,0,-2,0]}}");
	struct rs_pose_layout L;
	assert_int_equal(rs_pose_layout_load(p, &L, NULL), RS_OK);
	assert_true(L.markers[2][0] == 0.02);
	assert_true(L.T_markers_display.position[2] == 0.03);
	/* [0,0,-2,0] normalised, then canonicalised (w == 0: first nonzero made positive). */
	assert_true(L.T_markers_display.orientation[2] == 1.0);
	remove(p);
}

static void test_layout_load_errors(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	struct rs_error err;
	assert_int_equal(rs_pose_layout_load("no/such/file.json", &L, &err), RS_ERR_NOT_FOUND);
	const char *p = write_tmp("test_pose_layout_bad.json", "{\"markers\": [[0,0,0],[1,0");
	assert_int_equal(rs_pose_layout_load(p, &L, &err), RS_ERR_PARSE);
	p = write_tmp("test_pose_layout_bad.json", "{\"markers\": [[0,0,0],[0.1,0,0]]}");
	assert_int_equal(rs_pose_layout_load(p, &L, &err), RS_ERR_PARSE);
	p = write_tmp("test_pose_layout_bad.json",
	              "{\"markers\": [[0,0,0],[0.1,0,0],[0.05,0.08,0]]}");
	assert_int_equal(rs_pose_layout_load(p, &L, &err), RS_ERR_DEGENERATE);
	p = write_tmp("test_pose_layout_bad.json",
	              "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]], \"T_markers_display\":"
	              " {\"position\": [0,0,0], \"orientation\": [0,0,0,0]}}");
	assert_int_equal(rs_pose_layout_load(p, &L, &err), RS_ERR_BAD_DATA);
	remove(p);
}

/* ---- solver ---- */

static void test_solver_applies_calibration_offset(void **state)
{
	(void)state;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose T_md = {.position = {0.03, -0.05, 0.02},
	                       .orientation = {0.0, 0.6, 0.0, 0.8}};
	L.T_markers_display = T_md;
	struct rs_pose_solver *s = NULL;
	struct rs_pose_solver_desc d = {.independent_samples = 1}; /* unrelated poses */
	assert_int_equal(rs_pose_solver_create(&d, &L, &s, NULL), RS_OK);
	struct rng r = {3};
	for (int trial = 0; trial < 100; ++trial) {
		struct rs_pose T_tm, expect, out;
		struct rs_marker_sample smp;
		struct rs_pose_quality q;
		random_pose(&r, 2.0, &T_tm);
		make_sample(&L, &T_tm, 0.0, &r, 0.01 * trial, &smp);
		assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
		assert_int_equal(q.status, RS_POSE_OK);
		rs_pose_compose(&T_tm, &T_md, &expect);
		assert_true(rs_pose_angle_between(&out, &expect) < 1e-9);
		assert_true(pos_error(&out, &expect) < 1e-9);
		assert_true(out.time_s == smp.host_time_s);
		assert_true(q.residual_rms_m < 1e-9);
		assert_int_equal(q.markers_used, 3);
		/* Smallest height of the default triangle, 0.008 / |(0.02,0.08)-(0.1,0)|. */
		assert_true(fabs(q.min_height_m - 0.008 / sqrt(0.08 * 0.08 * 2)) < 1e-9);
	}
	rs_pose_solver_destroy(&s);
	assert_null(s);
}

/* sqrt(trace(J^-1)) for J = sum(|c|^2 I - c c^T) over the centred layout: the linearised
 * RMS rotation error per unit of per-axis noise (docs/pose.md). */
static double rotation_error_constant(const struct rs_pose_layout *L)
{
	double c[3] = {0}, J[3][3] = {{0}};
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			c[k] += L->markers[i][k] / 3.0;
	for (int i = 0; i < 3; ++i) {
		double p[3] = {L->markers[i][0] - c[0], L->markers[i][1] - c[1],
		               L->markers[i][2] - c[2]};
		double n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				J[a][b] += (a == b ? n2 : 0.0) - p[a] * p[b];
	}
	double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
	             J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
	             J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
	double tr_inv = (J[1][1] * J[2][2] - J[1][2] * J[2][1] + J[0][0] * J[2][2] -
	                 J[0][2] * J[2][0] + J[0][0] * J[1][1] - J[0][1] * J[1][0]) /
	                det;
	return sqrt(tr_inv);
}

/* The layout with its origin moved to the markers' centroid, so the solved position is the
 * centroid, whose error is sigma / sqrt(3) per axis independently of the rotation error. */
static void centred_layout(struct rs_pose_layout *L)
{
	rs_pose_layout_default(L);
	double c[3] = {0};
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			c[k] += L->markers[i][k] / 3.0;
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			L->markers[i][k] -= c[k];
}

#define MC_TRIALS 4000

/* MC_TRIALS solved samples of random poses. Samples whose ids the side lengths cannot
 * settle (RS_POSE_HELD / NONE: most at 2 mm on this layout, see docs/pose.md) are skipped:
 * to first order the side lengths see only the 3 shape components of the noise and the
 * pose error only the 6 rigid ones, which are independent, so skipping them does not bias
 * the pose error statistics. *out_solved: fraction of samples solved. */
static void monte_carlo_solved(double sigma, double *out_rot_rms, double *out_pos_rms_axis,
                               double *out_residual_rms, double *out_solved)
{
	struct rs_pose_layout L;
	centred_layout(&L);
	struct rs_pose_solver_desc d = {.noise_sigma_m = sigma > 0 ? sigma : 0.0005};
	struct rs_pose_solver *s = NULL;
	assert_int_equal(rs_pose_solver_create(&d, &L, &s, NULL), RS_OK);
	struct rng r = {1000 + (uint64_t)(sigma * 1e6)};
	double sum_rot = 0.0, sum_pos = 0.0, sum_res = 0.0;
	int solved = 0, tried = 0;
	while (solved < MC_TRIALS && tried < 20 * MC_TRIALS) {
		struct rs_pose T, out;
		struct rs_marker_sample smp;
		struct rs_pose_quality q;
		random_pose(&r, 2.0, &T);
		make_sample(&L, &T, sigma, &r, 0.001 * tried++, &smp);
		rs_pose_solver_reset(s);
		assert_int_equal(rs_pose_solver_update(s, &smp, &out, &q), RS_OK);
		if (q.status != RS_POSE_OK) {
			assert_int_equal(q.status, RS_POSE_NONE);
			continue;
		}
		double a = rs_pose_angle_between(&out, &T), e = pos_error(&out, &T);
		sum_rot += a * a;
		sum_pos += e * e;
		sum_res += q.residual_rms_m * q.residual_rms_m;
		++solved;
	}
	rs_pose_solver_destroy(&s);
	assert_int_equal(solved, MC_TRIALS);
	*out_rot_rms = sqrt(sum_rot / MC_TRIALS);
	*out_pos_rms_axis = sqrt(sum_pos / (3.0 * MC_TRIALS));
	*out_residual_rms = sqrt(sum_res / MC_TRIALS);
	*out_solved = (double)solved / tried;
}

static void monte_carlo(double sigma, double *out_rot_rms, double *out_pos_rms_axis,
                        double *out_residual_rms)
{
	double solved;
	monte_carlo_solved(sigma, out_rot_rms, out_pos_rms_axis, out_residual_rms, &solved);
}

static void test_monte_carlo_sigma_zero(void **state)
{
	(void)state;
	double rot, pos, res;
	monte_carlo(0.0, &rot, &pos, &res);
	assert_true(rot < 1e-9);
	assert_true(pos < 1e-9);
	assert_true(res < 1e-9);
}

/* Bounds: the linearised prediction sigma * sqrt(trace(J^-1)) (= 1.68 sigma / h_min for
 * this triangle: 0.136 deg at 0.1 mm, 1.36 deg at 1 mm) and sigma / sqrt(3) per axis must
 * hold within +-10 %. With 4000 trials the sampling error of an RMS is ~0.7 % (rotation,
 * three unequal chi-square terms) and ~0.6 % (position, 12000 terms), and the second-order
 * (nonlinear) terms are < (sigma / h)^2 ~ 0.1 % at 2 mm, so 10 % is > 10 standard errors
 * wide yet would catch a wrong constant (e.g. missing centring or a sqrt(2)). */
static void check_sigma(double sigma)
{
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	double k = rotation_error_constant(&L);
	double rot, pos, res, solved;
	monte_carlo_solved(sigma, &rot, &pos, &res, &solved);
	double expect_rot = k * sigma, expect_pos = sigma / sqrt(3.0);
	double h_min = 0.008 / sqrt(0.08 * 0.08 * 2);
	/* The sigma / h law with its constant: k * h_min = 1.68 for this layout. */
	assert_true(fabs(k * h_min - 1.68) < 0.01);
	printf("# sigma %.4f mm: rot rms %.4f deg (expect %.4f), pos rms/axis %.4f mm "
	       "(expect %.4f)\n",
	       sigma * 1e3, rot * DEG, expect_rot * DEG, pos * 1e3, expect_pos * 1e3);
	assert_true(rot > 0.9 * expect_rot && rot < 1.1 * expect_rot);
	assert_true(pos > 0.9 * expect_pos && pos < 1.1 * expect_pos);
	/* The quality figure: 9 measured coordinates minus 6 pose parameters leave 3 degrees
	 * of freedom, so E[sum |r_i|^2] = 3 sigma^2 and the per-marker residual RMS is sigma
	 * (chi-square with 3 x 4000 dof: ~0.6 % sampling error; +-10 % as above). The
	 * residual is the shape part of the noise, so it is only unbiased where (nearly) every
	 * sample is solved: skipping ambiguous labellings keeps the small-residual ones. */
	if (solved > 0.99)
		assert_true(res > 0.9 * sigma && res < 1.1 * sigma);
}

static void test_monte_carlo_sigma_0_1mm(void **state)
{
	(void)state;
	check_sigma(0.0001);
	/* The figure: about 0.13 deg at 0.1 mm. */
	double rot, pos, res;
	monte_carlo(0.0001, &rot, &pos, &res);
	assert_true(rot * DEG > 0.12 && rot * DEG < 0.15);
}

static void test_monte_carlo_sigma_0_5mm(void **state)
{
	(void)state;
	check_sigma(0.0005);
}

static void test_monte_carlo_sigma_1mm(void **state)
{
	(void)state;
	check_sigma(0.001);
	double rot, pos, res;
	monte_carlo(0.001, &rot, &pos, &res);
	assert_true(rot * DEG > 1.2 && rot * DEG < 1.5); /* the "1.3 deg at 1 mm" */
}

static void test_monte_carlo_sigma_2mm(void **state)
{
	(void)state;
	check_sigma(0.002);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_fit_exact_recovers_pose),
	    cmocka_unit_test(test_fit_many_points_exact),
	    cmocka_unit_test(test_fit_mirrored_triangle_is_rotation),
	    cmocka_unit_test(test_fit_rejects_bad_input),
	    cmocka_unit_test(test_layout_default_is_valid),
	    cmocka_unit_test(test_layout_zero_calibration_is_identity),
	    cmocka_unit_test(test_layout_check_rejects_isosceles),
	    cmocka_unit_test(test_layout_load_json),
	    cmocka_unit_test(test_layout_load_errors),
	    cmocka_unit_test(test_solver_applies_calibration_offset),
	    cmocka_unit_test(test_monte_carlo_sigma_zero),
	    cmocka_unit_test(test_monte_carlo_sigma_0_1mm),
	    cmocka_unit_test(test_monte_carlo_sigma_0_5mm),
	    cmocka_unit_test(test_monte_carlo_sigma_1mm),
	    cmocka_unit_test(test_monte_carlo_sigma_2mm),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
