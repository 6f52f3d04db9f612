/*
 * Simulator motion: the script grammar and the velocity profile of each segment kind.
 * Every profile is shaped by sin^2 over its segment, so velocities start and end at zero
 * and the motion stays continuous across segment boundaries and script loops.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

#define PI 3.14159265358979323846

static const struct {
	const char *name;
	enum sim_segment_kind kind;
	double default_s;
} kinds[] = {
    {"still", SIM_STILL, 1.0},
    {"walk", SIM_WALK, 2.0},
    {"turn", SIM_TURN, 2.0},
    {"shake", SIM_SHAKE, 1.0},
};

enum rs_status sim_parse_script(const char *script, struct sim_segment *out, size_t *out_n,
                                struct rs_error *err)
{
	size_t n = 0;
	const char *p = script;
	for (;;) {
		size_t len = strcspn(p, ",");
		size_t name_len = strcspn(p, ":,");
		if (n == RS_SIM_MAX_SEGMENTS)
			return rs_error_set(err, RS_ERR_INVALID,
			                    "sim: script longer than %d segments",
			                    RS_SIM_MAX_SEGMENTS);
		size_t k = 0;
		while (k < sizeof kinds / sizeof kinds[0] &&
		       !(strlen(kinds[k].name) == name_len && !strncmp(kinds[k].name, p, name_len)))
			k++;
		if (k == sizeof kinds / sizeof kinds[0])
			return rs_error_set(
			    err, RS_ERR_INVALID,
			    "sim: unknown script segment '%.*s' (still, walk, turn, shake)",
			    (int)(name_len > 32 ? 32 : name_len), p);
		out[n].kind = kinds[k].kind;
		out[n].duration_s = kinds[k].default_s;
		if (name_len < len) {
			char num[32];
			size_t nl = len - name_len - 1;
			char *end = NULL;
			if (nl == 0 || nl >= sizeof num)
				return rs_error_set(err, RS_ERR_INVALID,
				                    "sim: bad segment duration");
			memcpy(num, p + name_len + 1, nl);
			num[nl] = '\0';
			double d = strtod(num, &end);
			if (*end != '\0' || !(d > 0.0 && d < 1e6))
				return rs_error_set(err, RS_ERR_INVALID,
				                    "sim: segment duration '%s' not in (0, 1e6) s",
				                    num);
			out[n].duration_s = d;
		}
		n++;
		if (p[len] == '\0')
			break;
		p += len + 1;
	}
	*out_n = n;
	return RS_OK;
}

void sim_quat_rotate(const double q[4], const double v[3], double out[3])
{
	/* v' = v + 2w (u x v) + 2 u x (u x v), u = q.xyz */
	double u[3] = {q[0], q[1], q[2]}, w = q[3];
	double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
	               u[0] * v[1] - u[1] * v[0]};
	double cc[3] = {u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2],
	                u[0] * c[1] - u[1] * c[0]};
	for (int i = 0; i < 3; i++)
		out[i] = v[i] + 2.0 * w * c[i] + 2.0 * cc[i];
}

static void quat_mul(const double a[4], const double b[4], double out[4])
{
	double r[4] = {
	    a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
	    a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
	    a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
	    a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
	};
	memcpy(out, r, sizeof r);
}

static void quat_exp(const double w[3], double h, double out[4])
{
	double a = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * h;
	double s = a > 1e-12 ? sin(a / 2) / (a / h) : h / 2;
	out[0] = w[0] * s;
	out[1] = w[1] * s;
	out[2] = w[2] * s;
	out[3] = cos(a / 2);
}

void sim_quat_integrate(double q[4], const double w_world[3], const double w_body[3], double h)
{
	double e[4];
	quat_exp(w_world, h, e);
	quat_mul(e, q, q);
	quat_exp(w_body, h, e);
	quat_mul(q, e, q);
	double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
	for (int i = 0; i < 4; i++)
		q[i] /= n;
}

void sim_segment_motion(const struct sim_segment *seg, double t, const double q[4],
                        struct sim_motion *out)
{
	memset(out, 0, sizeof *out);
	double D = seg->duration_s;
	double s = sin(PI * t / D);
	double env = s * s; /* integrates to D/2 over the segment */
	switch (seg->kind) {
	case SIM_STILL:
		break;
	case SIM_WALK: {
		/* Forward along the body's heading at up to 0.6 m/s, with a 1.8 Hz, 3 cm bob. */
		static const double x_axis[3] = {1, 0, 0};
		double f[3];
		sim_quat_rotate(q, x_axis, f);
		double n = sqrt(f[0] * f[0] + f[1] * f[1]);
		if (n < 1e-6) {
			f[0] = 1;
			f[1] = 0;
			n = 1;
		}
		out->v_world[0] = 0.6 * env * f[0] / n;
		out->v_world[1] = 0.6 * env * f[1] / n;
		out->v_world[2] = 0.03 * 2 * PI * 1.8 * cos(2 * PI * 1.8 * t) * env;
		break;
	}
	case SIM_TURN:
		/* A quarter turn about the vertical, plus a gentle 10 degree tilt and back. */
		out->w_world[2] = (PI / 2) * env * 2.0 / D;
		out->w_body[0] = (10.0 * PI / 180.0) * 2 * PI / D * cos(2 * PI * t / D) * 0.5;
		break;
	case SIM_SHAKE:
		/* Hand shake: 4-5 Hz rotation about two body axes, 1 cm lateral wobble. */
		out->w_body[0] = 1.5 * sin(2 * PI * 4.0 * t) * env;
		out->w_body[1] = 1.0 * sin(2 * PI * 5.0 * t + 1.0) * env;
		out->v_world[1] = 0.01 * 2 * PI * 3.0 * cos(2 * PI * 3.0 * t) * env;
		break;
	}
}
