/**
 * @file rs_pose.h
 * Display pose from three tracked markers: the marker layout (calibration), the closed-form
 * rigid fit (Horn's quaternion method, double precision, centred first), a solver that turns
 * marker samples into T_tracker_display with a quality figure and defined answers for every
 * bad sample, and an optional 1-euro filter with capped constant-velocity prediction.
 *
 * Conventions (VRPN's): metres, seconds, quaternions x, y, z, w in the canonical hemisphere
 * (w >= 0). T_A_B is frame B expressed in frame A: it maps B-frame points into frame A, so
 * T_tracker_display = T_tracker_markers * T_markers_display.
 * See docs/pose.md for the maths, the gates and the error bounds the tests assert.
 */
#ifndef RS_POSE_H
#define RS_POSE_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Layout check: every two side lengths of the marker triangle must differ by more than this. */
#define RS_POSE_LAYOUT_MIN_SIDE_DIFF_M 0.005
/** Layout check: the smallest height of the marker triangle must exceed this. */
#define RS_POSE_LAYOUT_MIN_HEIGHT_M 0.01
/** Largest allowed max_prediction_s (solver and filter): extrapolating further mostly
 *  amplifies jitter. Also the default. */
#define RS_POSE_MAX_PREDICTION_S 0.03
/** Marker coordinates beyond this magnitude are treated as invalid (keeps sums finite). */
#define RS_POSE_MAX_COORD_M 1.0e6

/** The rigid marker layout of the display and the marker-to-display calibration offset. */
struct rs_pose_layout {
	/** Marker id i's position in the marker (body) frame, metres. */
	double markers[RS_TRACK_MARKERS][3];
	/** Display frame expressed in the marker frame; an all-zero orientation means identity. */
	struct rs_pose T_markers_display;
	/** An optional fourth light, the verifier, in the marker frame (metres), used when
	 *  has_verifier is nonzero. It is not part of the pose's triangle: the optical tracker
	 *  checks that it is seen where each pose puts it, which refuses a stray spot that
	 *  three markers cannot tell from a marker (docs/optical.md, "The verifier"). The
	 *  pose solver ignores it. */
	double verifier[3];
	uint32_t has_verifier;
};

/** Layout check: the verifier lies at least this far from the line through any two markers
 *  (a pose error that turns the triangle about one of its sides moves it) and each
 *  triangle of two markers and the verifier has sides at least this far from the layout's
 *  in every ordering (it is never taken for the marker triangle). */
#define RS_POSE_LAYOUT_MIN_VERIFIER_M 0.02

/**
 * Load a layout from a JSON calibration file:
 * `{"markers": [[x,y,z],[x,y,z],[x,y,z]],
 *   "T_markers_display": {"position":[x,y,z], "orientation":[x,y,z,w]},
 *   "verifier": [x,y,z]}` (metres).
 * "T_markers_display" may be omitted (identity), "verifier" too (none). The orientation is
 * normalised and put in the w >= 0 hemisphere. The layout is checked with rs_pose_layout_check().
 * @param path        file to read (caller's string, not kept)
 * @param out_layout  caller-owned; written only on RS_OK
 * @return RS_OK, RS_ERR_NOT_FOUND / RS_ERR_IO (file), RS_ERR_PARSE (JSON or shape),
 *         RS_ERR_BAD_DATA (non-finite numbers, zero quaternion), RS_ERR_DEGENERATE (layout).
 */
enum rs_status rs_pose_layout_load(const char *path, struct rs_pose_layout *out_layout,
                                   struct rs_error *err);

/**
 * Reject non-scalene or degenerate layouts: all coordinates finite (and, like the
 * calibration offset, within RS_POSE_MAX_COORD_M), smallest triangle height
 * > RS_POSE_LAYOUT_MIN_HEIGHT_M, every two sides differ by > RS_POSE_LAYOUT_MIN_SIDE_DIFF_M
 * (so swapped marker ids can be told apart by side lengths), unit (or all-zero = identity)
 * calibration quaternion; with a verifier: finite, and RS_POSE_LAYOUT_MIN_VERIFIER_M from
 * every side's line and from the triangle's side lengths.
 * @return RS_OK, RS_ERR_INVALID (NULL), RS_ERR_BAD_DATA or RS_ERR_DEGENERATE.
 */
enum rs_status rs_pose_layout_check(const struct rs_pose_layout *layout, struct rs_error *err);

/**
 * The example layout used by tests and the simulator: a 10 cm x 8 cm scalene triangle in the
 * marker frame's z = 0 plane, marker 0 = (0, 0, 0), 1 = (0.10, 0, 0), 2 = (0.02, 0.08, 0);
 * sides 0.1000, 0.1131, 0.0825 m; smallest height 0.0707 m; T_markers_display = identity.
 */
void rs_pose_layout_default(struct rs_pose_layout *out_layout);

/**
 * rs_pose_layout_default() with a verifier light on a 12 cm post above the triangle's
 * plane, at (0.04, 0.03, 0.12): 130-138 mm from the markers, 122-124 mm from each side's
 * line, the triangles it makes with two markers at least 30 mm from the layout's sides in
 * every ordering. Lower posts see a stray less well: docs/optical.md, "The verifier".
 */
void rs_pose_layout_default_verified(struct rs_pose_layout *out_layout);

/** What a solved pose is based on. */
enum rs_pose_status {
	RS_POSE_OK = 0,        /**< solved from three good markers */
	RS_POSE_RELABELED = 1, /**< solved after reassigning swapped marker ids by side lengths */
	RS_POSE_HELD = 2,      /**< could not solve (degenerate/missing/NaN); last pose returned */
	RS_POSE_PREDICTED =
	    3, /**< could not solve; last pose extrapolated (constant velocity, capped) */
	RS_POSE_NONE =
	    4, /**< nothing solved yet (or lost past hold_timeout_s): identity, do not use */
};

/** Quality figures of one solver update. */
struct rs_pose_quality {
	enum rs_pose_status status;
	double residual_rms_m; /**< RMS of fitted-model minus measured marker positions (0 if not
	                          solved) */
	double
	    min_height_m; /**< smallest height of the measured marker triangle (0 if < 3 markers) */
	uint32_t markers_used; /**< markers that passed the validity checks (3 when solved) */
	/** Stated RMS rotation error of a solved pose (OK/RELABELED; 0 otherwise) for the
	 *  solver's noise_sigma_m: sigma sqrt(trace J^-1), docs/pose.md. A good pose is within
	 *  6 times this unless the real noise exceeds noise_sigma_m. */
	double rotation_rms_rad;
	/** Stated RMS 3-D position error of the display origin of a solved pose (0 otherwise). */
	double position_rms_m;
};

/** Solver options; zero-initialised means defaults (see rs_pose_solver_desc_resolve()). */
struct rs_pose_solver_desc {
	double noise_sigma_m;     /**< expected per-axis marker noise, default 0.0005 */
	double min_height_sigmas; /**< gate: solve only if min height >= this * sigma, default 10 */
	double hold_timeout_s; /**< HELD/PREDICTED last at most this long, then NONE; default 0.5 */
	int predict_when_lost; /**< nonzero: PREDICTED instead of HELD */
	double max_prediction_s; /**< cap on the PREDICTED extrapolation horizon, default and
	                            at most RS_POSE_MAX_PREDICTION_S (0.03) */
	double velocity_time_constant_s; /**< smoothing of the velocity used by PREDICTED, default
	                                    0.05 */
	int independent_samples; /**< nonzero: samples are unrelated poses (batch solving, tests):
	                              no step gate and no labelling by the predicted pose */
};

/** Copy `desc` (NULL: all zero) to `out` with every zero field replaced by its default. */
void rs_pose_solver_desc_resolve(const struct rs_pose_solver_desc *desc,
                                 struct rs_pose_solver_desc *out);

struct rs_pose_solver;

/**
 * Create a solver for `layout` (copied; checked with rs_pose_layout_check()).
 * @param desc  NULL or zero fields: defaults. Negative or non-finite fields, or
 *              max_prediction_s > RS_POSE_MAX_PREDICTION_S: RS_ERR_INVALID.
 * @param out   receives the solver; the caller frees it with rs_pose_solver_destroy().
 */
enum rs_status rs_pose_solver_create(const struct rs_pose_solver_desc *desc,
                                     const struct rs_pose_layout *layout,
                                     struct rs_pose_solver **out, struct rs_error *err);

/** Free a solver; accepts NULL and sets *solver to NULL. */
void rs_pose_solver_destroy(struct rs_pose_solver **solver);

/**
 * out_pose = T_tracker_display at sample->host_time_s. Never NaN, never allocates.
 * Markers are used when flagged RS_MARKER_VALID, not RS_MARKER_OCCLUDED, and finite with
 * |coordinate| <= RS_POSE_MAX_COORD_M. Ids are matched to the layout by side lengths when
 * they disagree (RS_POSE_RELABELED). When no pose can be solved the reason is kept as the
 * last error and the last pose is held or predicted (see enum rs_pose_status), stamped with
 * this sample's time (the last finite one if this one is not finite).
 * @param out_quality  may be NULL
 * @return RS_OK whenever a pose (possibly held) is written; the quality status says which.
 *         NULL solver/sample/out_pose is a contract violation (RS_ASSERT).
 */
enum rs_status rs_pose_solver_update(struct rs_pose_solver *solver,
                                     const struct rs_marker_sample *sample,
                                     struct rs_pose *out_pose, struct rs_pose_quality *out_quality);

/** Forget the last pose (next update without a solution gives RS_POSE_NONE). */
void rs_pose_solver_reset(struct rs_pose_solver *solver);

/** Why the last update did not solve (or ""); owned by the solver, valid until its next call. */
const char *rs_pose_solver_last_error(const struct rs_pose_solver *solver);

/** Constant name of a pose status ("RS_POSE_HELD"); never NULL. */
const char *rs_pose_status_name(enum rs_pose_status status);

/**
 * The closed-form least-squares rigid fit (Horn 1987, unit quaternions, double precision,
 * both point sets centred before the cross-covariance is accumulated): T_measured_model so
 * that measured ~= T * model, for n >= 3 point pairs. Always a proper rotation (never a
 * reflection). Caller owns all arrays; nothing is allocated.
 * @param out_rms  may be NULL; RMS distance between T * model and measured
 * @return RS_OK; RS_ERR_INVALID (NULL, n < 3); RS_ERR_BAD_DATA (non-finite or out-of-range
 *         coordinates); RS_ERR_DEGENERATE (points (nearly) collinear or coincident, so the
 *         rotation is not determined). On error *out_T is the identity and *out_rms 0.
 */
enum rs_status rs_pose_fit(const double (*model)[3], const double (*measured)[3], size_t n,
                           struct rs_pose *out_T, double *out_rms, struct rs_error *err);

/**
 * Compose transforms: out = T_a_b * T_b_c (so a point in c maps to a). out may alias either
 * input. The result quaternion is normalised and canonical (w >= 0); time_s is T_b_c's.
 */
void rs_pose_compose(const struct rs_pose *T_a_b, const struct rs_pose *T_b_c, struct rs_pose *out);

/** Apply a pose to a point: out = R * p + t. out may alias p. */
void rs_pose_transform_point(const struct rs_pose *T, const double p[3], double out[3]);

/** Angle in radians of the rotation between two poses' orientations (sign-insensitive). */
double rs_pose_angle_between(const struct rs_pose *a, const struct rs_pose *b);

/** Step gate bound: a solved pose whose squared step from its prediction exceeds this many
 *  times its variance (rs_pose_step_score()) is held. 18 is the 2e-5 tail of one degree of
 *  freedom, the worst case of a step dominated by one axis (docs/pose.md). */
#define RS_POSE_STEP_CHI2 18.0
/** The motion the step gate allows beyond constant velocity: a handheld display's largest
 *  angular (rad/s^2; the simulator's hand shake peaks at 48) and linear (m/s^2)
 *  acceleration. */
#define RS_POSE_MAX_ANGULAR_ACCEL 50.0
#define RS_POSE_MAX_ACCEL 20.0

/**
 * `p` moved on at constant linear and angular velocity (tracker frame, rad/s) for `h`
 * seconds: position + v h, orientation exp(w h) q. out may alias p.
 */
void rs_pose_extrapolate(const struct rs_pose *p, const double velocity[3],
                         const double angular_velocity[3], double h, struct rs_pose *out);

/**
 * Exponentially smoothed finite-difference velocities (time constant time_constant_s) of a
 * sequence of poses: `now` after `prev`. Zeroed when prev is NULL, not older than now, or
 * more than max_gap_s older. Finite for any dt > 0 (also denormal).
 */
void rs_pose_velocity_update(const struct rs_pose *prev, const struct rs_pose *now,
                             double time_constant_s, double max_gap_s, double velocity[3],
                             double angular_velocity[3]);

/**
 * How far `pose` jumped from `predicted` (made from a pose dt seconds older with velocities
 * that lag the motion by velocity_lag_s): the larger of (angle - A h)^2 / rot_rms^2 and
 * (distance - a h)^2 / pos_rms^2 (0 where the step is within A h, a h), h = dt (dt / 2 +
 * lag), with rot_rms, pos_rms the
 * RMS error of the difference (both poses' stated errors in quadrature) and A, a
 * RS_POSE_MAX_ANGULAR_ACCEL, RS_POSE_MAX_ACCEL. Consistent when at most RS_POSE_STEP_CHI2;
 * infinite for non-finite input.
 */
double rs_pose_step_score(const struct rs_pose *predicted, const struct rs_pose *pose,
                          double rot_rms, double pos_rms, double dt, double velocity_lag_s);

/** 1-euro filter options; zero-initialised means defaults (VRPN's vrpn_Tracker_FilterOneEuro). */
struct rs_pose_filter_desc {
	double position_min_cutoff_hz;    /**< default 1.15 Hz */
	double position_beta;             /**< default 0.5 (Hz per m/s); zero means default,
	                                       so use a tiny value for a plain low-pass */
	double position_d_cutoff_hz;      /**< default 1.2 Hz */
	double orientation_min_cutoff_hz; /**< default 1.5 Hz */
	double orientation_beta;          /**< default 0.5 (Hz per rad/s) */
	double orientation_d_cutoff_hz;   /**< default 1.2 Hz */
	double max_prediction_s;          /**< cap on prediction horizon, default and at most
	                                       RS_POSE_MAX_PREDICTION_S (0.03) */
	int disable_filter;               /**< nonzero: pass through (prediction still available) */
	double reset_gap_s;               /**< a gap between samples longer than this restarts the
	                                       filter from the new sample; default 0.25 */
};

/** Copy `desc` (NULL: all zero) to `out` with every zero field replaced by its default. */
void rs_pose_filter_desc_resolve(const struct rs_pose_filter_desc *desc,
                                 struct rs_pose_filter_desc *out);

struct rs_pose_filter;

/**
 * Create a filter. @param desc NULL or zero fields: defaults; negative or non-finite fields,
 * or max_prediction_s > RS_POSE_MAX_PREDICTION_S, give RS_ERR_INVALID. The caller frees *out with
 * rs_pose_filter_destroy().
 */
enum rs_status rs_pose_filter_create(const struct rs_pose_filter_desc *desc,
                                     struct rs_pose_filter **out, struct rs_error *err);

/** Free a filter; accepts NULL and sets *filter to NULL. */
void rs_pose_filter_destroy(struct rs_pose_filter **filter);

/**
 * Feed one pose (its time_s is the sample time) and get the filtered pose. The input
 * quaternion's sign is irrelevant (flipped internally for continuity); the output is
 * canonical (w >= 0). A sample whose time is not after the previous one (dt <= 0) leaves the
 * state unchanged and returns it; a gap > reset_gap_s restarts the filter at the input.
 * @param out  may alias `in`
 * @return RS_OK; RS_ERR_BAD_DATA (non-finite input, |position|
 *         > RS_POSE_MAX_COORD_M or zero quaternion: state unchanged, *out = current state,
 *         or the identity at time 0 if the filter is empty).
 */
enum rs_status rs_pose_filter_update(struct rs_pose_filter *filter, const struct rs_pose *in,
                                     struct rs_pose *out, struct rs_error *err);

/**
 * Constant-velocity prediction from the filtered state to display_time_s; the horizon is
 * clamped to [0, max_prediction_s]. Velocities are the filter's smoothed derivatives.
 * out->time_s is the time the prediction is for: state time + clamped horizon.
 * @return RS_OK; RS_ERR_INVALID (non-finite time); RS_END when no sample was fed yet
 *         (*out = identity at display_time_s).
 */
enum rs_status rs_pose_filter_predict(const struct rs_pose_filter *filter, double display_time_s,
                                      struct rs_pose *out, struct rs_error *err);

/** Forget all state; the next sample starts the filter afresh. Accepts NULL. */
void rs_pose_filter_reset(struct rs_pose_filter *filter);

/** Last error message of the filter (or ""); owned by the filter. */
const char *rs_pose_filter_last_error(const struct rs_pose_filter *filter);

#ifdef __cplusplus
}
#endif
#endif
