/* rs_track stream source over a scripted fake transport: framing across reads,
 * timeouts, disconnect and reopen bookkeeping. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_track.h"

/* One scripted transport reply. */
struct step {
	enum rs_status status;
	uint8_t bytes[256];
	size_t n;
};

struct fake {
	struct step steps[16];
	size_t nsteps, next;
	int reads, reopens, reopen_fails, destroyed;
	int *destroyed_flag;
};

static enum rs_status fake_read(void *impl, uint8_t *buf, size_t cap, int timeout_ms, size_t *out_n,
                                struct rs_error *err)
{
	struct fake *f = impl;
	f->reads++;
	*out_n = 0;
	if (f->next >= f->nsteps)
		return rs_error_set(err, RS_TIMEOUT, "fake: nothing");
	struct step *s = &f->steps[f->next++];
	if (s->status != RS_OK)
		return rs_error_set(err, s->status, "fake: scripted %s", rs_status_name(s->status));
	assert_true(s->n <= cap);
	memcpy(buf, s->bytes, s->n);
	*out_n = s->n;
	return RS_OK;
}

static enum rs_status fake_reopen(void *impl, struct rs_error *err)
{
	struct fake *f = impl;
	if (f->reopen_fails > 0) {
		f->reopen_fails--;
		return rs_error_set(err, RS_ERR_NOT_FOUND, "fake: still unplugged");
	}
	f->reopens++;
	return RS_OK;
}

static void fake_destroy(void *impl)
{
	struct fake *f = impl;
	*f->destroyed_flag = 1;
	free(f);
}

static const struct rs_track_transport fake_transport = {fake_read, fake_reopen, fake_destroy};

static int destroyed;

static struct fake *new_fake(void)
{
	struct fake *f = calloc(1, sizeof *f);
	assert_non_null(f);
	f->destroyed_flag = &destroyed;
	destroyed = 0;
	return f;
}

static void add_bytes(struct fake *f, const uint8_t *b, size_t n)
{
	struct step *s = &f->steps[f->nsteps++];
	s->status = RS_OK;
	memcpy(s->bytes, b, n);
	s->n = n;
}

static void add_status(struct fake *f, enum rs_status st)
{
	f->steps[f->nsteps++].status = st;
}

static void frame(uint32_t seq, uint8_t *out)
{
	struct rs_marker_sample s = {
	    .sequence = seq, .device_time_us = seq * 100, .marker_count = 3};
	assert_int_equal(rs_proto_encode(&s, out, NULL), RS_OK);
}

static struct rs_track_source *open_fake(struct fake *f)
{
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_stream_create(&fake_transport, f, &src, NULL), RS_OK);
	return src;
}

static void frame_split_across_reads(void **state)
{
	struct fake *f = new_fake();
	uint8_t fr[RS_PROTO_FRAME_SIZE];
	frame(1, fr);
	add_bytes(f, fr, 10);
	add_bytes(f, fr + 10, 40);
	add_bytes(f, fr + 50, RS_PROTO_FRAME_SIZE - 50);
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 100, NULL), RS_OK);
	assert_int_equal(s.sequence, 1);
	assert_int_equal(f->reads, 3);
	assert_true(s.host_time_s > 0);
	rs_track_source_destroy(&src);
	assert_null(src);
	assert_int_equal(destroyed, 1);
}

static void several_frames_in_one_read(void **state)
{
	struct fake *f = new_fake();
	uint8_t b[3 * RS_PROTO_FRAME_SIZE];
	for (uint32_t i = 0; i < 3; i++)
		frame(i + 1, b + i * RS_PROTO_FRAME_SIZE);
	add_bytes(f, b, sizeof b);
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s[3];
	for (int i = 0; i < 3; i++) {
		assert_int_equal(rs_track_source_read(src, &s[i], 0, NULL), RS_OK);
		assert_int_equal(s[i].sequence, (uint32_t)i + 1);
	}
	assert_int_equal(f->reads, 1);
	assert_true(s[0].host_time_s == s[2].host_time_s); /* stamped at arrival of the read */
	rs_track_source_destroy(&src);
}

static void quiet_transport_times_out(void **state)
{
	struct fake *f = new_fake();
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_TIMEOUT);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_TIMEOUT);
	rs_track_source_destroy(&src);
}

/* A transport that comes back early with nothing (a spurious wake-up) does not end a
 * read before the caller's timeout, nor a read that waits for ever. */
static void early_empty_transport_read_keeps_waiting(void **state)
{
	struct fake *f = new_fake();
	uint8_t fr[RS_PROTO_FRAME_SIZE];
	add_status(f, RS_TIMEOUT);
	frame(7, fr);
	add_bytes(f, fr, sizeof fr);
	add_status(f, RS_TIMEOUT);
	add_status(f, RS_TIMEOUT);
	frame(8, fr);
	add_bytes(f, fr, sizeof fr);
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 1000, NULL), RS_OK);
	assert_int_equal(s.sequence, 7);
	assert_int_equal(rs_track_source_read(src, &s, -1, NULL), RS_OK);
	assert_int_equal(s.sequence, 8);
	rs_track_source_destroy(&src);
}

static void disconnect_then_reopen(void **state)
{
	struct fake *f = new_fake();
	uint8_t fr[RS_PROTO_FRAME_SIZE];
	frame(50, fr);
	add_bytes(f, fr, sizeof fr);
	add_status(f, RS_ERR_DISCONNECTED);
	frame(3, fr); /* the device restarted its count: must not be "out of order" */
	add_bytes(f, fr, sizeof fr);
	f->reopen_fails = 1;
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_ERR_DISCONNECTED);
	assert_true(rs_track_source_last_error(src)[0] != '\0');
	int reads = f->reads;
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_ERR_DISCONNECTED);
	assert_int_equal(f->reads, reads); /* no transport call while disconnected */
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_ERR_NOT_FOUND);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_ERR_DISCONNECTED);
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
	assert_int_equal(s.sequence, 3);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_true(st.samples == 2 && st.disconnects == 1 && st.reopens == 1);
	assert_true(st.proto.out_of_order == 0);
	rs_track_source_destroy(&src);
}

static void transport_errors_pass_through(void **state)
{
	struct fake *f = new_fake();
	add_status(f, RS_ERR_IO);
	add_status(f, RS_END);
	struct rs_track_source *src = open_fake(f);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_ERR_IO);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_END);
	rs_track_source_destroy(&src);
}

static void destroy_accepts_null(void **state)
{
	struct rs_track_source *src = NULL;
	rs_track_source_destroy(&src);
	rs_track_source_destroy(NULL);
	assert_null(src);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(frame_split_across_reads),
	    cmocka_unit_test(several_frames_in_one_read),
	    cmocka_unit_test(quiet_transport_times_out),
	    cmocka_unit_test(early_empty_transport_read_keeps_waiting),
	    cmocka_unit_test(disconnect_then_reopen),
	    cmocka_unit_test(transport_errors_pass_through),
	    cmocka_unit_test(destroy_accepts_null),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
