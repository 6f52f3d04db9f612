/* Ray generation kernel of the reference renderer: pinhole primary rays from a camera
 * basis built once per frame (rs_trace_view), which the GLES backend hands to its kernels
 * as well. */
#include "trace_internal.h"

void rs_trace_view_init(const struct rs_camera *camera, const double origin[3], uint32_t width,
                        uint32_t height, struct rs_trace_view *out)
{
	RS_ASSERT(camera && out);
	struct rs_camera c;
	rs_camera_resolve(camera, &c);
	if (width == 0 || height == 0) {
		width = c.width;
		height = c.height;
	}
	double fwd[3] = {c.target[0] - c.eye[0], c.target[1] - c.eye[1], c.target[2] - c.eye[2]};
	double right[3], up[3];
	if (rs_v3_normalize(fwd) == 0.0) {
		/* rs_scene_set_camera() refuses this; answer something defined anyway */
		fwd[0] = 0.0, fwd[1] = 0.0, fwd[2] = -1.0;
	}
	rs_v3_cross(fwd, c.up, right);
	if (rs_v3_normalize(right) == 0.0) {
		double alt[3] = {fabs(fwd[1]) < 0.9 ? 0.0 : 1.0, fabs(fwd[1]) < 0.9 ? 1.0 : 0.0,
		                 0.0};
		rs_v3_cross(fwd, alt, right);
		rs_v3_normalize(right);
	}
	rs_v3_cross(right, fwd, up);
	for (int a = 0; a < 3; ++a) {
		out->eye[a] = origin ? c.eye[a] - origin[a] : c.eye[a]; /* R1 */
		out->fwd[a] = fwd[a];
		out->right[a] = right[a];
		out->up[a] = up[a];
	}
	/* The paper's projection angle 2*atan(b/a): b = half the image plane's height at
	 * distance a = 1, so b = tan(fov/2); pixels are square. */
	out->tan_half_fov = tan(c.fov_y_deg * (RS_PI / 360.0));
	out->shift[0] = c.shift[0];
	out->shift[1] = c.shift[1];
	rs_trace_sample_offset(c.sample, out->pixel_offset);
	out->width = width;
	out->height = height;
}

void rs_trace_sample_offset(uint32_t sample, double out[2])
{
	RS_ASSERT(out);
	/* R2: x_n = frac(0.5 + n / g), y_n = frac(0.5 + n / g^2), g the plastic number
	 * (x^3 = x + 1); minus 0.5 so sample 0 is the pixel centre. n is exact in double. */
	static const double a1 = 0.75487766624669276005, a2 = 0.56984029099805326591;
	double n = (double)sample;
	double x = 0.5 + n * a1, y = 0.5 + n * a2;
	out[0] = x - floor(x) - 0.5;
	out[1] = y - floor(y) - 0.5;
}

void rs_trace_view_ray(const struct rs_trace_view *view, double px, double py,
                       struct rs_ray *out_ray)
{
	/* The lens shift moves the window off the axis (it adds exactly 0 when unset, so
	 * centred rays are unchanged). */
	double b = view->tan_half_fov, w = (double)view->width, h = (double)view->height;
	px += view->pixel_offset[0]; /* 0 for sample 0: centred rays stay bit for bit */
	py += view->pixel_offset[1];
	double sx = ((2.0 * px / w - 1.0) * (w / h) + view->shift[0]) * b;
	double sy = ((1.0 - 2.0 * py / h) + view->shift[1]) * b;
	double dir[3];
	for (int a = 0; a < 3; ++a) {
		dir[a] = view->fwd[a] + sx * view->right[a] + sy * view->up[a];
		out_ray->origin[a] = view->eye[a];
	}
	rs_v3_normalize(dir);
	for (int a = 0; a < 3; ++a)
		out_ray->dir[a] = dir[a];
	out_ray->tmin = 0.0;
	out_ray->tmax = INFINITY;
	out_ray->skip_slot = RS_NO_SLOT;
}

void rs_trace_camera_ray(const struct rs_camera *camera, uint32_t width, uint32_t height, double px,
                         double py, struct rs_ray *out_ray)
{
	struct rs_trace_view view;
	rs_trace_view_init(camera, NULL, width, height, &view);
	rs_trace_view_ray(&view, px, py, out_ray);
}
