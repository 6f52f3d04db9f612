/**
 * @file rs_track.h
 * Tracker sources (module rs_track): one interface for timestamped marker samples,
 * whatever delivers them. A source is an opaque object behind a small table of function
 * pointers (Monado's driver pattern); backends (backends/serial, hid, usb) implement a
 * byte transport and wrap it with rs_track_stream_create(), which adds the protocol
 * parser, host timestamps and disconnect bookkeeping. This module itself provides the
 * replay (recorded file) and simulator sources and the recorder. URI dispatch over all
 * backends lives in backends/tracker (rs_tracker.h), so lib/ stays free of devices.
 */
#ifndef RS_TRACK_H
#define RS_TRACK_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_proto.h"
#include "raystream/rs_sim.h"
#include "raystream/rs_status.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** An open tracker source. Opaque; see rs_track_source_read(). */
struct rs_track_source;

/** Counters of a source (all zero for sources that do not parse frames). */
struct rs_track_source_stats {
	struct rs_proto_stats proto; /**< parser counters, accumulated over reopens */
	uint64_t samples;            /**< samples returned by rs_track_source_read() */
	uint64_t disconnects;        /**< times the source reported RS_ERR_DISCONNECTED */
	uint64_t reopens;            /**< successful rs_track_source_reopen() calls */
};

/**
 * Wait up to `timeout_ms` (0: poll, < 0: forever) for the next sample and copy it into
 * `out_sample` (caller-owned). host_time_s is CLOCK_MONOTONIC when the bytes arrived
 * (replay: the recorded time). Returns RS_OK, RS_TIMEOUT, RS_END (replay/sim ran out),
 * RS_ERR_DISCONNECTED (device gone: every further read says so until
 * rs_track_source_reopen() succeeds) or another error; the message is in `err` (may be
 * NULL) and in rs_track_source_last_error().
 */
enum rs_status rs_track_source_read(struct rs_track_source *source,
                                    struct rs_marker_sample *out_sample, int timeout_ms,
                                    struct rs_error *err);

/**
 * Reopen the device after RS_ERR_DISCONNECTED (or at any time); clears the parser's
 * buffered bytes and sequence history, keeps the counters. RS_ERR_NOT_FOUND while the
 * device is still absent: try again later.
 */
enum rs_status rs_track_source_reopen(struct rs_track_source *source, struct rs_error *err);

/** Current counters into `out_stats`. */
void rs_track_source_get_stats(const struct rs_track_source *source,
                               struct rs_track_source_stats *out_stats);

/** Last error message of `source`, owned by it, valid until its next call; "" if none. */
const char *rs_track_source_last_error(const struct rs_track_source *source);

/** Close the device and free `*source` (NULL allowed); sets `*source` to NULL. */
void rs_track_source_destroy(struct rs_track_source **source);

/* ---- For implementers of sources (backends) ------------------------------------------ */

/** A sample-level source implementation. `impl` is whatever the implementer allocated. */
struct rs_track_source_ops {
	/** As rs_track_source_read(); fill `err` on failure. */
	enum rs_status (*read)(void *impl, struct rs_marker_sample *out_sample, int timeout_ms,
	                       struct rs_error *err);
	/** Reopen the device; NULL: reopening unsupported (RS_ERR_UNSUPPORTED). */
	enum rs_status (*reopen)(void *impl, struct rs_error *err);
	/** Parser counters; NULL: none. */
	void (*get_proto_stats)(const void *impl, struct rs_proto_stats *out_stats);
	/** Release everything `impl` holds, including `impl` itself. */
	void (*destroy)(void *impl);
};

/**
 * Wrap an implementation into a source. On success the source owns `impl` (ops->destroy
 * runs in rs_track_source_destroy()); on failure ops->destroy(impl) has already run.
 * `ops` must outlive the source (use a static const table).
 */
enum rs_status rs_track_source_create(const struct rs_track_source_ops *ops, void *impl,
                                      struct rs_track_source **out_source, struct rs_error *err);

/** A byte transport (serial line, HID reports, USB transfers) for rs_track_stream_create(). */
struct rs_track_transport {
	/**
	 * Wait up to `timeout_ms` (< 0: forever) and read at most `cap` bytes into `buf`.
	 * RS_OK with *out_n > 0, RS_TIMEOUT, RS_END, RS_ERR_DISCONNECTED or another error.
	 */
	enum rs_status (*read)(void *impl, uint8_t *buf, size_t cap, int timeout_ms, size_t *out_n,
	                       struct rs_error *err);
	/** Close (if still open) and open the device again; NULL: unsupported. */
	enum rs_status (*reopen)(void *impl, struct rs_error *err);
	/** Close the device and free `impl`. */
	void (*destroy)(void *impl);
};

/**
 * A source that reads bytes from `transport`, parses protocol frames and stamps host
 * receive times. Ownership of `impl` as in rs_track_source_create().
 */
enum rs_status rs_track_stream_create(const struct rs_track_transport *transport, void *impl,
                                      struct rs_track_source **out_source, struct rs_error *err);

/** rs_now_ms() in seconds: the host clock of host_time_s. */
double rs_track_now_s(void);

/**
 * Parse the "VID:PID" that starts a device URI's rest ("046d:c52b", "046d:c52b:SERIAL"):
 * two hex numbers of 1 to 4 digits. *out_tail points at what follows the PID (a ':' or
 * the terminating NUL). Returns RS_ERR_PARSE and leaves the outputs unset when the text is
 * not of that form.
 */
enum rs_status rs_track_parse_vid_pid(const char *text, uint16_t *out_vid, uint16_t *out_pid,
                                      const char **out_tail, struct rs_error *err);

/* ---- Replay files ---------------------------------------------------------------------- */

/** Options of a replay source; zero = defaults. */
struct rs_track_replay_desc {
	/** Nonzero: pace samples by their recorded host times (read() may time out);
	 *  0 (default): deliver as fast as read() is called, host times as recorded. */
	int realtime;
};

/**
 * Open a replay file: either a recording (docs/protocol.md, "Replay files") or a raw dump
 * of protocol frames (host times then equal device times). RS_ERR_NOT_FOUND / RS_ERR_IO /
 * RS_ERR_PARSE with a message in `err`; RS_ERR_BAD_DATA for a regular file that is neither
 * (no header and no frame in its first MiB: not a recording). At the end of the file,
 * reads return RS_END.
 */
enum rs_status rs_track_replay_open(const char *path, const struct rs_track_replay_desc *desc,
                                    struct rs_track_source **out_source, struct rs_error *err);

/** Writes samples (as protocol frames with their host times) to a replay file. */
struct rs_track_recorder;

/**
 * Start a recording for `path`: samples go to a temporary file `path.tmp-XXXXXX` next to
 * it, which rs_track_recorder_destroy() renames to `path` (so a failed or interrupted run
 * never leaves a partial file under that name). RS_ERR_IO when it cannot be created (a
 * directory, no such folder, no permission). Caller destroys the recorder.
 */
enum rs_status rs_track_recorder_create(const char *path, struct rs_track_recorder **out,
                                        struct rs_error *err);

/** Append one sample. RS_ERR_BAD_DATA for unencodable samples (nothing written), RS_ERR_IO
 *  when the write fails (the recording is then dropped at destroy). */
enum rs_status rs_track_recorder_write(struct rs_track_recorder *rec,
                                       const struct rs_marker_sample *sample, struct rs_error *err);

/**
 * Finish: flush, close and rename the file to its name. After any failed write or flush
 * the temporary file is removed instead, an existing file of that name is left as it
 * was, and RS_ERR_IO is returned. `*rec` NULL allowed; set to NULL.
 */
enum rs_status rs_track_recorder_destroy(struct rs_track_recorder **rec, struct rs_error *err);

/* ---- Simulator source ------------------------------------------------------------------ */

/** Options of a simulator source besides the simulation itself; zero = defaults. */
struct rs_track_sim_source_desc {
	struct rs_sim_desc sim; /**< the simulation (rs_sim.h) */
	/** Nonzero: deliver samples at their simulated times against the host clock;
	 *  0 (default): as fast as read() is called, host_time_s = simulated time. */
	int realtime;
};

/**
 * A source fed by the simulator. Samples go through rs_proto_encode() and the parser,
 * so they carry the same micrometre quantisation as a real device's.
 */
enum rs_status rs_track_sim_open(const struct rs_track_sim_source_desc *desc,
                                 struct rs_track_source **out_source, struct rs_error *err);

/**
 * Parse the part after "sim:" (`key=value` pairs joined by '&') into `out_desc` (zeroed
 * first): every key of rs_sim_parse_params() plus realtime=0|1. The script text is copied
 * into `script_buf` (capacity `script_cap`), which must outlive `out_desc`. RS_ERR_PARSE
 * with a message naming the bad key or value.
 */
enum rs_status rs_track_sim_parse_params(const char *params,
                                         struct rs_track_sim_source_desc *out_desc,
                                         char *script_buf, size_t script_cap, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
