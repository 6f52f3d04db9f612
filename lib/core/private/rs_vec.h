/*
 * Private to raystream (never installed): the one copy of the double-precision vector and
 * quaternion helpers, used by pose, trace and the tracker simulator. cglm is float-only,
 * so it stays with the GL-side matrices. Quaternions are stored x, y, z, w like struct
 * rs_pose; every helper allows its output to alias an input.
 */
#ifndef RS_VEC_H
#define RS_VEC_H

#include <math.h>
#include <string.h>

static inline double rs_v3_dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void rs_v3_sub(const double a[3], const double b[3], double out[3])
{
	out[0] = a[0] - b[0];
	out[1] = a[1] - b[1];
	out[2] = a[2] - b[2];
}

static inline void rs_v3_cross(const double a[3], const double b[3], double out[3])
{
	double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
	               a[0] * b[1] - a[1] * b[0]};
	memcpy(out, r, sizeof r);
}

static inline double rs_v3_norm(const double a[3])
{
	return sqrt(rs_v3_dot(a, a));
}

static inline void rs_v3_scale(const double a[3], double s, double out[3])
{
	out[0] = a[0] * s;
	out[1] = a[1] * s;
	out[2] = a[2] * s;
}

/* out = a + s * b */
static inline void rs_v3_madd(const double a[3], double s, const double b[3], double out[3])
{
	out[0] = a[0] + s * b[0];
	out[1] = a[1] + s * b[1];
	out[2] = a[2] + s * b[2];
}

/* Normalise in place; returns the old length. Zero, tiny or non-finite vectors are left as
 * they are and 0 is returned, so callers pick a fallback instead of dividing by zero. */
static inline double rs_v3_normalize(double v[3])
{
	double len = sqrt(rs_v3_dot(v, v));
	if (!(len > 1e-300) || !isfinite(len))
		return 0.0;
	v[0] /= len;
	v[1] /= len;
	v[2] /= len;
	return len;
}

static inline int rs_v3_finite(const double a[3])
{
	return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

static inline double rs_q_dot(const double a[4], const double b[4])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

/* Hamilton product a * b (apply b first, then a). */
static inline void rs_q_mul(const double a[4], const double b[4], double out[4])
{
	double r[4] = {
	    a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
	    a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
	    a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
	    a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
	};
	memcpy(out, r, sizeof r);
}

static inline void rs_q_conj(const double q[4], double out[4])
{
	out[0] = -q[0];
	out[1] = -q[1];
	out[2] = -q[2];
	out[3] = q[3];
}

/* Normalise; returns 0 (and writes identity) for a zero or non-finite quaternion. */
static inline int rs_q_normalize(const double q[4], double out[4])
{
	double n = sqrt(rs_q_dot(q, q));
	if (!(n > 1e-300) || !isfinite(n)) {
		out[0] = out[1] = out[2] = 0.0;
		out[3] = 1.0;
		return 0;
	}
	for (int i = 0; i < 4; ++i)
		out[i] = q[i] / n;
	return 1;
}

/* The w >= 0 hemisphere; on w == 0 the first nonzero of x, y, z is made positive so that
 * q and -q always map to the same representative. */
static inline void rs_q_canonical(double q[4])
{
	int flip = q[3] < 0.0;
	if (q[3] == 0.0) {
		for (int i = 0; i < 3; ++i) {
			if (q[i] != 0.0) {
				flip = q[i] < 0.0;
				break;
			}
		}
	}
	if (flip)
		for (int i = 0; i < 4; ++i)
			q[i] = -q[i];
}

/* Rotate v by unit quaternion q. */
static inline void rs_q_rotate(const double q[4], const double v[3], double out[3])
{
	/* v' = v + 2w (u x v) + 2 u x (u x v), u = q.xyz */
	double t[3], ut[3];
	rs_v3_cross(q, v, t);
	t[0] *= 2.0;
	t[1] *= 2.0;
	t[2] *= 2.0;
	rs_v3_cross(q, t, ut);
	double r[3] = {v[0] + q[3] * t[0] + ut[0], v[1] + q[3] * t[1] + ut[1],
	               v[2] + q[3] * t[2] + ut[2]};
	memcpy(out, r, sizeof r);
}

/* Rotation vector (axis * angle, |angle| <= pi) of a unit quaternion. */
static inline void rs_q_log(const double q_in[4], double out[3])
{
	double q[4] = {q_in[0], q_in[1], q_in[2], q_in[3]};
	if (q[3] < 0.0)
		for (int i = 0; i < 4; ++i)
			q[i] = -q[i];
	double s = rs_v3_norm(q);
	/* atan2 is accurate for both tiny and near-pi angles, unlike acos(w). */
	double angle = 2.0 * atan2(s, q[3]);
	double k = s > 1e-12 ? angle / s : 2.0 / (q[3] > 0.0 ? q[3] : 1.0);
	out[0] = q[0] * k;
	out[1] = q[1] * k;
	out[2] = q[2] * k;
}

/* Unit quaternion of a rotation vector. */
static inline void rs_q_exp(const double v[3], double out[4])
{
	double angle = rs_v3_norm(v);
	double half = 0.5 * angle;
	double k = angle > 1e-12 ? sin(half) / angle : 0.5 - angle * angle / 48.0;
	out[0] = v[0] * k;
	out[1] = v[1] * k;
	out[2] = v[2] * k;
	out[3] = cos(half);
}

/* Spherical interpolation from a (t = 0) to b (t = 1) along the shorter arc. */
static inline void rs_q_slerp(const double a[4], const double b[4], double t, double out[4])
{
	double ac[4], d[4], v[3], step[4];
	rs_q_conj(a, ac);
	rs_q_mul(b, ac, d); /* d * a = b */
	rs_q_log(d, v);
	v[0] *= t;
	v[1] *= t;
	v[2] *= t;
	rs_q_exp(v, step);
	rs_q_mul(step, a, out);
	rs_q_normalize(out, out);
}

#endif
