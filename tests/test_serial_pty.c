/* rs_serial end to end through a pseudo-terminal: the simulator plays the device. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <math.h>

#include "raystream/rs_serial.h"

struct rig {
	struct rs_serial_pty *pty;
	struct rs_track_source *src;
};

static int setup(void **state)
{
	static struct rig r;
	memset(&r, 0, sizeof r);
	if (rs_serial_pty_create(&r.pty, NULL) != RS_OK)
		return -1;
	struct rs_serial_desc d = {.path = rs_serial_pty_path(r.pty), .baud = 115200};
	if (rs_serial_open(&d, &r.src, NULL) != RS_OK)
		return -1;
	*state = &r;
	return 0;
}

static int teardown(void **state)
{
	struct rig *r = *state;
	rs_track_source_destroy(&r->src);
	rs_serial_pty_destroy(&r->pty);
	return 0;
}

static void write_sample(struct rig *r, const struct rs_marker_sample *s)
{
	uint8_t f[RS_PROTO_FRAME_SIZE];
	assert_int_equal(rs_proto_encode(s, f, NULL), RS_OK);
	assert_int_equal(rs_serial_pty_write(r->pty, f, sizeof f, NULL), RS_OK);
}

static void sim_frames_arrive_in_order(void **state)
{
	/* 600 samples written in bursts of 20 (well under the pty buffer) and read back:
	 * every one arrives, in order, equal to the simulator's to 0.5 um. */
	struct rig *r = *state;
	struct rs_sim_desc d = {.seed = 21, .noise_sigma_m = 0.0002, .swap_prob = 0.02};
	struct rs_sim *sim = NULL;
	assert_int_equal(rs_sim_create(&d, &sim, NULL), RS_OK);
	struct rs_marker_sample ref[20], got;
	for (int burst = 0; burst < 30; burst++) {
		for (int i = 0; i < 20; i++) {
			assert_int_equal(rs_sim_next(sim, &ref[i], NULL, NULL), RS_OK);
			write_sample(r, &ref[i]);
		}
		for (int i = 0; i < 20; i++) {
			assert_int_equal(rs_track_source_read(r->src, &got, 2000, NULL), RS_OK);
			assert_int_equal(got.sequence, ref[i].sequence);
			assert_true(got.device_time_us == ref[i].device_time_us);
			for (int m = 0; m < 3; m++) {
				assert_int_equal(got.markers[m].id, ref[i].markers[m].id);
				for (int a = 0; a < 3; a++)
					assert_true(fabs(got.markers[m].position[a] -
					                 ref[i].markers[m].position[a]) <=
					            0.5e-6 + 1e-12);
			}
		}
	}
	struct rs_track_source_stats st;
	rs_track_source_get_stats(r->src, &st);
	assert_true(st.samples == 600 && st.proto.frames == 600);
	assert_true(rs_proto_stats_faults(&st.proto) == 0);
	rs_sim_destroy(&sim);
}

static void line_noise_is_skipped(void **state)
{
	/* Bytes the line discipline would mangle in cooked mode (CR, LF, ^C, ^S, DEL)
	 * between frames: raw mode passes them, the parser discards them as garbage. */
	struct rig *r = *state;
	static const uint8_t noise[] = {'\r', '\n', 0x03, 0x13, 0x11, 0x7f, 0x04, 0x00, 0xA5};
	for (uint32_t i = 0; i < 10; i++) {
		struct rs_marker_sample s = {.sequence = i, .marker_count = 3};
		assert_int_equal(rs_serial_pty_write(r->pty, noise, sizeof noise, NULL), RS_OK);
		write_sample(r, &s);
	}
	struct rs_marker_sample got;
	for (uint32_t i = 0; i < 10; i++) {
		assert_int_equal(rs_track_source_read(r->src, &got, 2000, NULL), RS_OK);
		assert_int_equal(got.sequence, i);
	}
	struct rs_track_source_stats st;
	rs_track_source_get_stats(r->src, &st);
	assert_int_equal(st.proto.garbage_bytes, 10 * sizeof noise);
}

static void silence_times_out(void **state)
{
	struct rig *r = *state;
	struct rs_marker_sample got;
	double t0 = rs_track_now_s();
	assert_int_equal(rs_track_source_read(r->src, &got, 50, NULL), RS_TIMEOUT);
	/* poll() sleeps at least the timeout; allow 5 ms of clock granularity below it. */
	assert_true(rs_track_now_s() - t0 >= 0.045);
}

static void hangup_is_disconnect(void **state)
{
	struct rig *r = *state;
	struct rs_marker_sample got;
	rs_serial_pty_hangup(r->pty);
	assert_int_equal(rs_track_source_read(r->src, &got, 1000, NULL), RS_ERR_DISCONNECTED);
	assert_int_equal(rs_track_source_read(r->src, &got, 0, NULL), RS_ERR_DISCONNECTED);
	/* The pty is gone, so reopening cannot find it yet. */
	assert_true(rs_track_source_reopen(r->src, NULL) != RS_OK);
}

static void reopen_resumes_reading(void **state)
{
	struct rig *r = *state;
	assert_int_equal(rs_track_source_reopen(r->src, NULL), RS_OK);
	struct rs_marker_sample s = {.sequence = 1, .marker_count = 3}, got;
	write_sample(r, &s);
	assert_int_equal(rs_track_source_read(r->src, &got, 2000, NULL), RS_OK);
	assert_int_equal(got.sequence, 1);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(r->src, &st);
	assert_int_equal(st.reopens, 1);
}

/* Nobody reads the slave: once the line is full a bounded write returns RS_TIMEOUT
 * after about its timeout instead of blocking for ever (what let raystream-track --pty
 * hang, deaf to Ctrl-C, when no reader was attached). */
static void full_line_write_times_out(void **state)
{
	struct rig *r = *state;
	enum { BIG = 1 << 20 }; /* far more than any pty buffers */
	static uint8_t junk[BIG];
	size_t written = 0;
	double t0 = rs_track_now_s();
	struct rs_error err;
	assert_int_equal(rs_serial_pty_write_timeout(r->pty, junk, BIG, 50, &written, &err),
	                 RS_TIMEOUT);
	double dt = rs_track_now_s() - t0;
	assert_true(written > 0 && written < BIG);
	/* It returned, so it did not block for ever (ctest's timeout is the hang guard), and
	 * not before its timeout (5 ms clock granularity below): a lower bound load cannot
	 * break. How soon it returns is not asserted. */
	assert_true(dt >= 0.045);
}

static void open_errors(void **state)
{
	struct rs_track_source *src = NULL;
	struct rs_error err;
	struct rs_serial_desc d = {.path = "/dev/raystream-no-such-tty"};
	assert_int_equal(rs_serial_open(&d, &src, &err), RS_ERR_NOT_FOUND);
	d.path = "/dev/null";
	assert_int_equal(rs_serial_open(&d, &src, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "not a terminal"));
	d.baud = 12345;
	assert_int_equal(rs_serial_open(&d, &src, &err), RS_ERR_INVALID);
	assert_null(src);
}

static void uri_parsing(void **state)
{
	char path[64];
	struct rs_serial_desc d;
	struct rs_error err;
	assert_int_equal(
	    rs_serial_parse_uri("/dev/ttyUSB0?baud=921600", path, sizeof path, &d, NULL), RS_OK);
	assert_string_equal(d.path, "/dev/ttyUSB0");
	assert_int_equal(d.baud, 921600);
	assert_int_equal(rs_serial_parse_uri("/dev/ttyACM1", path, sizeof path, &d, NULL), RS_OK);
	assert_int_equal(d.baud, 0);
	const char *bad[] = {"",
	                     "ttyUSB0",
	                     "?baud=9600",
	                     "/dev/x?baud=12345",
	                     "/dev/x?baud=",
	                     "/dev/x?speed=9600",
	                     "/dev/x?baud=96OO"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(rs_serial_parse_uri(bad[i], path, sizeof path, &d, &err),
		                 RS_ERR_PARSE);
		assert_true(err.message[0] != '\0');
	}
	char tiny[4];
	assert_int_equal(rs_serial_parse_uri("/dev/ttyS0", tiny, sizeof tiny, &d, &err),
	                 RS_ERR_PARSE);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test_setup_teardown(sim_frames_arrive_in_order, setup, teardown),
	    cmocka_unit_test_setup_teardown(line_noise_is_skipped, setup, teardown),
	    cmocka_unit_test_setup_teardown(silence_times_out, setup, teardown),
	    cmocka_unit_test_setup_teardown(hangup_is_disconnect, setup, teardown),
	    cmocka_unit_test_setup_teardown(reopen_resumes_reading, setup, teardown),
	    cmocka_unit_test_setup_teardown(full_line_write_times_out, setup, teardown),
	    cmocka_unit_test(open_errors),
	    cmocka_unit_test(uri_parsing),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
