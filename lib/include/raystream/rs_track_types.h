/**
 * @file rs_track_types.h
 * Plain data shared by the tracking modules: marker samples as a tracker reports them,
 * and poses as the solver and filters produce them (VRPN's convention: metres,
 * quaternion x, y, z, w, timestamps in seconds).
 */
#ifndef RS_TRACK_TYPES_H
#define RS_TRACK_TYPES_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Markers per sample: three sensors are fixed on the handheld display. */
#define RS_TRACK_MARKERS 3

/** Per-marker flags, as carried on the wire. */
enum rs_marker_flags {
	RS_MARKER_VALID = 1u << 0,       /**< the tracker saw this marker in this sample */
	RS_MARKER_OCCLUDED = 1u << 1,    /**< the tracker reports it hidden (position stale) */
	RS_MARKER_LOW_QUALITY = 1u << 2, /**< seen, but the tracker doubts the position */
};

/** One tracked point. Position in the tracker frame, metres. */
struct rs_marker {
	uint32_t id;    /**< sensor id as reported (0..2 for a well-labelled device) */
	uint32_t flags; /**< enum rs_marker_flags */
	double position[3];
};

/** One timestamped sample of all markers. */
struct rs_marker_sample {
	uint32_t sequence;       /**< device sequence number (wraps at 2^32) */
	uint64_t device_time_us; /**< device clock, microseconds */
	double host_time_s;      /**< host CLOCK_MONOTONIC at receipt, seconds */
	uint32_t marker_count;   /**< entries used in markers[] (<= RS_TRACK_MARKERS) */
	struct rs_marker markers[RS_TRACK_MARKERS];
};

/** A rigid pose: T_tracker_body maps body-frame points into the tracker frame. */
struct rs_pose {
	double time_s;         /**< the sample time this pose describes (host clock, seconds) */
	double position[3];    /**< metres */
	double orientation[4]; /**< unit quaternion x, y, z, w, canonical hemisphere (w >= 0) */
};

#ifdef __cplusplus
}
#endif
#endif
