/*
 * libFuzzer harness for the tracker protocol parser (rs_proto.h). Byte 0 picks the mode:
 * even = the rest is a raw byte stream; odd = the rest is a little program that builds a
 * stream of valid, corrupted and random frames (so the fuzzer reaches the accept paths
 * without guessing CRCs). Either way the stream is fed in fuzz-chosen chunk sizes and the
 * parser's invariants are checked; ASan/UBSan catch any read past a buffer.
 * Build and run: tests/fuzz.sh SECONDS [BUILD_DIR].
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_proto.h"

#define CHECK(c)                                                                                   \
	do {                                                                                       \
		if (!(c))                                                                          \
			abort();                                                                   \
	} while (0)

static uint8_t stream[1 << 14];

/* Builds a stream from the op program; returns its length. */
static size_t build(const uint8_t *p, size_t n)
{
	size_t len = 0, i = 0;
	uint32_t seq = 0;
	while (i < n && len + 2 * RS_PROTO_FRAME_SIZE < sizeof stream) {
		uint8_t op = p[i++];
		struct rs_marker_sample s = {.marker_count = RS_TRACK_MARKERS};
		switch (op % 4) {
		case 0: /* next frame in sequence */
		case 1: /* frame with a fuzz-chosen sequence step, corrupted at one byte */
			seq += op % 4 == 0 ? 1 : (uint32_t)(int8_t)(i < n ? p[i++] : 0);
			s.sequence = seq;
			s.device_time_us = seq * 1000ull;
			for (int m = 0; m < RS_TRACK_MARKERS; m++) {
				s.markers[m].id = (uint32_t)m;
				s.markers[m].flags = RS_MARKER_VALID;
				s.markers[m].position[m] = (op >> 2) * 1e-3;
			}
			CHECK(rs_proto_encode(&s, stream + len, NULL) == RS_OK);
			if (op % 4 == 0 && (op & 0x80) && i + 4 <= n) {
				/* A valid frame with a fuzz-chosen int32 coordinate (marker 0 x),
				 * so the whole coordinate range reaches the re-encode check. */
				memcpy(stream + len + 18, p + i, 4);
				i += 4;
				uint32_t crc =
				    rs_proto_crc32(stream + len, RS_PROTO_FRAME_SIZE - 4);
				for (int b = 0; b < 4; b++)
					stream[len + RS_PROTO_FRAME_SIZE - 4 + b] =
					    (uint8_t)(crc >> (8 * b));
			}
			if (op % 4 == 1 && i + 1 < n) {
				stream[len + p[i] % RS_PROTO_FRAME_SIZE] ^= p[i + 1];
				i += 2;
			}
			len += RS_PROTO_FRAME_SIZE;
			break;
		case 2: { /* raw bytes */
			size_t k = i < n ? p[i++] % 80 : 0;
			for (; k > 0 && i < n; k--)
				stream[len++] = p[i++];
			break;
		}
		case 3: /* a truncated frame */
			s.sequence = ++seq;
			CHECK(rs_proto_encode(&s, stream + len, NULL) == RS_OK);
			len += (op >> 2) % RS_PROTO_FRAME_SIZE;
			break;
		}
	}
	return len;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	const uint8_t *bytes = data + 2;
	size_t len = size - 2;
	if (data[0] & 1) {
		len = build(bytes, len);
		bytes = stream;
	}
	size_t chunk = data[1] ? data[1] : 1;

	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	uint64_t frames = 0;
	size_t off = 0;
	while (off < len) {
		size_t n = len - off < chunk ? len - off : chunk;
		/* Feed a private copy of exactly n bytes so ASan flags any over-read. */
		uint8_t *piece = malloc(n);
		CHECK(piece);
		memcpy(piece, bytes + off, n);
		const uint8_t *d = piece;
		size_t left = n;
		struct rs_marker_sample s;
		while (rs_proto_parser_feed(&p, &d, &left, &s)) {
			frames++;
			CHECK(s.marker_count == RS_TRACK_MARKERS);
			for (int m = 0; m < RS_TRACK_MARKERS; m++)
				for (int a = 0; a < 3; a++)
					CHECK(isfinite(s.markers[m].position[a]) &&
					      fabs(s.markers[m].position[a]) <= 2147.483648);
			/* Whatever was accepted must re-encode to a frame that parses the same
			 * (docs/protocol.md: every accepted frame encodes again). */
			uint8_t f[RS_PROTO_FRAME_SIZE];
			CHECK(rs_proto_encode(&s, f, NULL) == RS_OK);
			struct rs_proto_parser q;
			rs_proto_parser_init(&q);
			const uint8_t *fd = f;
			size_t fn = sizeof f;
			struct rs_marker_sample t;
			CHECK(rs_proto_parser_feed(&q, &fd, &fn, &t) == 1);
			CHECK(t.sequence == s.sequence && t.device_time_us == s.device_time_us);
		}
		CHECK(left == 0 && d == piece + n);
		free(piece);
		off += n;
	}
	const struct rs_proto_stats *st = rs_proto_parser_stats(&p);
	CHECK(st->frames == frames);
	CHECK(frames <= len / RS_PROTO_FRAME_SIZE);
	CHECK(st->garbage_bytes <= len);
	return 0;
}
