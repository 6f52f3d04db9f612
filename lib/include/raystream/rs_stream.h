/**
 * @file rs_stream.h
 * The remote rendering protocol (module rs_stream): versioned, length-prefixed messages
 * between the render server and its viewers over TCP, an encoder and an incremental,
 * allocation-free parser with counted faults. The wire format is docs/stream-protocol.md
 * (enough to write a viewer in another language). Every size is bounded.
 */
#ifndef RS_STREAM_H
#define RS_STREAM_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Protocol version this library speaks. */
#define RS_STREAM_VERSION 1u
/** Bytes of the message header: 'R' 'S' version type length(u32). */
#define RS_STREAM_HEADER_SIZE 8u
#define RS_STREAM_MAX_TOKEN 64u  /**< shared token bytes */
#define RS_STREAM_MAX_SCENE 128u /**< scene name bytes */
#define RS_STREAM_MAX_TEXT 200u  /**< bye reason text bytes */
#define RS_STREAM_MAX_SIDE 4096u /**< image side */
/** Fixed part of a frame message's payload (before the image bytes). */
#define RS_STREAM_FRAME_FIXED 32u
/** Largest message payload a viewer-to-server message can have (a hello). */
#define RS_STREAM_MAX_CLIENT_PAYLOAD (8u + RS_STREAM_MAX_TOKEN + RS_STREAM_MAX_SCENE)

enum rs_stream_type {
	RS_STREAM_HELLO = 1,   /**< viewer -> server: size, quality, token, scene */
	RS_STREAM_WELCOME = 2, /**< server -> viewer: accepted, effective settings */
	RS_STREAM_POSE = 3,    /**< viewer -> server: a camera with id and time */
	RS_STREAM_FRAME = 4,   /**< server -> viewer: an encoded image and its pose */
	RS_STREAM_STATS = 5,   /**< either way: what the sender measured */
	RS_STREAM_BYE = 6,     /**< either way: closing, with a reason */
};

enum rs_stream_encoding {
	RS_STREAM_ENC_JPEG = 1,  /**< baseline JPEG (4:2:0 or 4:4:4), RGB */
	RS_STREAM_ENC_RGBA8 = 2, /**< raw rows top first, 4 bytes per pixel */
};

/** Bye reasons. */
enum rs_stream_bye_reason {
	RS_STREAM_BYE_NORMAL = 0,
	RS_STREAM_BYE_PROTOCOL = 1, /**< malformed, oversized or unexpected message */
	RS_STREAM_BYE_TOKEN = 2,    /**< wrong or missing token */
	RS_STREAM_BYE_SCENE = 3,    /**< scene or size the server cannot serve */
	RS_STREAM_BYE_TIMEOUT = 4,  /**< no complete message in time (slow drip) */
	RS_STREAM_BYE_SHUTDOWN = 5, /**< the server is stopping */
	RS_STREAM_BYE_OVERLOAD = 6, /**< too many viewers */
	RS_STREAM_BYE_CAMERA = 7,   /**< a POSE whose camera cannot be rendered (degenerate) */
};

/** Pose flags. */
#define RS_STREAM_POSE_STALE 1u /**< the viewer's camera is not from a fresh pose */
/** The viewer acknowledges frames: after each FRAME it sends a STATS whose `frames` counts
 *  the frames received, and the server keeps one unacknowledged frame on the way. */
#define RS_STREAM_POSE_ACKS 2u
/** The viewer wants still-pose refinement: a POSE with the camera of the one before is
 *  rendered at the next sub-pixel sample and averaged (FRAME.samples counts them). */
#define RS_STREAM_POSE_REFINE 4u

struct rs_stream_hello {
	uint16_t width, height;              /**< requested image size, 1..RS_STREAM_MAX_SIDE */
	uint8_t quality;                     /**< JPEG quality 1..100; 0: the server's */
	char token[RS_STREAM_MAX_TOKEN + 1]; /**< printable ASCII, NUL-terminated, may be "" */
	char scene[RS_STREAM_MAX_SCENE + 1]; /**< printable ASCII; "": the server's scene */
};

struct rs_stream_welcome {
	uint32_t viewer_id;
	uint16_t width, height;
	uint8_t quality, encoding;
};

/** A camera as rs_camera has it (scene units): what the server renders from. */
struct rs_stream_pose {
	uint32_t pose_id;
	uint32_t flags;   /**< RS_STREAM_POSE_* */
	uint64_t time_us; /**< the viewer's clock when the pose was sampled; echoed in frames */
	double eye[3], target[3], up[3];
	double fov_y_deg; /**< 0 < fov < 180 */
	double shift[2];
};

struct rs_stream_frame {
	uint32_t frame_id; /**< per viewer, +1 per frame sent (gaps: frames dropped) */
	uint32_t pose_id;
	uint64_t pose_time_us;
	uint16_t width, height;
	uint8_t encoding; /**< enum rs_stream_encoding */
	/** Sub-pixel samples averaged in this image (still-pose refinement); 0 from a server
	 *  that predates it, meaning 1. Bytes 22-23 of the fixed part, which were zero. */
	uint16_t samples;
	uint32_t render_us;  /**< server time rendering */
	uint32_t encode_us;  /**< server time encoding */
	const uint8_t *data; /**< image bytes (parser: points into its buffer) */
	uint32_t size;
};

struct rs_stream_stats {
	uint32_t frames, dropped;
	uint64_t bytes;
	float fps, latency_median_ms, latency_p99_ms, link_mbps;
};

struct rs_stream_bye {
	uint32_t reason; /**< enum rs_stream_bye_reason */
	char text[RS_STREAM_MAX_TEXT + 1];
};

/** One message; the member named by `type` is valid. */
struct rs_stream_msg {
	enum rs_stream_type type;
	union {
		struct rs_stream_hello hello;
		struct rs_stream_welcome welcome;
		struct rs_stream_pose pose;
		struct rs_stream_frame frame;
		struct rs_stream_stats stats;
		struct rs_stream_bye bye;
	} u;
};

/** Fault and traffic counters; every rejected byte or message lands in exactly one. */
struct rs_stream_faults {
	uint64_t messages;      /**< accepted and returned */
	uint64_t garbage_bytes; /**< dropped while looking for 'R' 'S' */
	uint64_t bad_version;   /**< header with a version this parser does not know */
	uint64_t unknown_type;  /**< header with a type this version does not define */
	uint64_t oversized;     /**< length above the type's bound or the parser's buffer */
	uint64_t bad_length;    /**< length that does not fit the type's layout */
	uint64_t bad_value;     /**< well-framed message with an out-of-range field */
};

/** Incremental parser over a caller-owned buffer. Treat the fields as private. */
struct rs_stream_parser {
	uint8_t *buf;
	size_t cap, len;
	struct rs_stream_faults faults;
};

/** Buffer bytes a parser needs to accept frames of up to `max_image` image bytes. */
size_t rs_stream_parser_bound(size_t max_image);

/**
 * Start a parser over `buf` (`cap` bytes, caller-owned, outliving the parser). Messages
 * longer than `cap` count as oversized. A server's parser for viewers needs only
 * RS_STREAM_HEADER_SIZE + RS_STREAM_MAX_CLIENT_PAYLOAD bytes.
 */
void rs_stream_parser_init(struct rs_stream_parser *parser, uint8_t *buf, size_t cap);

/**
 * Consume bytes from `*data` (advancing it and decreasing `*len`) until one message is
 * complete or a fault is found. Returns RS_OK with `out_msg` filled (a frame's data points
 * into the parser's buffer, valid until the next call); RS_END when every byte was
 * consumed without completing a message; or, with a counted fault and a one-line message
 * in `err`: RS_ERR_UNSUPPORTED (version), RS_ERR_PARSE (type, length), RS_ERR_LIMIT
 * (oversized), RS_ERR_BAD_DATA (field value). After a header fault the parser drops the
 * two magic bytes and hunts for the next one; after a body fault it skips that message;
 * so calling again continues the stream (a server simply disconnects instead).
 */
enum rs_status rs_stream_parser_feed(struct rs_stream_parser *parser, const uint8_t **data,
                                     size_t *len, struct rs_stream_msg *out_msg,
                                     struct rs_error *err);

/** Counters since rs_stream_parser_init(). */
const struct rs_stream_faults *rs_stream_parser_faults(const struct rs_stream_parser *parser);

/** Sum of the fault counters (garbage bytes count once each). */
uint64_t rs_stream_faults_total(const struct rs_stream_faults *faults);

/** Bytes rs_stream_encode() writes for `msg`. */
size_t rs_stream_encoded_size(const struct rs_stream_msg *msg);

/**
 * Encode `msg` into `out` (`cap` bytes, caller-owned); *out_size gets the byte count.
 * Refuses (RS_ERR_BAD_DATA, nothing counted as written) what the parser would refuse:
 * out-of-range sizes, non-finite camera values, non-printable token/scene/text, a raw
 * frame whose size is not width * height * 4. RS_ERR_LIMIT when `cap` is too small.
 */
enum rs_status rs_stream_encode(const struct rs_stream_msg *msg, uint8_t *out, size_t cap,
                                size_t *out_size, struct rs_error *err);

/* ---- Link emulation ------------------------------------------------------------------ */

/** A token bucket: what a bandwidth-limited link lets through (the latency part is a
 * per-message ready time kept by the sender). Zero-initialised means unlimited. */
struct rs_stream_link_desc {
	double rate_bits_per_s; /**< 0: unlimited */
	double latency_s;       /**< one-way delay added to every message (sender side) */
	size_t burst_bytes;     /**< bucket size; 0: 10 ms of rate, at least 1500 bytes */
};

/** Token bucket state; caller-owned, treat the fields as private. */
struct rs_stream_link {
	struct rs_stream_link_desc desc;
	double tokens, last_s;
	int started;
};

/** Start a link (full bucket at the first call). RS_ERR_INVALID for negative or
 * non-finite rate or latency. */
enum rs_status rs_stream_link_init(struct rs_stream_link *link,
                                   const struct rs_stream_link_desc *desc, struct rs_error *err);

/** Bytes (<= want) the link lets through at `now_s` (monotonic seconds); the caller
 * sends at most that many and reports what it really sent with rs_stream_link_spend(). */
size_t rs_stream_link_allow(struct rs_stream_link *link, double now_s, size_t want);

/** Take `sent` bytes' worth of tokens. */
void rs_stream_link_spend(struct rs_stream_link *link, size_t sent);

/** Seconds from `now_s` until at least min(want, burst) bytes are allowed (0: now). */
double rs_stream_link_wait_s(struct rs_stream_link *link, double now_s, size_t want);

/** Constant name of a message type ("HELLO"); "UNKNOWN" otherwise. */
const char *rs_stream_type_name(uint32_t type);

#ifdef __cplusplus
}
#endif
#endif
