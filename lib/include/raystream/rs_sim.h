/**
 * @file rs_sim.h
 * Tracker simulator (module rs_track): a handheld display carrying three markers moves
 * along a script of walks, turns, shakes and still periods; each sample comes with its
 * ground-truth pose. Marker noise, dropouts, occlusion of one marker, swapped ids and
 * device clock jitter are optional; a seed makes every run reproducible (the generator is
 * the simulator's own, so results do not depend on the C library).
 * Frame conventions: tracker frame z up, metres; the truth is T_tracker_body (the marker
 * layout's frame), so marker i is at R * layout[i] + t.
 */
#ifndef RS_SIM_H
#define RS_SIM_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Script used when rs_sim_desc::script is NULL or "" (it loops). */
#define RS_SIM_DEFAULT_SCRIPT "still:0.5,walk:2,turn:2,shake:1,still:0.5"
/** Longest script, in segments. */
#define RS_SIM_MAX_SEGMENTS 32

/** Simulation options; zero = defaults (rs_sim_desc_resolve()). */
struct rs_sim_desc {
	uint64_t seed;         /**< generator seed; 0 means 1 */
	double rate_hz;        /**< samples per second, default 120, range [0.01, 1e6] */
	double noise_sigma_m;  /**< per-axis Gaussian marker noise, default 0 */
	double dropout_prob;   /**< per marker and sample: reported not valid, default 0 */
	double occlusion_prob; /**< per sample: one marker starts an occlusion, default 0 */
	double occlusion_s;    /**< length of an occlusion, default 0.3 s */
	double swap_prob;      /**< per sample: two marker ids exchanged, default 0 */
	double clock_jitter_s; /**< sigma of device timestamp jitter, default 0, at most 1 s
	                            (kept monotonic) */
	double duration_s; /**< simulated time after which rs_sim_next() says RS_END; 0: endless */
	uint32_t first_sequence; /**< sequence number of the first sample, default 0 */
	/** Motion script: comma-separated `name[:seconds]`, names still, walk, turn, shake.
	 *  Copied at create. NULL/"": RS_SIM_DEFAULT_SCRIPT. */
	const char *script;
	/** Marker i's position in the body frame (m); copied at create. NULL: the default
	 *  layout (0,0,0), (0.10,0,0), (0.02,0.08,0), the same as rs_pose_layout_default(). */
	const double (*layout)[3];
	/** Where the motion starts in the tracker frame (m); default (0, 0, 0) */
	double start_position[3];
};

/** A running simulation. */
struct rs_sim;

/** Copy `desc` (NULL: all zero) into `out` with defaults filled in (script stays NULL
 *  when defaulted; layout stays NULL). */
void rs_sim_desc_resolve(const struct rs_sim_desc *desc, struct rs_sim_desc *out);

/** The default marker layout (m), as described at rs_sim_desc::layout. */
void rs_sim_default_layout(double out_layout[RS_TRACK_MARKERS][3]);

/**
 * Create a simulation. RS_ERR_INVALID with a message for a bad field or script (negative
 * or non-finite numbers, probabilities outside [0, 1], unknown segment names).
 * Destroy with rs_sim_destroy().
 */
enum rs_status rs_sim_create(const struct rs_sim_desc *desc, struct rs_sim **out_sim,
                             struct rs_error *err);

/** Free `*sim` (NULL allowed) and set it to NULL. */
void rs_sim_destroy(struct rs_sim **sim);

/**
 * Produce the next sample (caller-owned `out_sample`; host_time_s = simulated time in s)
 * and, if `out_truth` is not NULL, the ground-truth pose T_tracker_body at that time.
 * Returns RS_OK, or RS_END once duration_s has passed.
 */
enum rs_status rs_sim_next(struct rs_sim *sim, struct rs_marker_sample *out_sample,
                           struct rs_pose *out_truth, struct rs_error *err);

/** Length in seconds of one pass of `script` (NULL or "": RS_SIM_DEFAULT_SCRIPT, 6 s);
 *  RS_ERR_INVALID with a message for a bad script. */
enum rs_status rs_sim_script_seconds(const char *script, double *out_s, struct rs_error *err);

/**
 * Parse `key=value&key=value` (the part after "sim:") into `out_desc` (zeroed first).
 * Keys: seed, rate (Hz), noise (length: 0.5mm, 500um, 0.0005 = m), dropout, occlusion,
 * occlusion_time (time), swap, jitter (time: 0.2ms, 200us, 0.0002 = s), duration (time),
 * first_seq, script; an explicit rate must lie in [0.01, 1e6] Hz (rate=0 is refused, not
 * read as the default). The script text is copied into `script_buf` (capacity
 * `script_cap`) and out_desc->script points there. RS_ERR_PARSE with a message naming
 * the bad key or value; unknown keys are errors.
 */
enum rs_status rs_sim_parse_params(const char *params, struct rs_sim_desc *out_desc,
                                   char *script_buf, size_t script_cap, struct rs_error *err);

/**
 * Parse one `key=value` pair of rs_sim_parse_params() into `desc`. Returns RS_OK,
 * RS_ERR_NOT_FOUND for an unknown key (so callers can add their own keys), RS_ERR_PARSE
 * for a bad value. `key`/`value` are not NUL-terminated: lengths given.
 */
enum rs_status rs_sim_parse_pair(const char *key, size_t key_len, const char *value,
                                 size_t value_len, struct rs_sim_desc *desc, char *script_buf,
                                 size_t script_cap, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
