/**
 * @file rs_proto.h
 * The tracker wire protocol (module rs_track): one fixed-size frame per sample, the same
 * bytes on a serial line and in a 64-byte HID report. docs/protocol.md gives the layout
 * byte by byte. The parser is incremental (feed any number of bytes, get whole frames),
 * lives in a caller-owned struct, never allocates and never reads past what it is given.
 */
#ifndef RS_PROTO_H
#define RS_PROTO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RS_PROTO_SYNC0 0xA5u         /**< first byte of every frame */
#define RS_PROTO_SYNC1 0x5Au         /**< second byte of every frame */
#define RS_PROTO_VERSION 1u          /**< the only version this parser accepts */
#define RS_PROTO_FRAME_SIZE 62u      /**< bytes in a version-1 frame, sync and CRC included */
#define RS_PROTO_HEADER_SIZE 4u      /**< sync word, version, length */
#define RS_PROTO_HID_REPORT_SIZE 64u /**< a frame plus zero padding in one HID report */
/** Sequence numbers this far behind (or equal to) the last accepted one are rejected;
 *  a jump further back is taken as a device restart. */
#define RS_PROTO_SEQ_WINDOW 1024u
/** A run of this many valid frames, each one after the previous but all behind the last
 *  accepted one, is a device that restarted its count without a reconnect (an MCU reset
 *  behind a USB-serial adapter): the last of them is accepted as a restart. */
#define RS_PROTO_RESTART_RUN 4u
/** |coordinate| up to this always fits a frame (int32 micrometres; the exact range is
 *  -2147.483648 .. +2147.483647 m, and every coordinate the parser returns lies in it). */
#define RS_PROTO_MAX_COORD_M 2147.0

/** Fault and traffic counters; every rejected byte or frame lands in exactly one. */
struct rs_proto_stats {
	uint64_t frames;        /**< frames accepted and returned */
	uint64_t garbage_bytes; /**< bytes dropped while hunting for a sync word */
	uint64_t crc_errors;    /**< header fine, CRC-32 mismatch */
	uint64_t short_frames;  /**< length field below the version's frame size */
	uint64_t long_frames;   /**< length field above the version's frame size */
	uint64_t bad_version;   /**< version byte this parser does not know */
	uint64_t duplicates;    /**< valid frame whose sequence equals the last accepted one */
	uint64_t out_of_order;  /**< valid frame up to RS_PROTO_SEQ_WINDOW-1 behind the last */
	uint64_t lost_frames;   /**< sum of forward sequence gaps (informational, not a fault) */
	uint64_t restarts;      /**< sequence jumped back beyond the window: accepted as restart */
};

/** Incremental parser state. Caller-owned; treat the fields as private. */
struct rs_proto_parser {
	uint8_t buf[RS_PROTO_HID_REPORT_SIZE];
	size_t len;
	uint32_t last_sequence;
	int have_sequence;
	uint32_t run_sequence; /* last frame rejected as out of order */
	uint32_t run_length;   /* consecutive sequences among the rejected ones */
	struct rs_proto_stats stats;
};

/** Reset `parser` completely: empty buffer, no sequence history, zero counters. */
void rs_proto_parser_init(struct rs_proto_parser *parser);

/**
 * Forget buffered bytes and the sequence history (as after a device reconnect), but keep
 * the counters.
 */
void rs_proto_parser_reset(struct rs_proto_parser *parser);

/**
 * Consume bytes from `*data` (advancing `*data` and decreasing `*len`) until one frame is
 * complete. Returns true and fills `out_sample` (marker_count = 3, host_time_s = 0; the
 * caller stamps it) when a frame was accepted, false when all input was consumed first.
 * Call in a loop: `while (rs_proto_parser_feed(&p, &ptr, &n, &s)) use(&s);`.
 * Buffered bytes may complete a frame with `*len == 0`, so loop until it returns false.
 */
bool rs_proto_parser_feed(struct rs_proto_parser *parser, const uint8_t **data, size_t *len,
                          struct rs_marker_sample *out_sample);

/** Counters since rs_proto_parser_init(). */
const struct rs_proto_stats *rs_proto_parser_stats(const struct rs_proto_parser *parser);

/**
 * Encode `sample` into exactly RS_PROTO_FRAME_SIZE bytes at `out_frame` (caller-owned).
 * Positions are rounded to micrometres; markers beyond sample->marker_count are sent with
 * flags 0 (not valid). Marker ids must fit a byte. Returns RS_ERR_BAD_DATA (and writes
 * nothing) for NaN/Inf or a coordinate outside int32 micrometres (see
 * RS_PROTO_MAX_COORD_M) of a marker, or id > 255. Every sample the parser returns encodes.
 */
enum rs_status rs_proto_encode(const struct rs_marker_sample *sample, uint8_t *out_frame,
                               struct rs_error *err);

/** CRC-32 (ISO-HDLC, as zlib: reflected 0x04C11DB7, init and xorout 0xFFFFFFFF). */
uint32_t rs_proto_crc32(const uint8_t *data, size_t len);

/** Adds every counter of `b` to `acc`. */
void rs_proto_stats_add(struct rs_proto_stats *acc, const struct rs_proto_stats *b);

/** Sum of all fault counters (garbage bytes count once each; lost frames excluded). */
uint64_t rs_proto_stats_faults(const struct rs_proto_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
