/* Display calibration and the stateless pose -> camera maths (docs/view.md). */
#include <math.h>
#include <string.h>

#include "private/rs_vec.h"
#include "raystream/rs_view.h"

static int quat_zero(const double q[4])
{
	return q[0] == 0.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0;
}

/* All-zero means identity; otherwise it must normalise. Returns 0 on a bad quaternion. */
static int resolve_quat(double q[4])
{
	if (quat_zero(q)) {
		q[3] = 1.0;
		return 1;
	}
	if (!isfinite(q[0]) || !isfinite(q[1]) || !isfinite(q[2]) || !isfinite(q[3]))
		return 0;
	if (!rs_q_normalize(q, q))
		return 0;
	rs_q_canonical(q);
	return 1;
}

static int nonneg_finite(double v)
{
	return isfinite(v) && v >= 0.0;
}

enum rs_status rs_view_calibration_resolve(const struct rs_view_calibration *cal,
                                           struct rs_view_calibration *out, struct rs_error *err)
{
	RS_ASSERT(out);
	struct rs_view_calibration c = {0};
	if (cal)
		c = *cal;
	if ((unsigned)c.mode > RS_VIEW_CAMERA || (unsigned)c.eye_frame > RS_VIEW_EYE_IN_TRACKER)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "view calibration: unknown mode or eye frame");
	if (!nonneg_finite(c.screen_width_m) || !nonneg_finite(c.screen_height_m) ||
	    !nonneg_finite(c.scene_units_per_m) || !nonneg_finite(c.min_eye_distance_m) ||
	    !nonneg_finite(c.fov_y_deg) || !nonneg_finite(c.max_fov_deg))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "view calibration: sizes, scale, distances and fovs must be "
		                    "finite and >= 0");
	if (!rs_v3_finite(c.eye) || !rs_v3_finite(c.T_display_screen.position) ||
	    !rs_v3_finite(c.T_scene_tracker.position))
		return rs_error_set(err, RS_ERR_INVALID, "view calibration: non-finite position");
	if (!resolve_quat(c.T_display_screen.orientation) ||
	    !resolve_quat(c.T_scene_tracker.orientation))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "view calibration: orientation is not a usable quaternion");
	if (c.screen_width_m == 0.0)
		c.screen_width_m = RS_VIEW_DEFAULT_SCREEN_M;
	if (c.screen_height_m == 0.0)
		c.screen_height_m = RS_VIEW_DEFAULT_SCREEN_M;
	if (c.eye_frame == RS_VIEW_EYE_IN_SCREEN && c.eye[0] == 0.0 && c.eye[1] == 0.0 &&
	    c.eye[2] == 0.0)
		c.eye[2] = RS_VIEW_DEFAULT_EYE_M;
	if (c.scene_units_per_m == 0.0)
		c.scene_units_per_m = 1.0;
	if (c.fov_y_deg == 0.0)
		c.fov_y_deg = 45.0;
	if (c.min_eye_distance_m == 0.0)
		c.min_eye_distance_m = RS_VIEW_DEFAULT_MIN_EYE_DISTANCE_M;
	if (c.max_fov_deg == 0.0)
		c.max_fov_deg = RS_VIEW_DEFAULT_MAX_FOV_DEG;
	if (c.fov_y_deg >= 180.0 || c.max_fov_deg >= 180.0)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "view calibration: fov must be below 180 deg");
	*out = c;
	return RS_OK;
}

/* The screen frame and the eye in the tracker frame. */
struct screen_in_tracker {
	struct rs_pose T_tracker_screen;
	double axes[3][3]; /* right, up, normal (out of the screen) */
	double eye[3];
};

static enum rs_status screen_from_pose(const struct rs_view_calibration *cal,
                                       const struct rs_pose *T_tracker_display,
                                       struct screen_in_tracker *out, struct rs_error *err)
{
	const double *q = T_tracker_display->orientation;
	if (!rs_v3_finite(T_tracker_display->position) || !isfinite(q[0]) || !isfinite(q[1]) ||
	    !isfinite(q[2]) || !isfinite(q[3]) || rs_q_dot(q, q) < 1e-12)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "display pose is not finite or not a rotation");
	rs_pose_compose(T_tracker_display, &cal->T_display_screen, &out->T_tracker_screen);
	static const double basis[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
	for (int i = 0; i < 3; ++i)
		rs_q_rotate(out->T_tracker_screen.orientation, basis[i], out->axes[i]);
	if (cal->eye_frame == RS_VIEW_EYE_IN_SCREEN)
		rs_pose_transform_point(&out->T_tracker_screen, cal->eye, out->eye);
	else
		memcpy(out->eye, cal->eye, sizeof out->eye);
	return RS_OK;
}

static void to_scene_point(const struct rs_view_calibration *cal, const double p[3], double out[3])
{
	double r[3];
	rs_q_rotate(cal->T_scene_tracker.orientation, p, r);
	for (int i = 0; i < 3; ++i)
		out[i] = cal->scene_units_per_m * r[i] + cal->T_scene_tracker.position[i];
}

enum rs_status rs_view_camera_from_pose(const struct rs_view_calibration *cal,
                                        const struct rs_pose *T_tracker_display, uint32_t width,
                                        uint32_t height, struct rs_camera *out_camera,
                                        struct rs_view_geometry *out_geometry, struct rs_error *err)
{
	RS_ASSERT(cal && T_tracker_display && out_camera);
	if (width == 0 || height == 0)
		return rs_error_set(err, RS_ERR_INVALID, "view: image size %ux%u", width, height);
	struct screen_in_tracker s;
	enum rs_status st = screen_from_pose(cal, T_tracker_display, &s, err);
	if (st != RS_OK)
		return st;
	struct rs_view_geometry g;
	double to_eye[3];
	rs_v3_sub(s.eye, s.T_tracker_screen.position, to_eye);
	g.eye_distance_m = rs_v3_dot(to_eye, s.axes[2]);
	for (int i = 0; i < 3; ++i)
		rs_q_rotate(cal->T_scene_tracker.orientation, s.axes[i],
		            i == 0   ? g.right
		            : i == 1 ? g.up
		                     : g.normal);
	to_scene_point(cal, s.eye, g.eye);
	to_scene_point(cal, s.T_tracker_screen.position, g.screen_center);

	struct rs_camera cam = {.width = width, .height = height};
	if (cal->mode == RS_VIEW_CAMERA) {
		memcpy(cam.eye, g.screen_center, sizeof cam.eye);
		cam.fov_y_deg = cal->fov_y_deg;
	} else {
		double d = g.eye_distance_m;
		if (!(d > 0.0))
			return rs_error_set(err, RS_ERR_DEGENERATE,
			                    "view: the eye is behind the screen (%.4g m)", d);
		if (d < cal->min_eye_distance_m)
			return rs_error_set(
			    err, RS_ERR_DEGENERATE,
			    "view: the screen is edge-on to the eye (%.4g m < %.4g m)", d,
			    cal->min_eye_distance_m);
		double aspect_img = (double)width / (double)height;
		double aspect_scr = cal->screen_width_m / cal->screen_height_m;
		if (fabs(aspect_img / aspect_scr - 1.0) > RS_VIEW_ASPECT_TOLERANCE)
			return rs_error_set(
			    err, RS_ERR_INVALID,
			    "view: image aspect %.4g differs from the screen's %.4g", aspect_img,
			    aspect_scr);
		double half_h = 0.5 * cal->screen_height_m;
		double fov = 2.0 * atan(half_h / d) * (180.0 / RS_PI);
		if (fov > cal->max_fov_deg)
			return rs_error_set(err, RS_ERR_DEGENERATE,
			                    "view: the frustum needs %.1f deg (> %.1f): screen too "
			                    "close to the eye",
			                    fov, cal->max_fov_deg);
		/* The window centre seen from the eye, in units of the half height: what
		 * rs_camera.shift means (camera_rays.c). */
		double c_from_eye[3];
		rs_v3_sub(s.T_tracker_screen.position, s.eye, c_from_eye);
		cam.shift[0] = rs_v3_dot(c_from_eye, s.axes[0]) / half_h;
		cam.shift[1] = rs_v3_dot(c_from_eye, s.axes[1]) / half_h;
		if (fabs(cam.shift[0]) > 1e6 || fabs(cam.shift[1]) > 1e6)
			return rs_error_set(err, RS_ERR_DEGENERATE,
			                    "view: the screen is too far off axis");
		memcpy(cam.eye, g.eye, sizeof cam.eye);
		cam.fov_y_deg = fov;
	}
	for (int i = 0; i < 3; ++i) {
		cam.target[i] = cam.eye[i] - g.normal[i];
		cam.up[i] = g.up[i];
	}
	*out_camera = cam;
	if (out_geometry)
		*out_geometry = g;
	return RS_OK;
}

/* Unit quaternion of the rotation whose columns are a, b, c (Shepperd's method). */
static void quat_from_columns(const double a[3], const double b[3], const double c[3], double q[4])
{
	double m00 = a[0], m11 = b[1], m22 = c[2], tr = m00 + m11 + m22;
	if (tr > 0.0) {
		double s = 2.0 * sqrt(1.0 + tr);
		q[3] = 0.25 * s;
		q[0] = (b[2] - c[1]) / s;
		q[1] = (c[0] - a[2]) / s;
		q[2] = (a[1] - b[0]) / s;
	} else if (m00 > m11 && m00 > m22) {
		double s = 2.0 * sqrt(1.0 + m00 - m11 - m22);
		q[3] = (b[2] - c[1]) / s;
		q[0] = 0.25 * s;
		q[1] = (b[0] + a[1]) / s;
		q[2] = (c[0] + a[2]) / s;
	} else if (m11 > m22) {
		double s = 2.0 * sqrt(1.0 + m11 - m00 - m22);
		q[3] = (c[0] - a[2]) / s;
		q[0] = (b[0] + a[1]) / s;
		q[1] = 0.25 * s;
		q[2] = (c[1] + b[2]) / s;
	} else {
		double s = 2.0 * sqrt(1.0 + m22 - m00 - m11);
		q[3] = (a[1] - b[0]) / s;
		q[0] = (c[0] + a[2]) / s;
		q[1] = (c[1] + b[2]) / s;
		q[2] = 0.25 * s;
	}
	rs_q_normalize(q, q);
	rs_q_canonical(q);
}

enum rs_status rs_view_recentre(struct rs_view_calibration *cal,
                                const struct rs_pose *T_tracker_display,
                                const struct rs_camera *home, struct rs_error *err)
{
	RS_ASSERT(cal && T_tracker_display && home);
	struct screen_in_tracker s;
	enum rs_status st = screen_from_pose(cal, T_tracker_display, &s, err);
	if (st != RS_OK)
		return st;
	double f[3], r[3], u[3], back[3];
	rs_v3_sub(home->target, home->eye, f);
	double fn = rs_v3_norm(f);
	rs_v3_cross(f, home->up, r);
	double rn = rs_v3_norm(r);
	if (!(fn > 0.0) || !(rn > 1e-12 * fn * rs_v3_norm(home->up)) || !isfinite(rn))
		return rs_error_set(err, RS_ERR_DEGENERATE,
		                    "view: home camera's direction and up are parallel or zero");
	for (int i = 0; i < 3; ++i) {
		r[i] /= rn;
		back[i] = -f[i] / fn;
	}
	rs_v3_cross(back, r, u);
	/* R_scene_tracker * R_tracker_screen = R_home, the home camera's (right, up, back). */
	double q_home[4], q_ts_inv[4], q_st[4];
	quat_from_columns(r, u, back, q_home);
	rs_q_conj(s.T_tracker_screen.orientation, q_ts_inv);
	rs_q_mul(q_home, q_ts_inv, q_st);
	rs_q_normalize(q_st, q_st);
	rs_q_canonical(q_st);
	/* The point that becomes the home eye: the eye (window) or the screen centre (camera). */
	const double *o = cal->mode == RS_VIEW_CAMERA ? s.T_tracker_screen.position : s.eye;
	double ro[3];
	rs_q_rotate(q_st, o, ro);
	for (int i = 0; i < 3; ++i)
		cal->T_scene_tracker.position[i] = home->eye[i] - cal->scene_units_per_m * ro[i];
	memcpy(cal->T_scene_tracker.orientation, q_st, sizeof q_st);
	return RS_OK;
}
