/*
 * libFuzzer harness for the remote rendering protocol parser (rs_stream.h). Byte 0 picks
 * the chunk-size seed and the parser's buffer size; the rest is the byte stream, fed in
 * fuzz-chosen chunks. Invariants: the parser never reads past what it is given (ASan),
 * never keeps more than its buffer, every accepted message encodes again and parses back
 * to the same message, and every call either returns a message, a counted fault, or
 * consumes all input.
 * Build and run: RS_FUZZ_TARGET=stream tests/fuzz.sh SECONDS [BUILD_DIR].
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_stream.h"

#define CHECK(c)                                                                                   \
	do {                                                                                       \
		if (!(c))                                                                          \
			abort();                                                                   \
	} while (0)

static uint8_t pbuf[1 << 16], enc[1 << 16], pbuf2[1 << 16];

static void check_round_trip(const struct rs_stream_msg *m)
{
	size_t n = 0;
	CHECK(rs_stream_encode(m, enc, sizeof enc, &n, NULL) == RS_OK);
	struct rs_stream_parser p;
	rs_stream_parser_init(&p, pbuf2, sizeof pbuf2);
	const uint8_t *d = enc;
	size_t len = n;
	struct rs_stream_msg again;
	CHECK(rs_stream_parser_feed(&p, &d, &len, &again, NULL) == RS_OK && len == 0);
	CHECK(again.type == m->type);
	if (m->type == RS_STREAM_FRAME) {
		CHECK(again.u.frame.size == m->u.frame.size);
		CHECK(memcmp(again.u.frame.data, m->u.frame.data, m->u.frame.size) == 0);
	} else {
		CHECK(memcmp(&again.u, &m->u, sizeof m->u) == 0);
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	uint8_t ctl = data[0];
	size_t cap = ctl & 1 ? 256 : sizeof pbuf; /* small: oversized paths; large: frames */
	struct rs_stream_parser p;
	rs_stream_parser_init(&p, pbuf, cap);
	const uint8_t *d = data + 1;
	size_t left = size - 1, chunk = (size_t)(ctl >> 1) + 1;
	uint64_t results = 0;
	while (left > 0) {
		size_t n = left < chunk ? left : chunk, before = n;
		const uint8_t *c = d;
		for (;;) {
			struct rs_stream_msg m;
			enum rs_status st = rs_stream_parser_feed(&p, &c, &n, &m, NULL);
			CHECK(n <= before && p.len <= p.cap);
			if (st == RS_END) {
				CHECK(n == 0);
				break;
			}
			++results;
			if (st == RS_OK)
				check_round_trip(&m);
		}
		d += before;
		left -= before;
	}
	const struct rs_stream_faults *f = rs_stream_parser_faults(&p);
	CHECK(f->messages + f->bad_version + f->unknown_type + f->oversized + f->bad_length +
	          f->bad_value ==
	      results);
	return 0;
}
