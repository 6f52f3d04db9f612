/* Motion consistency (issue 19): constant-velocity extrapolation of a pose, and the step
 * gate that holds a solved pose which jumps further from its prediction than its stated
 * error and a hand's acceleration allow. Shared by the pose solver and the optical
 * tracker, each with its own stated errors. */
#include "raystream/rs_pose.h"

#include "private/rs_vec.h"

#include <string.h>

void rs_pose_extrapolate(const struct rs_pose *p, const double velocity[3],
                         const double angular_velocity[3], double h, struct rs_pose *out)
{
	RS_ASSERT(p && velocity && angular_velocity && out);
	double rv[3], dq[4], q[4];
	struct rs_pose r = *p;
	for (int k = 0; k < 3; ++k) {
		r.position[k] += velocity[k] * h;
		rv[k] = angular_velocity[k] * h;
	}
	rs_q_exp(rv, dq);
	rs_q_mul(dq, p->orientation, q);
	rs_q_normalize(q, r.orientation);
	rs_q_canonical(r.orientation);
	*out = r;
}

void rs_pose_velocity_update(const struct rs_pose *prev, const struct rs_pose *now,
                             double time_constant_s, double max_gap_s, double velocity[3],
                             double angular_velocity[3])
{
	RS_ASSERT(now && velocity && angular_velocity);
	double dt = prev ? now->time_s - prev->time_s : 0.0;
	if (!prev || !(dt > 0.0) || dt > max_gap_s) {
		memset(velocity, 0, 3 * sizeof(double));
		memset(angular_velocity, 0, 3 * sizeof(double));
		return;
	}
	/* v += a (d / dt - v) with a = dt / (dt + tc), written as (1 - a) v + d / (dt + tc):
	 * the same value, but d / dt would overflow for a (denormal) dt near 0. The smoothing
	 * keeps marker noise (sigma / dt per sample) from being extrapolated. */
	double inv = 1.0 / (dt + time_constant_s);
	double keep = time_constant_s * inv;
	double qc[4], dq[4], w[3];
	rs_q_conj(prev->orientation, qc);
	rs_q_mul(now->orientation, qc, dq);
	rs_q_log(dq, w);
	for (int k = 0; k < 3; ++k) {
		double d = now->position[k] - prev->position[k];
		velocity[k] = keep * velocity[k] + d * inv;
		angular_velocity[k] = keep * angular_velocity[k] + w[k] * inv;
	}
}

double rs_pose_step_score(const struct rs_pose *predicted, const struct rs_pose *pose,
                          double rot_rms, double pos_rms, double dt, double velocity_lag_s)
{
	RS_ASSERT(predicted && pose);
	/* What constant velocity cannot foresee: half the largest acceleration times dt^2,
	 * and the velocity estimate's lag behind it (acceleration times lag, for dt). */
	double h = dt > 0.0 ? dt * (0.5 * dt + (velocity_lag_s > 0.0 ? velocity_lag_s : 0.0)) : 0.0;
	double ar = RS_POSE_MAX_ANGULAR_ACCEL * h, ap = RS_POSE_MAX_ACCEL * h;
	double a = rs_pose_angle_between(predicted, pose), d[3];
	rs_v3_sub(pose->position, predicted->position, d);
	double e2 = rs_v3_dot(d, d);
	/* The acceleration is a bound, not noise: what is left of the step beyond it, against
	 * the stated errors. */
	double ra = a > ar ? a - ar : 0.0, rp = sqrt(e2) > ap ? sqrt(e2) - ap : 0.0;
	double zr = ra * ra / (rot_rms * rot_rms);
	double zp = rp * rp / (pos_rms * pos_rms);
	double z = zr > zp ? zr : zp;
	return isnan(z) ? INFINITY : z;
}
