/* The 1-euro filter (Casiez, Roussel, Vogel, CHI 2012) for poses, with per-sample
 * timestamps, and capped constant-velocity prediction.
 *
 * Position: the reference algorithm per vector (speed = norm of the smoothed derivative, so
 * the cutoff does not depend on the axes). Orientation: on the unit-quaternion manifold, the
 * derivative is the rotation vector of the relative rotation between consecutive samples
 * divided by dt, and smoothing is a slerp by the 1-euro alpha. The derivative is taken from
 * consecutive raw samples, as in the authors' reference implementation, so on a ramp it
 * converges to the true speed and the lag is speed / (2 pi (min_cutoff + beta * speed)). */
#include "raystream/rs_pose.h"

#include "private/rs_vec.h"

#include <stdio.h>
#include <stdlib.h>

struct rs_pose_filter {
	struct rs_pose_filter_desc desc;
	int have;
	double t;
	double x_raw[3], x_hat[3], dx_hat[3];
	double q_raw[4], q_hat[4], w_hat[3]; /* q_raw kept in q_hat's hemisphere */
	char message[RS_ERROR_MESSAGE_MAX];
};

void rs_pose_filter_desc_resolve(const struct rs_pose_filter_desc *desc,
                                 struct rs_pose_filter_desc *out)
{
	struct rs_pose_filter_desc d;
	if (desc)
		d = *desc;
	else
		memset(&d, 0, sizeof d);
	/* VRPN's vrpn_Tracker_FilterOneEuro defaults (vrpn_Tracker_Filter.h). */
	if (d.position_min_cutoff_hz == 0.0)
		d.position_min_cutoff_hz = 1.15;
	if (d.position_beta == 0.0)
		d.position_beta = 0.5;
	if (d.position_d_cutoff_hz == 0.0)
		d.position_d_cutoff_hz = 1.2;
	if (d.orientation_min_cutoff_hz == 0.0)
		d.orientation_min_cutoff_hz = 1.5;
	if (d.orientation_beta == 0.0)
		d.orientation_beta = 0.5;
	if (d.orientation_d_cutoff_hz == 0.0)
		d.orientation_d_cutoff_hz = 1.2;
	if (d.max_prediction_s == 0.0)
		d.max_prediction_s = RS_POSE_MAX_PREDICTION_S;
	if (d.reset_gap_s == 0.0)
		d.reset_gap_s = 0.25;
	*out = d;
}

static int positive(double v)
{
	return isfinite(v) && v > 0.0;
}

enum rs_status rs_pose_filter_create(const struct rs_pose_filter_desc *desc,
                                     struct rs_pose_filter **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_pose_filter_desc d;
	rs_pose_filter_desc_resolve(desc, &d);
	/* beta may be meant as "no speed adaptation"; zero already means default, so only
	 * negative or non-finite values are refused. */
	if (!positive(d.position_min_cutoff_hz) || !positive(d.position_d_cutoff_hz) ||
	    !positive(d.orientation_min_cutoff_hz) || !positive(d.orientation_d_cutoff_hz) ||
	    !positive(d.position_beta) || !positive(d.orientation_beta) ||
	    !positive(d.max_prediction_s) || !positive(d.reset_gap_s))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pose filter: cutoffs, betas, max_prediction_s and reset_gap_s "
		                    "must be finite and > 0");
	if (d.max_prediction_s > RS_POSE_MAX_PREDICTION_S)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pose filter: max_prediction_s %g s above the %g s cap",
		                    d.max_prediction_s, RS_POSE_MAX_PREDICTION_S);
	struct rs_pose_filter *f = calloc(1, sizeof *f);
	if (!f)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pose filter: out of memory");
	f->desc = d;
	rs_pose_filter_reset(f);
	*out = f;
	return RS_OK;
}

void rs_pose_filter_destroy(struct rs_pose_filter **filter)
{
	if (!filter)
		return;
	free(*filter);
	*filter = NULL;
}

void rs_pose_filter_reset(struct rs_pose_filter *f)
{
	if (!f)
		return;
	f->have = 0;
	f->t = 0.0;
	memset(f->x_hat, 0, sizeof f->x_hat);
	memset(f->dx_hat, 0, sizeof f->dx_hat);
	memset(f->w_hat, 0, sizeof f->w_hat);
	memset(f->q_hat, 0, sizeof f->q_hat);
	f->q_hat[3] = 1.0;
	f->message[0] = '\0';
}

const char *rs_pose_filter_last_error(const struct rs_pose_filter *f)
{
	return f ? f->message : "pose filter: NULL";
}

static void state_out(const struct rs_pose_filter *f, struct rs_pose *out)
{
	out->time_s = f->t;
	memcpy(out->position, f->x_hat, sizeof f->x_hat);
	memcpy(out->orientation, f->q_hat, sizeof f->q_hat);
	rs_q_canonical(out->orientation);
}

/* Smoothing factor of a first-order low-pass with cutoff fc sampled after dt. */
static double alpha(double fc, double dt)
{
	double tau = 1.0 / (2.0 * RS_PI * fc);
	return 1.0 / (1.0 + tau / dt);
}

static void start(struct rs_pose_filter *f, double t, const double x[3], const double q[4])
{
	f->have = 1;
	f->t = t;
	memcpy(f->x_raw, x, sizeof f->x_raw);
	memcpy(f->x_hat, x, sizeof f->x_hat);
	memcpy(f->q_raw, q, sizeof f->q_raw);
	memcpy(f->q_hat, q, sizeof f->q_hat);
	memset(f->dx_hat, 0, sizeof f->dx_hat);
	memset(f->w_hat, 0, sizeof f->w_hat);
}

enum rs_status rs_pose_filter_update(struct rs_pose_filter *f, const struct rs_pose *in,
                                     struct rs_pose *out, struct rs_error *err)
{
	RS_ASSERT(f && in && out);
	double q[4], x[3], t = in->time_s;
	memcpy(x, in->position, sizeof x);
	/* Positions beyond RS_POSE_MAX_COORD_M are refused like the solver's markers: their
	 * differences could overflow and turn the state into NaN. */
	int ok = isfinite(t) && fabs(x[0]) <= RS_POSE_MAX_COORD_M &&
	         fabs(x[1]) <= RS_POSE_MAX_COORD_M && fabs(x[2]) <= RS_POSE_MAX_COORD_M &&
	         rs_q_normalize(in->orientation, q);
	if (!ok) {
		snprintf(
		    f->message, sizeof f->message,
		    "pose filter: non-finite or out-of-range input or zero quaternion ignored");
		if (f->have) {
			state_out(f, out);
		} else {
			memset(out, 0, sizeof *out);
			out->orientation[3] = 1.0;
		}
		return rs_error_set(err, RS_ERR_BAD_DATA, "%s", f->message);
	}
	f->message[0] = '\0';
	double dt = t - f->t;
	if (!f->have || dt > f->desc.reset_gap_s) {
		start(f, t, x, q);
		state_out(f, out);
		return RS_OK;
	}
	if (!(dt > 0.0)) {
		/* Repeated or out-of-order timestamp: no rate to work with, keep the state. */
		state_out(f, out);
		return RS_OK;
	}
	const struct rs_pose_filter_desc *d = &f->desc;

	/* Derivative low-pass dx_hat += alpha (dx / dt - dx_hat), alpha = dt / (dt + tau),
	 * evaluated as tau / (dt + tau) * dx_hat + dx / (dt + tau): the same value, but dx / dt
	 * would overflow (and then turn into NaN) for a denormal dt. */
	double tau_d = 1.0 / (2.0 * RS_PI * d->position_d_cutoff_hz);
	double inv = 1.0 / (dt + tau_d), keep = tau_d * inv, speed2 = 0.0;
	for (int k = 0; k < 3; ++k) {
		f->dx_hat[k] = keep * f->dx_hat[k] + (x[k] - f->x_raw[k]) * inv;
		speed2 += f->dx_hat[k] * f->dx_hat[k];
	}
	double a = alpha(d->position_min_cutoff_hz + d->position_beta * sqrt(speed2), dt);
	for (int k = 0; k < 3; ++k)
		f->x_hat[k] = d->disable_filter ? x[k] : f->x_hat[k] + a * (x[k] - f->x_hat[k]);
	memcpy(f->x_raw, x, sizeof x);

	/* q and -q are the same rotation: keep the input in the state's hemisphere so a sign
	 * flip between samples is not a 360-degree jump. */
	if (rs_q_dot(q, f->q_hat) < 0.0)
		for (int k = 0; k < 4; ++k)
			q[k] = -q[k];
	double rc[4], rel[4], w[3];
	rs_q_conj(f->q_raw, rc);
	rs_q_mul(q, rc, rel);
	rs_q_log(rel, w);
	tau_d = 1.0 / (2.0 * RS_PI * d->orientation_d_cutoff_hz);
	inv = 1.0 / (dt + tau_d);
	keep = tau_d * inv;
	speed2 = 0.0;
	for (int k = 0; k < 3; ++k) {
		f->w_hat[k] = keep * f->w_hat[k] + w[k] * inv;
		speed2 += f->w_hat[k] * f->w_hat[k];
	}
	a = alpha(d->orientation_min_cutoff_hz + d->orientation_beta * sqrt(speed2), dt);
	if (d->disable_filter)
		memcpy(f->q_hat, q, sizeof q);
	else
		rs_q_slerp(f->q_hat, q, a, f->q_hat);
	memcpy(f->q_raw, q, sizeof q);
	f->t = t;
	state_out(f, out);
	return RS_OK;
}

enum rs_status rs_pose_filter_predict(const struct rs_pose_filter *f, double display_time_s,
                                      struct rs_pose *out, struct rs_error *err)
{
	RS_ASSERT(f && out);
	if (!isfinite(display_time_s))
		return rs_error_set(err, RS_ERR_INVALID, "pose filter: non-finite display time");
	if (!f->have) {
		memset(out, 0, sizeof *out);
		out->orientation[3] = 1.0;
		out->time_s = display_time_s;
		return rs_error_set(err, RS_END, "pose filter: no pose yet");
	}
	double h = display_time_s - f->t;
	if (h < 0.0)
		h = 0.0;
	if (h > f->desc.max_prediction_s)
		h = f->desc.max_prediction_s;
	double rv[3], dq[4], q[4];
	for (int k = 0; k < 3; ++k) {
		out->position[k] = f->x_hat[k] + f->dx_hat[k] * h;
		rv[k] = f->w_hat[k] * h;
	}
	rs_q_exp(rv, dq);
	rs_q_mul(dq, f->q_hat, q);
	rs_q_normalize(q, q);
	rs_q_canonical(q);
	memcpy(out->orientation, q, sizeof q);
	out->time_s = f->t + h;
	/* Only an absurd max_prediction_s can push this past the double range; then the
	 * unextrapolated state is the one defined answer. */
	if (!rs_v3_finite(out->position) || !isfinite(out->time_s))
		state_out(f, out);
	return RS_OK;
}
