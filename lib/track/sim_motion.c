/*
 * Simulator motion: the script grammar and the velocity profile of each segment kind.
 * Every profile is shaped by sin^2 over its segment, so velocities start and end at zero
 * and the motion stays continuous across segment boundaries and script loops.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "private/rs_vec.h"
#include "sim_internal.h"

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

enum rs_status rs_sim_script_seconds(const char *script, double *out_s, struct rs_error *err)
{
	RS_ASSERT(out_s);
	struct sim_segment seg[RS_SIM_MAX_SEGMENTS];
	size_t n = 0;
	enum rs_status st =
	    sim_parse_script(script && script[0] ? script : RS_SIM_DEFAULT_SCRIPT, seg, &n, err);
	if (st != RS_OK)
		return st;
	double total = 0;
	for (size_t i = 0; i < n; i++)
		total += seg[i].duration_s;
	*out_s = total;
	return RS_OK;
}

void sim_quat_integrate(double q[4], const double w_world[3], const double w_body[3], double h)
{
	double e[4], v[3];
	rs_v3_scale(w_world, h, v);
	rs_q_exp(v, e);
	rs_q_mul(e, q, q);
	rs_v3_scale(w_body, h, v);
	rs_q_exp(v, e);
	rs_q_mul(q, e, q);
	rs_q_normalize(q, q);
}

void sim_segment_motion(const struct sim_segment *seg, double t, const double q[4],
                        struct sim_motion *out)
{
	memset(out, 0, sizeof *out);
	double D = seg->duration_s;
	double s = sin(RS_PI * t / D);
	double env = s * s; /* integrates to D/2 over the segment */
	switch (seg->kind) {
	case SIM_STILL:
		break;
	case SIM_WALK: {
		/* Forward along the body's heading at up to 0.6 m/s, with a 1.8 Hz, 3 cm bob. */
		static const double x_axis[3] = {1, 0, 0};
		double f[3];
		rs_q_rotate(q, x_axis, f);
		double n = sqrt(f[0] * f[0] + f[1] * f[1]);
		if (n < 1e-6) {
			f[0] = 1;
			f[1] = 0;
			n = 1;
		}
		out->v_world[0] = 0.6 * env * f[0] / n;
		out->v_world[1] = 0.6 * env * f[1] / n;
		out->v_world[2] = 0.03 * 2 * RS_PI * 1.8 * cos(2 * RS_PI * 1.8 * t) * env;
		break;
	}
	case SIM_TURN:
		/* A quarter turn about the vertical, plus a gentle 10 degree tilt and back. */
		out->w_world[2] = (RS_PI / 2) * env * 2.0 / D;
		out->w_body[0] =
		    (10.0 * RS_PI / 180.0) * 2 * RS_PI / D * cos(2 * RS_PI * t / D) * 0.5;
		break;
	case SIM_SHAKE:
		/* Hand shake: 4-5 Hz rotation about two body axes, 1 cm lateral wobble. */
		out->w_body[0] = 1.5 * sin(2 * RS_PI * 4.0 * t) * env;
		out->w_body[1] = 1.0 * sin(2 * RS_PI * 5.0 * t + 1.0) * env;
		out->v_world[1] = 0.01 * 2 * RS_PI * 3.0 * cos(2 * RS_PI * 3.0 * t) * env;
		break;
	}
}
