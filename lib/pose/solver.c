/* Marker samples to T_tracker_display: validity checks, the degeneracy gate, relabelling of
 * swapped ids by side lengths, the Horn fit, the calibration offset, and a defined answer
 * (held, predicted or none) whenever a sample cannot be solved. */
#include "raystream/rs_pose.h"

#include "pose_internal.h"
#include "private/rs_vec.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

struct rs_pose_solver {
	struct rs_pose_solver_desc desc;
	struct rs_pose_layout layout;
	double layout_sides[3];
	double side_tolerance; /* m: worst side mismatch still taken for this layout */
	double rotation_rms;   /* rad: stated error of a solved pose (rs_pose_error_law) */
	double position_rms;   /* m */
	int have_pose;
	struct rs_pose last_good;   /* T_tracker_display of the last solved sample */
	double velocity[3];         /* smoothed, m/s */
	double angular_velocity[3]; /* smoothed, rad/s, tracker frame */
	double last_time;           /* latest finite sample time seen */
	char message[RS_ERROR_MESSAGE_MAX];
};

/* A labelling is taken only when the measured side lengths lie at least this many standard
 * deviations of their noise from every other ordering's decision boundary, so a wrong one
 * needs a > 4.5 sigma noise excursion (plus half the orderings' distance) to be reported
 * good; see rs_pose_label() and docs/pose.md. */
#define LABEL_MIN_SEPARATION 4.5
/* Residual gate: the 2e-5 tail of chi-square with 3 degrees of freedom (docs/pose.md). */
#define RS_POSE_RESIDUAL_CHI2 24.4

void rs_pose_solver_desc_resolve(const struct rs_pose_solver_desc *desc,
                                 struct rs_pose_solver_desc *out)
{
	struct rs_pose_solver_desc d;
	if (desc)
		d = *desc;
	else
		memset(&d, 0, sizeof d);
	if (d.noise_sigma_m == 0.0)
		d.noise_sigma_m = 0.0005;
	if (d.min_height_sigmas == 0.0)
		d.min_height_sigmas = 10.0;
	if (d.hold_timeout_s == 0.0)
		d.hold_timeout_s = 0.5;
	if (d.max_prediction_s == 0.0)
		d.max_prediction_s = RS_POSE_MAX_PREDICTION_S;
	if (d.velocity_time_constant_s == 0.0)
		d.velocity_time_constant_s = 0.05;
	*out = d;
}

const char *rs_pose_status_name(enum rs_pose_status status)
{
	switch (status) {
	case RS_POSE_OK:
		return "RS_POSE_OK";
	case RS_POSE_RELABELED:
		return "RS_POSE_RELABELED";
	case RS_POSE_HELD:
		return "RS_POSE_HELD";
	case RS_POSE_PREDICTED:
		return "RS_POSE_PREDICTED";
	case RS_POSE_NONE:
		return "RS_POSE_NONE";
	}
	return "RS_POSE_UNKNOWN";
}

static int valid_param(double v)
{
	return isfinite(v) && v >= 0.0;
}

enum rs_status rs_pose_solver_create(const struct rs_pose_solver_desc *desc,
                                     const struct rs_pose_layout *layout,
                                     struct rs_pose_solver **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_pose_solver_desc d;
	rs_pose_solver_desc_resolve(desc, &d);
	if (!valid_param(d.noise_sigma_m) || !valid_param(d.min_height_sigmas) ||
	    !valid_param(d.hold_timeout_s) || !valid_param(d.max_prediction_s) ||
	    !valid_param(d.velocity_time_constant_s))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pose solver: descriptor fields must be finite and >= 0");
	if (d.max_prediction_s > RS_POSE_MAX_PREDICTION_S)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pose solver: max_prediction_s %g s above the %g s cap",
		                    d.max_prediction_s, RS_POSE_MAX_PREDICTION_S);
	enum rs_status st = rs_pose_layout_check(layout, err);
	if (st != RS_OK)
		return st;
	struct rs_pose_solver *s = calloc(1, sizeof *s);
	if (!s)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pose solver: out of memory");
	s->desc = d;
	s->layout = *layout;
	double *q = s->layout.T_markers_display.orientation;
	if (q[0] == 0.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0)
		q[3] = 1.0;
	rs_q_normalize(q, q);
	rs_q_canonical(q);
	double h;
	rs_pose_triangle_metrics(layout->markers, s->layout_sides, &h);
	rs_pose_error_law(&s->layout, d.noise_sigma_m, &s->rotation_rms, &s->position_rms);
	/* Side lengths carry about sqrt(2) sigma of noise each; beyond ten of those plus 2 mm of
	 * calibration slack the points are not this display's markers at all. */
	s->side_tolerance = 10.0 * sqrt(2.0) * d.noise_sigma_m + 0.002;
	rs_pose_solver_reset(s);
	*out = s;
	return RS_OK;
}

void rs_pose_solver_destroy(struct rs_pose_solver **solver)
{
	if (!solver)
		return;
	free(*solver);
	*solver = NULL;
}

void rs_pose_solver_reset(struct rs_pose_solver *s)
{
	if (!s)
		return;
	s->have_pose = 0;
	memset(&s->last_good, 0, sizeof s->last_good);
	s->last_good.orientation[3] = 1.0;
	memset(s->velocity, 0, sizeof s->velocity);
	memset(s->angular_velocity, 0, sizeof s->angular_velocity);
	s->last_time = 0.0;
	s->message[0] = '\0';
}

const char *rs_pose_solver_last_error(const struct rs_pose_solver *s)
{
	return s ? s->message : "pose solver: NULL";
}

static void note(struct rs_pose_solver *s, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(s->message, sizeof s->message, fmt, ap);
	va_end(ap);
}

/* No solution for this sample: hold, predict or give up, as configured. */
static void lost(struct rs_pose_solver *s, double t, struct rs_pose *out, struct rs_pose_quality *q)
{
	double elapsed = t - s->last_good.time_s;
	if (!s->have_pose || elapsed > s->desc.hold_timeout_s) {
		memset(out, 0, sizeof *out);
		out->orientation[3] = 1.0;
		out->time_s = t;
		q->status = RS_POSE_NONE;
		return;
	}
	*out = s->last_good;
	out->time_s = t;
	if (!s->desc.predict_when_lost) {
		q->status = RS_POSE_HELD;
		return;
	}
	double h = elapsed < 0.0 ? 0.0 : elapsed;
	if (h > s->desc.max_prediction_s)
		h = s->desc.max_prediction_s;
	rs_pose_extrapolate(&s->last_good, s->velocity, s->angular_velocity, h, out);
	out->time_s = t;
	q->status = RS_POSE_PREDICTED;
	/* An absurd configuration (max_prediction_s and hold_timeout_s near DBL_MAX) could
	 * extrapolate past the double range: never hand that out, hold instead. */
	if (!rs_v3_finite(out->position) ||
	    !isfinite(rs_q_dot(out->orientation, out->orientation))) {
		*out = s->last_good;
		out->time_s = t;
		q->status = RS_POSE_HELD;
	}
}

/* Smoothed velocities of the solved poses, for PREDICTED and the step gate. */
static void update_velocity(struct rs_pose_solver *s, const struct rs_pose *p)
{
	rs_pose_velocity_update(s->have_pose ? &s->last_good : NULL, p,
	                        s->desc.velocity_time_constant_s, s->desc.hold_timeout_s,
	                        s->velocity, s->angular_velocity);
}

/* One labelling's solution: the display pose, the fit's residual and its chi-square. */
struct candidate {
	int ordering;
	struct rs_pose pose;
	double rms, chi2_total, chi2_marker;
	char message[RS_ERROR_MESSAGE_MAX];
};

/* Fit ordering p (rs_pose_perms) of the measured points; false when the fit fails. */
static int solve_ordering(const struct rs_pose_solver *s, const double pts[3][3], int p,
                          struct candidate *c)
{
	double model[3][3];
	for (int j = 0; j < 3; ++j)
		memcpy(model[j], s->layout.markers[rs_pose_perms[p][j]], sizeof model[j]);
	struct rs_pose T;
	struct rs_error e;
	rs_error_clear(&e);
	c->ordering = p;
	c->message[0] = '\0';
	if (rs_pose_fit((const double(*)[3])model, pts, 3, &T, &c->rms, &e) != RS_OK) {
		snprintf(c->message, sizeof c->message, "%s", e.message);
		return 0;
	}
	/* Nine coordinates less six pose parameters: sum |r|^2 / sigma^2 is chi-square with 3
	 * degrees of freedom; one marker's share is at most that (the fit's projection only
	 * shrinks isotropic noise). */
	double sig2 = s->desc.noise_sigma_m * s->desc.noise_sigma_m;
	c->chi2_total = c->chi2_marker = 0.0;
	for (int j = 0; j < 3; ++j) {
		double f[3], r[3];
		rs_pose_transform_point(&T, model[j], f);
		rs_v3_sub(pts[j], f, r);
		double z = rs_v3_dot(r, r) / sig2;
		c->chi2_total += z;
		c->chi2_marker = z > c->chi2_marker ? z : c->chi2_marker;
	}
	rs_pose_compose(&T, &s->layout.T_markers_display, &c->pose);
	return 1;
}

/* The step gate of pose against its prediction from the last good pose, `since` seconds
 * older: both carry the stated error. */
static double step_score(const struct rs_pose_solver *s, const struct rs_pose *predicted,
                         const struct rs_pose *pose, double since)
{
	return rs_pose_step_score(predicted, pose, sqrt(2.0) * s->rotation_rms,
	                          sqrt(2.0) * s->position_rms, since,
	                          s->desc.velocity_time_constant_s);
}

/* Side lengths leave the ids open: the ordering whose pose is consistent with the
 * prediction, if exactly one is (every other refused by the step gate). */
static int settle_by_prior(const struct rs_pose_solver *s, const double pts[3][3],
                           const struct rs_pose *predicted, double since, struct candidate *out)
{
	int found = 0;
	for (int p = 0; p < 6; ++p) {
		struct candidate c;
		if (!solve_ordering(s, pts, p, &c))
			continue;
		if (!(step_score(s, predicted, &c.pose, since) <= RS_POSE_STEP_CHI2))
			continue;
		if (found++)
			return 0;
		*out = c;
	}
	return found == 1;
}

static int marker_usable(const struct rs_marker *m)
{
	if (!(m->flags & RS_MARKER_VALID) || (m->flags & RS_MARKER_OCCLUDED))
		return 0;
	for (int k = 0; k < 3; ++k)
		if (!(fabs(m->position[k]) <= RS_POSE_MAX_COORD_M))
			return 0;
	return 1;
}

enum rs_status rs_pose_solver_update(struct rs_pose_solver *s,
                                     const struct rs_marker_sample *sample, struct rs_pose *out,
                                     struct rs_pose_quality *out_quality)
{
	struct rs_pose_quality qdummy;
	struct rs_pose_quality *q = out_quality ? out_quality : &qdummy;
	memset(q, 0, sizeof *q);
	RS_ASSERT(s && sample && out);
	s->message[0] = '\0';
	double t = sample->host_time_s;
	if (!isfinite(t)) {
		note(s, "non-finite sample time");
		lost(s, s->last_time, out, q);
		return RS_OK;
	}
	s->last_time = t;
	if (sample->marker_count > RS_TRACK_MARKERS) {
		note(s, "marker_count %u > %d", (unsigned)sample->marker_count, RS_TRACK_MARKERS);
		lost(s, t, out, q);
		return RS_OK;
	}
	double pts[3][3];
	int given[3], n = 0;
	for (uint32_t i = 0; i < sample->marker_count; ++i) {
		const struct rs_marker *m = &sample->markers[i];
		if (!marker_usable(m))
			continue;
		memcpy(pts[n], m->position, sizeof pts[n]);
		given[n] = m->id < RS_TRACK_MARKERS ? (int)m->id : -1;
		++n;
	}
	q->markers_used = (uint32_t)n;
	if (n < 3) {
		note(s, "only %d usable markers (need 3)", n);
		lost(s, t, out, q);
		return RS_OK;
	}
	double sides[3], h;
	rs_pose_triangle_metrics((const double(*)[3])pts, sides, &h);
	q->min_height_m = h;
	double gate = s->desc.min_height_sigmas * s->desc.noise_sigma_m;
	if (!(h >= gate) || !(h > 0.0)) {
		note(s, "degenerate marker triangle: smallest height %.3g m < gate %.3g m", h,
		     gate);
		lost(s, t, out, q);
		return RS_OK;
	}
	double worst = INFINITY, separation = 0.0;
	int p = rs_pose_label(s->layout_sides, (const double(*)[3])pts, sides,
	                      s->desc.noise_sigma_m, &worst, &separation);
	if (!(worst <= s->side_tolerance)) {
		note(s, "marker distances do not match the layout (off by %.3g m > %.3g m)", worst,
		     s->side_tolerance);
		lost(s, t, out, q);
		return RS_OK;
	}
	/* A recent good pose predicts this one (constant velocity): the step gate below, and
	 * the labelling's tie-breaker where the side lengths cannot decide. */
	struct rs_pose predicted;
	double since = t - s->last_good.time_s;
	int have_prior = !s->desc.independent_samples && s->have_pose && since > 0.0 &&
	                 since <= s->desc.hold_timeout_s;
	if (have_prior)
		rs_pose_extrapolate(&s->last_good, s->velocity, s->angular_velocity, since,
		                    &predicted);
	struct candidate c;
	/* The tracker's ids are no evidence: a swapped pair that noise makes fit almost as
	 * well as the truth is exactly the case that must not come back as a good pose. */
	if (separation >= LABEL_MIN_SEPARATION) {
		if (!solve_ordering(s, (const double(*)[3])pts, p, &c)) {
			note(s, "%s", c.message);
			lost(s, t, out, q);
			return RS_OK;
		}
	} else if (!have_prior ||
	           !settle_by_prior(s, (const double(*)[3])pts, &predicted, since, &c)) {
		note(s,
		     "marker ids ambiguous: side lengths only %.2f sigma from another ordering "
		     "(need %.1f)%s",
		     separation, LABEL_MIN_SEPARATION,
		     have_prior ? ", and the predicted pose does not settle them" : "");
		lost(s, t, out, q);
		return RS_OK;
	}
	/* The consistency gate (issue 19): a pose that fails is held, never reported good. */
	if (!(c.chi2_total <= RS_POSE_RESIDUAL_CHI2) || !(c.chi2_marker <= RS_POSE_RESIDUAL_CHI2)) {
		note(s,
		     "fit residual beyond the stated noise: chi-square %.1f total, %.1f worst "
		     "marker (bound %.1f)",
		     c.chi2_total, c.chi2_marker, RS_POSE_RESIDUAL_CHI2);
		lost(s, t, out, q);
		return RS_OK;
	}
	double step = have_prior ? step_score(s, &predicted, &c.pose, since) : 0.0;
	if (!(step <= RS_POSE_STEP_CHI2)) {
		note(s, "step from the predicted pose: %.1f times its variance (bound %.1f)", step,
		     RS_POSE_STEP_CHI2);
		lost(s, t, out, q);
		return RS_OK;
	}
	int same = 1;
	for (int j = 0; j < 3; ++j)
		same &= given[j] == rs_pose_perms[c.ordering][j];
	struct rs_pose pose = c.pose;
	double rms = c.rms;
	pose.time_s = t;
	update_velocity(s, &pose);
	s->last_good = pose;
	s->have_pose = 1;
	*out = pose;
	q->status = same ? RS_POSE_OK : RS_POSE_RELABELED;
	q->residual_rms_m = rms;
	q->rotation_rms_rad = s->rotation_rms;
	q->position_rms_m = s->position_rms;
	return RS_OK;
}
