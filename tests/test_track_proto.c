/* rs_track wire protocol: encoding, CRC, and every fault the parser must detect. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <math.h>

#include "raystream/rs_proto.h"

static struct rs_marker_sample make_sample(uint32_t seq)
{
	struct rs_marker_sample s;
	memset(&s, 0, sizeof s);
	s.sequence = seq;
	s.device_time_us = 1000000ull * 5000 + seq * 8333ull; /* beyond 32 bits on purpose */
	s.marker_count = RS_TRACK_MARKERS;
	for (uint32_t m = 0; m < RS_TRACK_MARKERS; m++) {
		s.markers[m].id = m;
		s.markers[m].flags = RS_MARKER_VALID;
		s.markers[m].position[0] = 0.1 * m - 0.123456;
		s.markers[m].position[1] = -1.5 + 0.01 * (seq % 1000);
		s.markers[m].position[2] = 2.0 + 1e-6 * m;
	}
	return s;
}

static void frame_of(uint32_t seq, uint8_t *f)
{
	struct rs_marker_sample s = make_sample(seq);
	assert_int_equal(rs_proto_encode(&s, f, NULL), RS_OK);
}

/* Feeds `len` bytes; returns frames produced, their sequences in seqs[] (up to cap). */
static size_t feed_all(struct rs_proto_parser *p, const uint8_t *data, size_t len, uint32_t *seqs,
                       size_t cap)
{
	struct rs_marker_sample s;
	size_t n = 0;
	while (rs_proto_parser_feed(p, &data, &len, &s)) {
		if (seqs && n < cap)
			seqs[n] = s.sequence;
		n++;
	}
	return n;
}

static void crc32_matches_check_value(void **state)
{
	/* The catalogue check value of CRC-32/ISO-HDLC. */
	assert_int_equal(rs_proto_crc32((const uint8_t *)"123456789", 9), 0xCBF43926u);
}

static void encode_matches_documented_example(void **state)
{
	/* The example frame of docs/protocol.md, byte for byte. */
	static const uint8_t want[RS_PROTO_FRAME_SIZE] = {
	    0xa5, 0x5a, 0x01, 0x3e, 0x01, 0x00, 0x00, 0x00, 0x8d, 0x20, 0x00, 0x00, 0x00,
	    0x00, 0x00, 0x00, 0x00, 0x01, 0xa0, 0x86, 0x01, 0x00, 0x40, 0x0d, 0x03, 0x00,
	    0x60, 0xe3, 0x16, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
	    0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
	    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x34, 0xcf, 0x7c, 0x0e};
	struct rs_marker_sample s = {.sequence = 1, .device_time_us = 8333, .marker_count = 3};
	s.markers[0].flags = RS_MARKER_VALID;
	s.markers[0].position[0] = 0.1;
	s.markers[0].position[1] = 0.2;
	s.markers[0].position[2] = 1.5;
	s.markers[1].id = 1;
	s.markers[2].id = 2;
	uint8_t f[RS_PROTO_FRAME_SIZE];
	assert_int_equal(rs_proto_encode(&s, f, NULL), RS_OK);
	assert_memory_equal(f, want, sizeof want);
}

static void encode_parse_round_trip(void **state)
{
	struct rs_marker_sample in = make_sample(77), out;
	in.markers[2].flags = RS_MARKER_OCCLUDED | RS_MARKER_LOW_QUALITY;
	in.markers[1].id = 2;
	uint8_t f[RS_PROTO_FRAME_SIZE];
	assert_int_equal(rs_proto_encode(&in, f, NULL), RS_OK);
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	const uint8_t *d = f;
	size_t n = sizeof f;
	assert_int_equal(rs_proto_parser_feed(&p, &d, &n, &out), 1);
	assert_int_equal(n, 0);
	assert_int_equal(out.sequence, 77);
	assert_true(out.device_time_us == in.device_time_us);
	assert_int_equal(out.marker_count, 3);
	for (int m = 0; m < 3; m++) {
		assert_int_equal(out.markers[m].id, in.markers[m].id);
		assert_int_equal(out.markers[m].flags, in.markers[m].flags);
		/* Quantised to whole micrometres: rounding error at most 0.5 um. */
		for (int a = 0; a < 3; a++)
			assert_true(fabs(out.markers[m].position[a] - in.markers[m].position[a]) <=
			            0.5e-6 + 1e-12);
	}
	assert_int_equal(rs_proto_parser_stats(&p)->frames, 1);
	assert_int_equal(rs_proto_stats_faults(rs_proto_parser_stats(&p)), 0);
}

static void encode_rejects_unencodable(void **state)
{
	uint8_t f[RS_PROTO_FRAME_SIZE];
	struct rs_error err;
	struct rs_marker_sample s = make_sample(1);
	s.markers[0].position[1] = NAN;
	assert_int_equal(rs_proto_encode(&s, f, &err), RS_ERR_BAD_DATA);
	s = make_sample(1);
	s.markers[2].position[0] = INFINITY;
	assert_int_equal(rs_proto_encode(&s, f, &err), RS_ERR_BAD_DATA);
	s = make_sample(1);
	s.markers[1].position[2] = 1e4; /* 10 km does not fit int32 micrometres */
	assert_int_equal(rs_proto_encode(&s, f, &err), RS_ERR_BAD_DATA);
	s = make_sample(1);
	s.markers[0].id = 300;
	assert_int_equal(rs_proto_encode(&s, f, &err), RS_ERR_BAD_DATA);
}

/* A device may send any int32 coordinate, e.g. INT32_MIN as a "no data" sentinel under
 * flags 0. Whatever the parser accepts must encode again byte for byte, or recording a
 * real device (--record) would fail on valid input. */
static void extreme_coordinates_round_trip(void **state)
{
	uint8_t f[RS_PROTO_FRAME_SIZE], g[RS_PROTO_FRAME_SIZE];
	frame_of(4, f);
	static const uint8_t int32_min[4] = {0x00, 0x00, 0x00, 0x80};
	static const uint8_t int32_max[4] = {0xff, 0xff, 0xff, 0x7f};
	memcpy(f + 16 + 2, int32_min, 4);       /* marker 0 x */
	memcpy(f + 16 + 14 + 6, int32_max, 4);  /* marker 1 y */
	f[16 + 28 + 1] = 0;                     /* marker 2 not valid */
	memcpy(f + 16 + 28 + 10, int32_min, 4); /* ... with a sentinel z */
	uint32_t crc = rs_proto_crc32(f, RS_PROTO_FRAME_SIZE - 4);
	for (int i = 0; i < 4; i++)
		f[RS_PROTO_FRAME_SIZE - 4 + i] = (uint8_t)(crc >> (8 * i));
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	struct rs_marker_sample s;
	const uint8_t *d = f;
	size_t n = sizeof f;
	assert_int_equal(rs_proto_parser_feed(&p, &d, &n, &s), 1);
	assert_true(s.markers[0].position[0] == -2147.483648);
	assert_true(s.markers[1].position[1] == 2147.483647);
	assert_int_equal(rs_proto_encode(&s, g, NULL), RS_OK);
	assert_memory_equal(f, g, sizeof f);
	/* One micrometre beyond either end does not fit. */
	struct rs_error err;
	s.markers[0].position[0] = -2147.483649;
	assert_int_equal(rs_proto_encode(&s, g, &err), RS_ERR_BAD_DATA);
	s.markers[0].position[0] = 2147.483648;
	assert_int_equal(rs_proto_encode(&s, g, &err), RS_ERR_BAD_DATA);
}

static void missing_markers_are_sent_invalid(void **state)
{
	struct rs_marker_sample in = make_sample(3), out;
	in.marker_count = 1;
	uint8_t f[RS_PROTO_FRAME_SIZE];
	assert_int_equal(rs_proto_encode(&in, f, NULL), RS_OK);
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	const uint8_t *d = f;
	size_t n = sizeof f;
	assert_int_equal(rs_proto_parser_feed(&p, &d, &n, &out), 1);
	assert_int_equal(out.markers[0].flags, RS_MARKER_VALID);
	assert_int_equal(out.markers[1].flags, 0);
	assert_int_equal(out.markers[2].flags, 0);
}

static void garbage_is_counted_and_skipped(void **state)
{
	uint8_t buf[100 + RS_PROTO_FRAME_SIZE];
	for (int i = 0; i < 100; i++)
		buf[i] = (uint8_t)(i % 7); /* never a sync byte */
	frame_of(5, buf + 100);
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	uint32_t seq = 0;
	assert_int_equal(feed_all(&p, buf, sizeof buf, &seq, 1), 1);
	assert_int_equal(seq, 5);
	assert_int_equal(rs_proto_parser_stats(&p)->garbage_bytes, 100);
}

static void lone_sync_byte_is_garbage(void **state)
{
	uint8_t buf[3 + RS_PROTO_FRAME_SIZE] = {RS_PROTO_SYNC0, 0x00, RS_PROTO_SYNC0};
	frame_of(9, buf + 3);
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_all(&p, buf, sizeof buf, NULL, 0), 1);
	assert_int_equal(rs_proto_parser_stats(&p)->garbage_bytes, 3);
}

/* A corrupted copy of frame `seq` followed by a good frame seq+1: exactly one fault of
 * the expected kind, and the good frame still comes through. */
static const struct rs_proto_stats *one_fault(struct rs_proto_parser *p, int byte, uint8_t value)
{
	uint8_t buf[2 * RS_PROTO_FRAME_SIZE];
	frame_of(1, buf);
	buf[byte] = value;
	frame_of(2, buf + RS_PROTO_FRAME_SIZE);
	rs_proto_parser_init(p);
	uint32_t seq = 0;
	assert_int_equal(feed_all(p, buf, sizeof buf, &seq, 1), 1);
	assert_int_equal(seq, 2);
	return rs_proto_parser_stats(p);
}

static void bad_crc_is_counted(void **state)
{
	struct rs_proto_parser p;
	const struct rs_proto_stats *s = one_fault(&p, 20, 0xEE);
	assert_int_equal(s->crc_errors, 1);
	assert_int_equal(rs_proto_stats_faults(s) - s->garbage_bytes,
	                 1); /* the rest of the bad frame is garbage */
}

static void crc_field_corruption_is_counted(void **state)
{
	struct rs_proto_parser p;
	const struct rs_proto_stats *s = one_fault(&p, RS_PROTO_FRAME_SIZE - 1, 0x00);
	assert_int_equal(s->crc_errors, 1);
}

static void short_length_is_counted(void **state)
{
	struct rs_proto_parser p;
	const struct rs_proto_stats *s = one_fault(&p, 3, RS_PROTO_FRAME_SIZE - 1);
	assert_int_equal(s->short_frames, 1);
	assert_int_equal(rs_proto_stats_faults(s) - s->garbage_bytes,
	                 1); /* the rest of the bad frame is garbage */
}

static void long_length_is_counted(void **state)
{
	struct rs_proto_parser p;
	const struct rs_proto_stats *s = one_fault(&p, 3, 255);
	assert_int_equal(s->long_frames, 1);
	assert_int_equal(rs_proto_stats_faults(s) - s->garbage_bytes,
	                 1); /* the rest of the bad frame is garbage */
}

static void unknown_version_is_counted(void **state)
{
	struct rs_proto_parser p;
	const struct rs_proto_stats *s = one_fault(&p, 2, 2);
	assert_int_equal(s->bad_version, 1);
	assert_int_equal(rs_proto_stats_faults(s) - s->garbage_bytes,
	                 1); /* the rest of the bad frame is garbage */
}

static void truncated_frame_then_good_frame(void **state)
{
	/* A frame cut off after 30 bytes (device reset mid-frame) must not hide the next. */
	uint8_t buf[30 + RS_PROTO_FRAME_SIZE];
	uint8_t f[RS_PROTO_FRAME_SIZE];
	frame_of(1, f);
	memcpy(buf, f, 30);
	frame_of(2, buf + 30);
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	uint32_t seq = 0;
	assert_int_equal(feed_all(&p, buf, sizeof buf, &seq, 1), 1);
	assert_int_equal(seq, 2);
	assert_int_equal(rs_proto_parser_stats(&p)->crc_errors, 1);
}

static size_t feed_seqs(struct rs_proto_parser *p, const uint32_t *seqs, size_t n)
{
	size_t got = 0;
	for (size_t i = 0; i < n; i++) {
		uint8_t f[RS_PROTO_FRAME_SIZE];
		frame_of(seqs[i], f);
		got += feed_all(p, f, sizeof f, NULL, 0);
	}
	return got;
}

static void duplicate_sequence_is_rejected(void **state)
{
	const uint32_t seqs[] = {10, 11, 11, 12};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 4), 3);
	assert_int_equal(rs_proto_parser_stats(&p)->duplicates, 1);
}

static void backwards_sequence_is_rejected(void **state)
{
	const uint32_t seqs[] = {100, 101, 99, 101 - (RS_PROTO_SEQ_WINDOW - 1), 102};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 5), 3);
	assert_int_equal(rs_proto_parser_stats(&p)->out_of_order, 2);
}

static void jump_back_beyond_window_is_restart(void **state)
{
	const uint32_t seqs[] = {5000, 5000 - RS_PROTO_SEQ_WINDOW, 5000 - RS_PROTO_SEQ_WINDOW + 1};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 3), 3);
	assert_int_equal(rs_proto_parser_stats(&p)->restarts, 1);
	assert_int_equal(rs_proto_stats_faults(rs_proto_parser_stats(&p)), 0);
}

/* A device that restarts its count without a reconnect (last 500, then 0, 1, 2, ...):
 * the first RS_PROTO_RESTART_RUN - 1 frames are out of order, the next one and all after
 * it are accepted, instead of the next 500 being refused. */
static void restart_within_window_recovers(void **state)
{
	uint32_t seqs[12];
	seqs[0] = 500;
	for (uint32_t i = 1; i < 12; i++)
		seqs[i] = i - 1;
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 12), 12 - (RS_PROTO_RESTART_RUN - 1));
	assert_int_equal(rs_proto_parser_stats(&p)->out_of_order, RS_PROTO_RESTART_RUN - 1);
	assert_int_equal(rs_proto_parser_stats(&p)->restarts, 1);
	assert_int_equal(rs_proto_parser_stats(&p)->lost_frames, 0);
}

/* Stale frames that do not count up one by one are never taken for a restart. */
static void scattered_stale_frames_stay_rejected(void **state)
{
	const uint32_t seqs[] = {500, 10, 12, 14, 16, 18, 20, 20, 21, 21, 501};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 11), 2);
	assert_int_equal(rs_proto_parser_stats(&p)->out_of_order, 9);
	assert_int_equal(rs_proto_parser_stats(&p)->restarts, 0);
}

static void sequence_wrap_is_accepted(void **state)
{
	const uint32_t seqs[] = {0xFFFFFFFEu, 0xFFFFFFFFu, 0, 1};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 4), 4);
	assert_int_equal(rs_proto_parser_stats(&p)->lost_frames, 0);
	assert_int_equal(rs_proto_stats_faults(rs_proto_parser_stats(&p)), 0);
}

static void wrap_behind_is_out_of_order(void **state)
{
	const uint32_t seqs[] = {2, 0xFFFFFFFFu};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 2), 1);
	assert_int_equal(rs_proto_parser_stats(&p)->out_of_order, 1);
}

static void gaps_count_lost_frames(void **state)
{
	const uint32_t seqs[] = {5, 8, 9, 20};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 4), 4);
	assert_int_equal(rs_proto_parser_stats(&p)->lost_frames, 2 + 10);
}

static void reset_forgets_sequence_keeps_counters(void **state)
{
	const uint32_t seqs[] = {7, 7};
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	assert_int_equal(feed_seqs(&p, seqs, 2), 1);
	rs_proto_parser_reset(&p);
	assert_int_equal(feed_seqs(&p, seqs, 1), 1);
	assert_int_equal(rs_proto_parser_stats(&p)->duplicates, 1);
	assert_int_equal(rs_proto_parser_stats(&p)->frames, 2);
}

static void byte_at_a_time_equals_bulk(void **state)
{
	uint8_t buf[5 * RS_PROTO_FRAME_SIZE + 40];
	size_t off = 0;
	for (uint32_t i = 0; i < 5; i++) {
		buf[off++] = (uint8_t)(0x11 * i); /* some garbage between frames */
		buf[off++] = RS_PROTO_SYNC0;
		frame_of(i, buf + off);
		off += RS_PROTO_FRAME_SIZE;
	}
	struct rs_proto_parser a, b;
	rs_proto_parser_init(&a);
	rs_proto_parser_init(&b);
	uint32_t sa[8], sb[8];
	size_t na = feed_all(&a, buf, off, sa, 8), nb = 0;
	for (size_t i = 0; i < off; i++)
		nb += feed_all(&b, buf + i, 1, sb + nb, 8 - nb);
	assert_int_equal(na, 5);
	assert_int_equal(nb, 5);
	assert_memory_equal(sa, sb, sizeof sa[0] * 5);
	assert_memory_equal(rs_proto_parser_stats(&a), rs_proto_parser_stats(&b),
	                    sizeof(struct rs_proto_stats));
}

/* xorshift64 so the stream is identical on every machine. */
static uint64_t next_rand(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

static void random_megabyte_yields_exactly_embedded_frames(void **state)
{
	enum { SIZE = 1 << 20, FRAMES = 3000 };
	uint8_t *buf = malloc(SIZE);
	assert_non_null(buf);
	uint64_t r = 0x1234567887654321ull;
	for (size_t i = 0; i < SIZE; i++)
		buf[i] = (uint8_t)next_rand(&r);
	/* Frames at increasing, non-overlapping random offsets, one per SIZE/FRAMES slot. */
	size_t slot = SIZE / FRAMES;
	for (uint32_t k = 0; k < FRAMES; k++) {
		size_t off = k * slot + (size_t)(next_rand(&r) % (slot - RS_PROTO_FRAME_SIZE));
		frame_of(1000 + k, buf + off);
	}
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	uint32_t *seqs = calloc(FRAMES + 10, sizeof *seqs);
	assert_non_null(seqs);
	size_t got = feed_all(&p, buf, SIZE, seqs, FRAMES + 10);
	assert_int_equal(got, FRAMES);
	for (uint32_t k = 0; k < FRAMES; k++)
		assert_int_equal(seqs[k], 1000 + k);
	assert_int_equal(rs_proto_parser_stats(&p)->lost_frames, 0);
	assert_true(rs_proto_parser_stats(&p)->garbage_bytes > SIZE / 2);
	free(seqs);
	free(buf);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(crc32_matches_check_value),
	    cmocka_unit_test(encode_matches_documented_example),
	    cmocka_unit_test(encode_parse_round_trip),
	    cmocka_unit_test(encode_rejects_unencodable),
	    cmocka_unit_test(extreme_coordinates_round_trip),
	    cmocka_unit_test(missing_markers_are_sent_invalid),
	    cmocka_unit_test(garbage_is_counted_and_skipped),
	    cmocka_unit_test(lone_sync_byte_is_garbage),
	    cmocka_unit_test(bad_crc_is_counted),
	    cmocka_unit_test(crc_field_corruption_is_counted),
	    cmocka_unit_test(short_length_is_counted),
	    cmocka_unit_test(long_length_is_counted),
	    cmocka_unit_test(unknown_version_is_counted),
	    cmocka_unit_test(truncated_frame_then_good_frame),
	    cmocka_unit_test(duplicate_sequence_is_rejected),
	    cmocka_unit_test(backwards_sequence_is_rejected),
	    cmocka_unit_test(jump_back_beyond_window_is_restart),
	    cmocka_unit_test(restart_within_window_recovers),
	    cmocka_unit_test(scattered_stale_frames_stay_rejected),
	    cmocka_unit_test(sequence_wrap_is_accepted),
	    cmocka_unit_test(wrap_behind_is_out_of_order),
	    cmocka_unit_test(gaps_count_lost_frames),
	    cmocka_unit_test(reset_forgets_sequence_keeps_counters),
	    cmocka_unit_test(byte_at_a_time_equals_bulk),
	    cmocka_unit_test(random_megabyte_yields_exactly_embedded_frames),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
