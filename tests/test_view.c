/* rs_view: display pose -> camera. Known poses give the expected eye, view direction and
 * off-axis frustum (checked by tracing the image corners through the real ray generator
 * onto the screen rectangle); the hard cases (edge-on, eye behind, lost and regained
 * poses) give statuses, never a wrong camera. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "raystream/rs_trace.h"
#include "raystream/rs_view.h"
#include "contract.h"

static struct rs_pose pose_axis_angle(double ax, double ay, double az, double deg, double px,
                                      double py, double pz)
{
	double n = sqrt(ax * ax + ay * ay + az * az), h = deg * RS_PI / 360.0;
	struct rs_pose p = {.position = {px, py, pz}};
	p.orientation[0] = ax / n * sin(h);
	p.orientation[1] = ay / n * sin(h);
	p.orientation[2] = az / n * sin(h);
	p.orientation[3] = cos(h);
	return p;
}

static void assert_v3(const double a[3], double x, double y, double z, double tol)
{
	if (!(fabs(a[0] - x) <= tol && fabs(a[1] - y) <= tol && fabs(a[2] - z) <= tol))
		print_error("got (%.17g, %.17g, %.17g) want (%g, %g, %g)\n", a[0], a[1], a[2], x, y,
		            z);
	assert_true(fabs(a[0] - x) <= tol);
	assert_true(fabs(a[1] - y) <= tol);
	assert_true(fabs(a[2] - z) <= tol);
}

static struct rs_view_calibration resolved(const struct rs_view_calibration *in)
{
	struct rs_view_calibration c;
	assert_int_equal(rs_view_calibration_resolve(in, &c, NULL), RS_OK);
	return c;
}

static void test_defaults_identity_pose(void **state)
{
	(void)state;
	struct rs_view_calibration c = resolved(NULL);
	assert_true(c.screen_width_m == RS_VIEW_DEFAULT_SCREEN_M);
	struct rs_pose id = pose_axis_angle(0, 0, 1, 0, 0, 0, 0);
	struct rs_camera cam;
	struct rs_view_geometry g;
	assert_int_equal(rs_view_camera_from_pose(&c, &id, 64, 64, &cam, &g, NULL), RS_OK);
	assert_v3(cam.eye, 0, 0, RS_VIEW_DEFAULT_EYE_M, 1e-12);
	assert_v3(cam.target, 0, 0, RS_VIEW_DEFAULT_EYE_M - 1.0, 1e-12);
	assert_v3(cam.up, 0, 1, 0, 1e-12);
	double want =
	    2.0 * atan(0.5 * RS_VIEW_DEFAULT_SCREEN_M / RS_VIEW_DEFAULT_EYE_M) * 180 / RS_PI;
	assert_true(fabs(cam.fov_y_deg - want) < 1e-9);
	assert_true(fabs(cam.shift[0]) < 1e-12 && fabs(cam.shift[1]) < 1e-12);
	assert_true(fabs(g.eye_distance_m - RS_VIEW_DEFAULT_EYE_M) < 1e-12);
}

/* Trace the four image corners with the renderer's own ray generator; each must pass
 * through the matching screen corner (the frustum is the window). */
static void check_corners(const struct rs_view_calibration *c, const struct rs_pose *pose,
                          uint32_t w, uint32_t h)
{
	struct rs_camera cam;
	struct rs_view_geometry g;
	assert_int_equal(rs_view_camera_from_pose(c, pose, w, h, &cam, &g, NULL), RS_OK);
	/* the view direction is the screen's inward normal */
	double f[3] = {cam.target[0] - cam.eye[0], cam.target[1] - cam.eye[1],
	               cam.target[2] - cam.eye[2]};
	assert_v3(f, -g.normal[0], -g.normal[1], -g.normal[2], 1e-12);
	double s = c->scene_units_per_m;
	const double px[4] = {0, w, 0, w}, py[4] = {0, 0, h, h};
	const double sx[4] = {-0.5, 0.5, -0.5, 0.5}, sy[4] = {0.5, 0.5, -0.5, -0.5};
	for (int k = 0; k < 4; ++k) {
		struct rs_ray ray;
		rs_trace_camera_ray(&cam, w, h, px[k], py[k], &ray);
		double corner[3], oc[3];
		for (int i = 0; i < 3; ++i)
			corner[i] =
			    g.screen_center[i] + s * (sx[k] * c->screen_width_m * g.right[i] +
			                              sy[k] * c->screen_height_m * g.up[i]);
		for (int i = 0; i < 3; ++i)
			oc[i] = corner[i] - ray.origin[i];
		double t = oc[0] * ray.dir[0] + oc[1] * ray.dir[1] + oc[2] * ray.dir[2];
		assert_true(t > 0.0);
		for (int i = 0; i < 3; ++i) /* distance from the corner to the ray */
			assert_true(fabs(oc[i] - t * ray.dir[i]) < 1e-9 * s);
	}
}

static void test_off_axis_frustum_hits_screen_corners(void **state)
{
	(void)state;
	struct rs_view_calibration in = {.eye = {0.012, -0.021, 0.3}};
	struct rs_view_calibration c = resolved(&in);
	struct rs_pose id = pose_axis_angle(0, 0, 1, 0, 0, 0, 0);
	struct rs_camera cam;
	assert_int_equal(rs_view_camera_from_pose(&c, &id, 64, 64, &cam, NULL, NULL), RS_OK);
	/* the window centre is left of and above the eye: shift in half heights */
	assert_true(fabs(cam.shift[0] - (-0.012 / 0.029)) < 1e-12);
	assert_true(fabs(cam.shift[1] - (0.021 / 0.029)) < 1e-12);
	check_corners(&c, &id, 64, 64);
	/* a turned and moved display, a screen offset from the markers, a wide screen, a
	 * scaled and rotated room */
	struct rs_view_calibration in2 = {
	    .eye = {-0.03, 0.01, 0.25},
	    .screen_width_m = 0.1,
	    .screen_height_m = 0.05,
	    .T_display_screen = pose_axis_angle(1, 0, 0, 10, 0.02, 0.03, 0.005),
	    .T_scene_tracker = pose_axis_angle(0, 1, 0, 30, 5, -2, 1),
	    .scene_units_per_m = 10.0,
	};
	struct rs_view_calibration c2 = resolved(&in2);
	struct rs_pose p = pose_axis_angle(1, 2, -0.5, 70, 0.4, 1.2, -0.3);
	check_corners(&c2, &p, 128, 64);
	/* the eye fixed in the room: tilting the display changes the frustum */
	struct rs_view_calibration in3 = {.eye_frame = RS_VIEW_EYE_IN_TRACKER,
	                                  .eye = {0.1, 0.2, 0.5}};
	struct rs_view_calibration c3 = resolved(&in3);
	check_corners(&c3, &p, 64, 64);
}

static void test_known_rotation_gives_eye_and_direction(void **state)
{
	(void)state;
	struct rs_view_calibration c = resolved(NULL);
	/* display turned 90 deg about y and moved: its normal (+z) becomes +x */
	struct rs_pose p = pose_axis_angle(0, 1, 0, 90, 1, 2, 3);
	struct rs_camera cam;
	assert_int_equal(rs_view_camera_from_pose(&c, &p, 32, 32, &cam, NULL, NULL), RS_OK);
	assert_v3(cam.eye, 1 + RS_VIEW_DEFAULT_EYE_M, 2, 3, 1e-12);
	assert_v3(cam.target, RS_VIEW_DEFAULT_EYE_M, 2, 3, 1e-12);
	assert_v3(cam.up, 0, 1, 0, 1e-12);
	/* camera on the handheld: at the screen centre, centred frustum, the set fov */
	struct rs_view_calibration in = {.mode = RS_VIEW_CAMERA, .fov_y_deg = 60};
	struct rs_view_calibration cc = resolved(&in);
	assert_int_equal(rs_view_camera_from_pose(&cc, &p, 32, 16, &cam, NULL, NULL), RS_OK);
	assert_v3(cam.eye, 1, 2, 3, 1e-12);
	assert_v3(cam.target, 0, 2, 3, 1e-12);
	assert_true(cam.fov_y_deg == 60.0 && cam.shift[0] == 0.0 && cam.shift[1] == 0.0);
}

static void test_edge_on_and_eye_behind_refused(void **state)
{
	(void)state;
	struct rs_view_calibration in = {.eye_frame = RS_VIEW_EYE_IN_TRACKER, .eye = {0, 0, 1}};
	struct rs_view_calibration c = resolved(&in);
	struct rs_camera cam = {.fov_y_deg = 12.5};
	struct rs_error err = {0};
	/* turned 90 deg: the eye lies in the screen's plane */
	struct rs_pose edge = pose_axis_angle(0, 1, 0, 90, 0, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c, &edge, 64, 64, &cam, NULL, &err),
	                 RS_ERR_DEGENERATE);
	assert_non_null(strstr(err.message, "edge-on"));
	assert_true(cam.fov_y_deg == 12.5); /* untouched */
	/* 89.9 deg: 1.7 mm in front, nearer than the 5 mm limit */
	struct rs_pose near_edge = pose_axis_angle(0, 1, 0, 89.9, 0, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c, &near_edge, 64, 64, &cam, NULL, NULL),
	                 RS_ERR_DEGENERATE);
	/* 85 deg: 87 mm in front, allowed */
	struct rs_pose steep = pose_axis_angle(0, 1, 0, 85, 0, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c, &steep, 64, 64, &cam, NULL, NULL), RS_OK);
	/* turned away: the eye is behind the screen */
	struct rs_pose away = pose_axis_angle(0, 1, 0, 180, 0, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c, &away, 64, 64, &cam, NULL, &err),
	                 RS_ERR_DEGENERATE);
	assert_non_null(strstr(err.message, "behind"));
	/* close enough that the window needs more than 160 deg */
	struct rs_view_calibration in2 = {.eye = {0, 0, 0.0051}};
	struct rs_view_calibration c2 = resolved(&in2);
	struct rs_pose id = pose_axis_angle(0, 0, 1, 0, 0, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c2, &id, 64, 64, &cam, NULL, NULL),
	                 RS_ERR_DEGENERATE);
}

static void test_bad_inputs(void **state)
{
	(void)state;
	struct rs_view_calibration c = resolved(NULL), out;
	struct rs_camera cam;
	struct rs_pose nan_pose = pose_axis_angle(0, 0, 1, 0, NAN, 0, 0);
	assert_int_equal(rs_view_camera_from_pose(&c, &nan_pose, 64, 64, &cam, NULL, NULL),
	                 RS_ERR_BAD_DATA);
	struct rs_pose zero_q = {.position = {0, 0, 0}};
	assert_int_equal(rs_view_camera_from_pose(&c, &zero_q, 64, 64, &cam, NULL, NULL),
	                 RS_ERR_BAD_DATA);
	struct rs_pose id = pose_axis_angle(0, 0, 1, 0, 0, 0, 0);
	/* a 2:1 image on the square screen would stretch pixels */
	assert_int_equal(rs_view_camera_from_pose(&c, &id, 128, 64, &cam, NULL, NULL),
	                 RS_ERR_INVALID);
	assert_int_equal(rs_view_camera_from_pose(&c, &id, 0, 64, &cam, NULL, NULL),
	                 RS_ERR_INVALID);
	struct rs_view_calibration bad = {.screen_width_m = -1};
	assert_int_equal(rs_view_calibration_resolve(&bad, &out, NULL), RS_ERR_INVALID);
	bad = (struct rs_view_calibration){.fov_y_deg = 180};
	assert_int_equal(rs_view_calibration_resolve(&bad, &out, NULL), RS_ERR_INVALID);
	bad = (struct rs_view_calibration){.mode = (enum rs_view_mode)7};
	assert_int_equal(rs_view_calibration_resolve(&bad, &out, NULL), RS_ERR_INVALID);
	bad = (struct rs_view_calibration){.T_scene_tracker.orientation = {NAN, 0, 0, 1}};
	assert_int_equal(rs_view_calibration_resolve(&bad, &out, NULL), RS_ERR_INVALID);
}

static void test_lost_then_regained(void **state)
{
	(void)state;
	struct rs_camera home = {.eye = {0, 1, 5}, .target = {0, 1, 0}, .up = {0, 1, 0}};
	/* the eye stays in the room, so a display turned away leaves it behind the screen */
	struct rs_view_calibration in = {.eye_frame = RS_VIEW_EYE_IN_TRACKER, .eye = {0, 0, 1}};
	struct rs_view *v = NULL;
	assert_int_equal(rs_view_create(&in, &home, 64, 64, &v, NULL), RS_OK);
	struct rs_camera cam;
	enum rs_view_state st;
	struct rs_pose p1 = pose_axis_angle(0, 1, 0, 20, 0.1, 0, 0);
	/* nothing good yet: the home camera, flagged */
	rs_view_update(v, &p1, RS_POSE_NONE, &cam, &st);
	assert_int_equal(st, RS_VIEW_HOME);
	assert_memory_equal(cam.eye, home.eye, sizeof home.eye);
	rs_view_update(v, &p1, RS_POSE_OK, &cam, &st);
	assert_int_equal(st, RS_VIEW_FRESH);
	struct rs_camera good = cam;
	/* lost: the last good camera, flagged stale, with a reason */
	struct rs_pose p2 = pose_axis_angle(0, 1, 0, 40, 0.5, 0, 0);
	rs_view_update(v, &p2, RS_POSE_NONE, &cam, &st);
	assert_int_equal(st, RS_VIEW_STALE);
	assert_memory_equal(&cam, &good, sizeof cam);
	assert_true(strlen(rs_view_last_error(v)) > 0);
	/* a refused pose (turned away) is stale too */
	struct rs_pose away = pose_axis_angle(0, 1, 0, 180, 0, 0, 0);
	rs_view_update(v, &away, RS_POSE_OK, &cam, &st);
	assert_int_equal(st, RS_VIEW_STALE);
	assert_memory_equal(&cam, &good, sizeof cam);
	/* held by the solver: usable but flagged */
	rs_view_update(v, &p2, RS_POSE_HELD, &cam, &st);
	assert_int_equal(st, RS_VIEW_PREDICTED);
	/* regained: fresh, from the new pose */
	rs_view_update(v, &p2, RS_POSE_OK, &cam, &st);
	assert_int_equal(st, RS_VIEW_FRESH);
	assert_true(fabs(cam.target[0] - good.target[0]) > 0.1); /* turned 20 deg more */
	assert_string_equal(rs_view_last_error(v), "");
	rs_view_destroy(&v);
	assert_null(v);
	rs_view_destroy(NULL);
}

static void test_recentre_puts_camera_home(void **state)
{
	(void)state;
	struct rs_camera home = {.eye = {1, 2, 8}, .target = {0, 1, 0}, .up = {0, 1, 0}};
	struct rs_pose p = pose_axis_angle(0.3, 1, 0.2, 50, 0.2, 1.1, -0.4);
	for (int mode = 0; mode < 2; ++mode) {
		struct rs_view_calibration in = {.mode = (enum rs_view_mode)mode,
		                                 .scene_units_per_m = 3};
		struct rs_view_calibration c = resolved(&in);
		assert_int_equal(rs_view_recentre(&c, &p, &home, NULL), RS_OK);
		struct rs_camera cam;
		assert_int_equal(rs_view_camera_from_pose(&c, &p, 64, 64, &cam, NULL, NULL), RS_OK);
		assert_v3(cam.eye, 1, 2, 8, 1e-9);
		double f[3] = {cam.target[0] - cam.eye[0], cam.target[1] - cam.eye[1],
		               cam.target[2] - cam.eye[2]};
		double n = sqrt(1 + 1 + 64);
		assert_v3(f, -1 / n, -1 / n, -8 / n, 1e-9);
		/* up stays in the plane of the home up and the view direction */
		assert_true(cam.up[1] > 0.99 && fabs(cam.up[0] * 8 - cam.up[2] * 1) < 1e-9);
		/* moving the display 0.1 m along tracker x moves the camera 0.3 scene units */
		struct rs_pose q = p;
		q.position[0] += 0.1;
		struct rs_camera cam2;
		assert_int_equal(rs_view_camera_from_pose(&c, &q, 64, 64, &cam2, NULL, NULL),
		                 RS_OK);
		double dx = cam2.eye[0] - cam.eye[0], dy = cam2.eye[1] - cam.eye[1],
		       dz = cam2.eye[2] - cam.eye[2];
		assert_true(fabs(sqrt(dx * dx + dy * dy + dz * dz) - 0.3) < 1e-9);
	}
	struct rs_camera bad = {.eye = {0, 0, 0}, .target = {0, 1, 0}, .up = {0, 1, 0}};
	struct rs_view_calibration c = resolved(NULL);
	assert_int_equal(rs_view_recentre(&c, &p, &bad, NULL), RS_ERR_DEGENERATE);
	struct rs_view *v = NULL;
	assert_int_equal(rs_view_create(NULL, &home, 64, 64, &v, NULL), RS_OK);
	assert_int_equal(rs_view_recentre_last(v, NULL), RS_END);
	struct rs_camera cam;
	enum rs_view_state st;
	rs_view_update(v, &p, RS_POSE_OK, &cam, &st);
	assert_int_equal(rs_view_recentre_last(v, NULL), RS_OK);
	rs_view_update(v, &p, RS_POSE_OK, &cam, &st);
	assert_v3(cam.eye, 1, 2, 8, 1e-9);
	rs_view_destroy(&v);
}

/* NULL handles and out-pointers are contract violations, not statuses. */
static void test_contracts(void **state)
{
	(void)state;
	struct rs_view_calibration c = resolved(NULL);
	struct rs_pose id = pose_axis_angle(0, 0, 1, 0, 0, 0, 0);
	struct rs_camera cam, home = {.eye = {0, 0, 5}, .up = {0, 1, 0}};
	enum rs_view_state st;
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_camera_from_pose(NULL, &id, 8, 8, &cam, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_camera_from_pose(&c, &id, 8, 8, NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_calibration_resolve(NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_recentre(&c, NULL, &home, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_create(NULL, &home, 8, 8, NULL, NULL));
	struct rs_view *v = NULL;
	assert_int_equal(rs_view_create(NULL, &home, 8, 8, &v, NULL), RS_OK);
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_update(v, NULL, RS_POSE_OK, &cam, &st));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_update(NULL, &id, RS_POSE_OK, &cam, &st));
	RS_EXPECT_CONTRACT_VIOLATION(rs_view_recentre_last(NULL, NULL));
	rs_view_destroy(&v);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_defaults_identity_pose),
	    cmocka_unit_test(test_off_axis_frustum_hits_screen_corners),
	    cmocka_unit_test(test_known_rotation_gives_eye_and_direction),
	    cmocka_unit_test(test_edge_on_and_eye_behind_refused),
	    cmocka_unit_test(test_bad_inputs),
	    cmocka_unit_test(test_lost_then_regained),
	    cmocka_unit_test(test_recentre_puts_camera_home),
	    cmocka_unit_test(test_contracts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
