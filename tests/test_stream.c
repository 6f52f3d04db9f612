/* rs_stream: every message type round-trips; the parser survives garbage, truncation,
 * oversized, malformed and out-of-range input with the right counter, and resynchronises;
 * the encoder refuses what the parser would refuse; the documented example is byte-exact. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "raystream/rs_stream.h"
#include "contract.h"

static uint8_t pbuf[4096];
static uint8_t wire[8192];

static struct rs_stream_msg sample(enum rs_stream_type t)
{
	static const uint8_t image[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
	struct rs_stream_msg m;
	memset(&m, 0, sizeof m);
	m.type = t;
	switch (t) {
	case RS_STREAM_HELLO:
		m.u.hello = (struct rs_stream_hello){.width = 512, .height = 256, .quality = 85};
		strcpy(m.u.hello.token, "s3cret");
		strcpy(m.u.hello.scene, "cow1");
		break;
	case RS_STREAM_WELCOME:
		m.u.welcome = (struct rs_stream_welcome){7, 512, 256, 85, RS_STREAM_ENC_JPEG};
		break;
	case RS_STREAM_POSE:
		m.u.pose = (struct rs_stream_pose){.pose_id = 42,
		                                   .flags = RS_STREAM_POSE_STALE,
		                                   .time_us = 1234567890123ull,
		                                   .eye = {0.5, -1.25, 3},
		                                   .target = {0, 0, 0},
		                                   .up = {0, 1, 0},
		                                   .fov_y_deg = 9.46,
		                                   .shift = {-0.25, 0.125}};
		break;
	case RS_STREAM_FRAME:
		m.u.frame = (struct rs_stream_frame){.frame_id = 9,
		                                     .pose_id = 42,
		                                     .pose_time_us = 77,
		                                     .width = 2,
		                                     .height = 2,
		                                     .encoding = RS_STREAM_ENC_RGBA8,
		                                     .render_us = 1000,
		                                     .encode_us = 20,
		                                     .data = image,
		                                     .size = 16};
		break;
	case RS_STREAM_STATS:
		m.u.stats =
		    (struct rs_stream_stats){100, 3, 123456789ull, 29.5f, 12.25f, 30.5f, 24.0f};
		break;
	case RS_STREAM_BYE:
		m.u.bye.reason = RS_STREAM_BYE_TIMEOUT;
		strcpy(m.u.bye.text, "no pose for 5 s");
		break;
	}
	return m;
}

static size_t encode(const struct rs_stream_msg *m, uint8_t *out)
{
	size_t n = 0;
	assert_int_equal(rs_stream_encode(m, out, 4096, &n, NULL), RS_OK);
	assert_int_equal(n, rs_stream_encoded_size(m));
	return n;
}

static void assert_same(const struct rs_stream_msg *a, const struct rs_stream_msg *b)
{
	assert_int_equal(a->type, b->type);
	if (a->type == RS_STREAM_FRAME) {
		struct rs_stream_frame fa = a->u.frame, fb = b->u.frame;
		assert_int_equal(fa.size, fb.size);
		assert_memory_equal(fa.data, fb.data, fa.size);
		fa.data = fb.data = NULL;
		assert_memory_equal(&fa, &fb, sizeof fa);
	} else {
		assert_memory_equal(&a->u, &b->u, sizeof a->u);
	}
}

static void test_round_trip_every_type_whole_and_bytewise(void **state)
{
	(void)state;
	for (int t = RS_STREAM_HELLO; t <= RS_STREAM_BYE; ++t) {
		struct rs_stream_msg m = sample((enum rs_stream_type)t), got;
		size_t n = encode(&m, wire);
		struct rs_stream_parser p;
		rs_stream_parser_init(&p, pbuf, sizeof pbuf);
		const uint8_t *d = wire;
		size_t len = n;
		assert_int_equal(rs_stream_parser_feed(&p, &d, &len, &got, NULL), RS_OK);
		assert_int_equal(len, 0);
		assert_same(&m, &got);
		/* one byte at a time: RS_END until the last */
		rs_stream_parser_init(&p, pbuf, sizeof pbuf);
		for (size_t i = 0; i < n; ++i) {
			const uint8_t *b = wire + i;
			size_t one = 1;
			enum rs_status st = rs_stream_parser_feed(&p, &b, &one, &got, NULL);
			assert_int_equal(st, i + 1 < n ? RS_END : RS_OK);
		}
		assert_same(&m, &got);
		assert_int_equal(rs_stream_faults_total(rs_stream_parser_faults(&p)), 0);
		assert_int_equal(rs_stream_parser_faults(&p)->messages, 1);
	}
}

/* Feed `bytes` then a valid pose; the first call must fail with `want`, the counter
 * selected by `field` must be 1 (garbage: `garbage` bytes), and the pose must follow. */
static void check_fault(const uint8_t *bytes, size_t n, enum rs_status want, size_t offset,
                        uint64_t garbage)
{
	struct rs_stream_msg pose = sample(RS_STREAM_POSE), got;
	memcpy(wire, bytes, n);
	size_t total = n + encode(&pose, wire + n);
	struct rs_stream_parser p;
	rs_stream_parser_init(&p, pbuf, 512);
	const uint8_t *d = wire;
	size_t len = total;
	struct rs_error err = {0};
	enum rs_status st = rs_stream_parser_feed(&p, &d, &len, &got, &err);
	if (want != RS_OK) {
		assert_int_equal(st, want);
		assert_true(strlen(err.message) > 0);
		st = rs_stream_parser_feed(&p, &d, &len, &got, NULL);
	}
	assert_int_equal(st, RS_OK);
	assert_same(&pose, &got);
	const struct rs_stream_faults *f = rs_stream_parser_faults(&p);
	if (offset != SIZE_MAX) {
		uint64_t v;
		memcpy(&v, (const uint8_t *)f + offset, sizeof v);
		assert_int_equal(v, 1);
	}
	assert_int_equal(f->garbage_bytes, garbage);
}

static void test_faults_are_counted_and_parser_resyncs(void **state)
{
	(void)state;
	const uint8_t junk[] = {0, 'R', 'x', 'S', 0xff, 'R', 'R'};
	check_fault(junk, sizeof junk, RS_OK, SIZE_MAX, sizeof junk);
	const uint8_t version[] = {'R', 'S', 9, RS_STREAM_POSE, 112, 0, 0, 0};
	check_fault(version, sizeof version, RS_ERR_UNSUPPORTED,
	            offsetof(struct rs_stream_faults, bad_version), 6);
	const uint8_t type[] = {'R', 'S', 1, 99, 0, 0, 0, 0};
	check_fault(type, sizeof type, RS_ERR_PARSE,
	            offsetof(struct rs_stream_faults, unknown_type), 6);
	/* a pose claiming 4 GiB: never buffered, never waited for */
	const uint8_t huge[] = {'R', 'S', 1, RS_STREAM_POSE, 0xff, 0xff, 0xff, 0xff};
	check_fault(huge, sizeof huge, RS_ERR_LIMIT, offsetof(struct rs_stream_faults, oversized),
	            6);
	/* a frame larger than this parser's 512-byte buffer */
	const uint8_t big[] = {'R', 'S', 1, RS_STREAM_FRAME, 0x00, 0x10, 0, 0};
	check_fault(big, sizeof big, RS_ERR_LIMIT, offsetof(struct rs_stream_faults, oversized), 6);
	/* a pose of 111 bytes: the layout does not fit, the message is skipped whole */
	uint8_t shortpose[8 + 111] = {'R', 'S', 1, RS_STREAM_POSE, 111, 0, 0, 0};
	check_fault(shortpose, sizeof shortpose, RS_ERR_PARSE,
	            offsetof(struct rs_stream_faults, bad_length), 0);
	/* a hello whose token length points past its end */
	const uint8_t hello[8 + 8] = {'R', 'S', 1, RS_STREAM_HELLO, 8, 0, 0, 0, 64, 0, 64, 0, 0,
	                              5,   0,   0};
	check_fault(hello, sizeof hello, RS_ERR_PARSE,
	            offsetof(struct rs_stream_faults, bad_length), 0);
}

static void test_bad_values_refused(void **state)
{
	(void)state;
	struct rs_stream_msg m = sample(RS_STREAM_POSE);
	size_t n = encode(&m, wire);
	double nan = NAN;
	memcpy(wire + 8 + 16, &nan, 8); /* eye x */
	check_fault(wire, n, RS_ERR_BAD_DATA, offsetof(struct rs_stream_faults, bad_value), 0);
	n = encode(&m, wire);
	double fov = 180.0;
	memcpy(wire + 8 + 16 + 9 * 8, &fov, 8);
	check_fault(wire, n, RS_ERR_BAD_DATA, offsetof(struct rs_stream_faults, bad_value), 0);
	m = sample(RS_STREAM_HELLO);
	n = encode(&m, wire);
	wire[8 + 8] = 0x07; /* a control character in the token */
	check_fault(wire, n, RS_ERR_BAD_DATA, offsetof(struct rs_stream_faults, bad_value), 0);
	n = encode(&m, wire);
	wire[8] = 0, wire[9] = 0; /* width 0 */
	check_fault(wire, n, RS_ERR_BAD_DATA, offsetof(struct rs_stream_faults, bad_value), 0);
	m = sample(RS_STREAM_FRAME);
	n = encode(&m, wire);
	wire[8 + 16] = 3; /* 3x2 raw frame with 16 bytes */
	check_fault(wire, n, RS_ERR_BAD_DATA, offsetof(struct rs_stream_faults, bad_value), 0);
}

static void test_encoder_refuses_what_parser_refuses(void **state)
{
	(void)state;
	size_t n = 99;
	struct rs_stream_msg m = sample(RS_STREAM_POSE);
	m.u.pose.up[1] = INFINITY;
	assert_int_equal(rs_stream_encode(&m, wire, sizeof wire, &n, NULL), RS_ERR_BAD_DATA);
	assert_int_equal(n, 0);
	m = sample(RS_STREAM_FRAME);
	m.u.frame.size = 15;
	assert_int_equal(rs_stream_encode(&m, wire, sizeof wire, &n, NULL), RS_ERR_BAD_DATA);
	m = sample(RS_STREAM_HELLO);
	m.u.hello.scene[0] = '\n';
	assert_int_equal(rs_stream_encode(&m, wire, sizeof wire, &n, NULL), RS_ERR_BAD_DATA);
	m = sample(RS_STREAM_BYE);
	assert_int_equal(rs_stream_encode(&m, wire, 10, &n, NULL), RS_ERR_LIMIT);
	m.type = (enum rs_stream_type)0;
	assert_int_equal(rs_stream_encode(&m, wire, sizeof wire, &n, NULL), RS_ERR_BAD_DATA);
	assert_true(rs_stream_parser_bound(1000) >=
	            RS_STREAM_HEADER_SIZE + RS_STREAM_FRAME_FIXED + 1000);
	assert_true(rs_stream_parser_bound(0) >=
	            RS_STREAM_HEADER_SIZE + RS_STREAM_MAX_CLIENT_PAYLOAD);
	assert_string_equal(rs_stream_type_name(RS_STREAM_FRAME), "FRAME");
	assert_string_equal(rs_stream_type_name(77), "UNKNOWN");
}

/* The example of docs/stream-protocol.md, byte for byte. */
static void test_documented_example(void **state)
{
	(void)state;
	struct rs_stream_msg m;
	memset(&m, 0, sizeof m);
	m.type = RS_STREAM_HELLO;
	m.u.hello.width = 512;
	m.u.hello.height = 512;
	m.u.hello.quality = 85;
	strcpy(m.u.hello.token, "abc");
	strcpy(m.u.hello.scene, "box");
	const uint8_t want[] = {0x52, 0x53, 0x01, 0x01, 0x0e, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00,
	                        0x02, 0x55, 0x03, 0x03, 0x00, 0x61, 0x62, 0x63, 0x62, 0x6f, 0x78};
	size_t n = encode(&m, wire);
	assert_int_equal(n, sizeof want);
	assert_memory_equal(wire, want, sizeof want);
}

/* Truncation: a message cut anywhere waits (RS_END) and completes with the rest. */
static void test_truncated_then_completed(void **state)
{
	(void)state;
	struct rs_stream_msg m = sample(RS_STREAM_FRAME), got;
	size_t n = encode(&m, wire);
	for (size_t cut = 0; cut < n; ++cut) {
		struct rs_stream_parser p;
		rs_stream_parser_init(&p, pbuf, sizeof pbuf);
		const uint8_t *d = wire;
		size_t len = cut;
		assert_int_equal(rs_stream_parser_feed(&p, &d, &len, &got, NULL), RS_END);
		len = n - cut;
		assert_int_equal(rs_stream_parser_feed(&p, &d, &len, &got, NULL), RS_OK);
		assert_same(&m, &got);
	}
}

/* NULL handles and buffers are contract violations, not statuses. */
static void test_contracts(void **state)
{
	(void)state;
	struct rs_stream_parser p;
	struct rs_stream_msg m = sample(RS_STREAM_BYE);
	const uint8_t *d = wire;
	size_t len = 0, n = 0;
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_parser_init(&p, NULL, 100));
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_parser_init(&p, pbuf, 4)); /* < a header */
	rs_stream_parser_init(&p, pbuf, sizeof pbuf);
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_parser_feed(NULL, &d, &len, &m, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_parser_feed(&p, &d, &len, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_encode(NULL, wire, sizeof wire, &n, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_encode(&m, wire, sizeof wire, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_stream_link_init(NULL, NULL, NULL));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_round_trip_every_type_whole_and_bytewise),
	    cmocka_unit_test(test_faults_are_counted_and_parser_resyncs),
	    cmocka_unit_test(test_bad_values_refused),
	    cmocka_unit_test(test_encoder_refuses_what_parser_refuses),
	    cmocka_unit_test(test_documented_example),
	    cmocka_unit_test(test_truncated_then_completed),
	    cmocka_unit_test(test_contracts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
