/* rs_optical calibration: synthetic checkerboard views of a known rig in, the rig out
 * (calibrateCamera + stereoCalibrate), within stated tolerances; too few views refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#ifdef RS_HAVE_OPTICAL
#include "test_optical_fixture.h"

#define W 640
#define H 480
#define VIEWS 16

static uint8_t g_img[VIEWS][2][W * H];

/* Board poses around 1 m in front of camera 0, turned up to ~25 degrees. */
static int render_views(const struct rs_optical_rig *rig, const struct rs_optical_board *b,
                        struct rs_optical_image v0[VIEWS], struct rs_optical_image v1[VIEWS])
{
	struct rng r = {.s = 8};
	int n = 0;
	for (int tries = 0; n < VIEWS && tries < 2000; ++tries) {
		double ax = 0.45 * (2 * uniform01(&r) - 1), ay = 0.45 * (2 * uniform01(&r) - 1);
		double q[4] = {sin(ax / 2) * cos(ay / 2), cos(ax / 2) * sin(ay / 2),
		               -sin(ax / 2) * sin(ay / 2), cos(ax / 2) * cos(ay / 2)};
		struct rs_pose T = {.orientation = {q[0], q[1], q[2], q[3]}};
		T.position[0] = -0.1 + 0.2 * (2 * uniform01(&r) - 1);
		T.position[1] = -0.06 + 0.14 * (2 * uniform01(&r) - 1);
		T.position[2] = 0.9 + 0.15 * uniform01(&r);
		if (rs_optical_synth_board(rig, b, &T, g_img[n][0], g_img[n][1], NULL) != RS_OK)
			continue;
		v0[n] = (struct rs_optical_image){g_img[n][0], W, H, W};
		v1[n] = (struct rs_optical_image){g_img[n][1], W, H, W};
		++n;
	}
	return n;
}

/* Tolerances: focal lengths 0.5 %, principal point 3 px, distortion < 0.5 px in the image,
 * rotation 0.3 degree, baseline length 1 %, its direction 0.5 degree, and an RMS
 * reprojection error below 0.3 px (the rendering is exact up to bilinear resampling). */
static void test_calibration_recovers_rig(void **state)
{
	(void)state;
	struct rs_optical_rig truth, got;
	make_rig(0.4, &truth);
	struct rs_optical_board b = {.cols = 9, .rows = 6, .square_m = 0.025};
	struct rs_optical_image v0[VIEWS], v1[VIEWS];
	int n = render_views(&truth, &b, v0, v1);
	assert_int_equal(n, VIEWS);
	size_t used = 0;
	struct rs_error err;
	enum rs_status st = rs_optical_calibrate(&b, v0, v1, (size_t)n, &got, &used, &err);
	if (st != RS_OK)
		printf("# %s\n", err.message);
	assert_int_equal(st, RS_OK);
	printf("# %zu views: f %.2f %.2f c %.2f %.2f | f %.2f %.2f c %.2f %.2f, rms %.3f px\n",
	       used, got.cam[0].K[0], got.cam[0].K[4], got.cam[0].K[2], got.cam[0].K[5],
	       got.cam[1].K[0], got.cam[1].K[4], got.cam[1].K[2], got.cam[1].K[5], got.rms_px);
	assert_true(used >= 10);
	for (int c = 0; c < 2; ++c) {
		assert_true(fabs(got.cam[c].K[0] / 800 - 1) < 0.005);
		assert_true(fabs(got.cam[c].K[4] / 800 - 1) < 0.005);
		assert_true(fabs(got.cam[c].K[2] - 319.5) < 3 && fabs(got.cam[c].K[5] - 239.5) < 3);
		/* The distortion terms trade off against each other where the board never went;
		 * what matters is the displacement they cause inside the image: < 0.5 px at the
		 * image corners (r = 0.5 in normalised coordinates). */
		const double *k = got.cam[c].dist;
		double x = 0.4, y = 0.3, r2 = x * x + y * y;
		double rad = k[0] * r2 + k[1] * r2 * r2 + k[4] * r2 * r2 * r2;
		double dx = x * rad + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
		double dy = y * rad + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
		printf("# camera %d distortion %.4f %.4f %.5f %.5f %.4f: %.3f px at the corner\n",
		       c, k[0], k[1], k[2], k[3], k[4], 800 * hypot(dx, dy));
		assert_true(800 * hypot(dx, dy) < 0.5);
	}
	/* angle of R_got R_truth^T */
	double tr = 0;
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			tr += got.R_cam1_cam0[3 * i + k] * truth.R_cam1_cam0[3 * i + k];
	double ang = acos(fmin(1.0, (tr - 1) / 2));
	double *a = got.t_cam1_cam0, *bt = truth.t_cam1_cam0;
	double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
	double nb = sqrt(bt[0] * bt[0] + bt[1] * bt[1] + bt[2] * bt[2]);
	double dir = acos(fmin(1.0, (a[0] * bt[0] + a[1] * bt[1] + a[2] * bt[2]) / (na * nb)));
	printf("# R off %.4f deg, |t| %.4f m (true %.4f), direction off %.4f deg\n",
	       ang * 180 / RS_PI, na, nb, dir * 180 / RS_PI);
	assert_true(ang * 180 / RS_PI < 0.3);
	assert_true(fabs(na / nb - 1) < 0.01);
	assert_true(dir * 180 / RS_PI < 0.5);
	assert_true(got.rms_px > 0 && got.rms_px < 0.3);
}

/* Fewer than 5 views with the board, and views of different sizes, are refused. */
static void test_calibration_needs_views(void **state)
{
	(void)state;
	struct rs_optical_rig truth, got;
	make_rig(0.4, &truth);
	struct rs_optical_board b = {.cols = 9, .rows = 6, .square_m = 0.025};
	struct rs_optical_image v0[VIEWS], v1[VIEWS];
	assert_int_equal(render_views(&truth, &b, v0, v1), VIEWS);
	struct rs_error err;
	size_t used = 99;
	assert_int_equal(rs_optical_calibrate(&b, v0, v1, 4, &got, &used, &err), RS_ERR_DEGENERATE);
	assert_int_equal(used, 4);
	v1[1].width = W / 2;
	assert_int_equal(rs_optical_calibrate(&b, v0, v1, 3, &got, NULL, &err), RS_ERR_BAD_DATA);
	struct rs_optical_board bad = {.cols = 2};
	assert_int_equal(rs_optical_calibrate(&bad, v0, v1, 3, &got, NULL, &err), RS_ERR_INVALID);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_calibration_recovers_rig),
	    cmocka_unit_test(test_calibration_needs_views),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* opencv backend not built: nothing to test */
}
#endif
