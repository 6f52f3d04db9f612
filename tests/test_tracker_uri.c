/* rs_tracker: URI dispatch to every source kind, and clean errors for bad URIs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "contract.h"
#include "raystream/rs_serial.h"
#include "raystream/rs_tracker.h"

static void expect(const char *uri, enum rs_status want)
{
	struct rs_track_source *src = NULL;
	struct rs_error err;
	rs_error_clear(&err);
	enum rs_status st = rs_tracker_open(uri, &src, &err);
	if (st != want)
		fail_msg("%s: got %s (%s), want %s", uri, rs_status_name(st), err.message,
		         rs_status_name(want));
	assert_null(src);
	assert_true(err.message[0] != '\0');
	assert_null(strchr(err.message, '\n'));
}

static void malformed_uris_are_parse_errors(void **state)
{
	const char *bad[] = {"",
	                     "sim",
	                     ":x",
	                     "bogus:1",
	                     "SIM:seed=1",
	                     "sim:seed=",
	                     "sim:noise=1parsec",
	                     "sim:script=fly",
	                     "replay:",
	                     "serial:",
	                     "serial:dev/ttyS0",
	                     "serial:/dev/ttyS0?baud=7",
	                     "averyveryverylongscheme:x"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		expect(bad[i], RS_ERR_PARSE);
}

static void malformed_device_uris(void **state)
{
	/* A build without hidapi/libusb says so instead of parsing the rest. */
	const char *bad[] = {"hid:", "hid:1234", "hid:xyz:1", "usb:", "usb:1:2:3"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		bool have = rs_tracker_has_scheme(bad[i][0] == 'h' ? "hid" : "usb");
		expect(bad[i], have ? RS_ERR_PARSE : RS_ERR_UNSUPPORTED);
	}
}

/* A NULL URI is a programming error, not bad input. */
static void null_uri_is_a_contract_violation(void **state)
{
	struct rs_track_source *src = NULL;
	RS_EXPECT_CONTRACT_VIOLATION(rs_tracker_open(NULL, &src, NULL));
	assert_null(src);
}

static void missing_things_are_not_found(void **state)
{
	expect("replay:/nonexistent/file.rec", RS_ERR_NOT_FOUND);
	expect("serial:/dev/raystream-none", RS_ERR_NOT_FOUND);
	expect("serial:/dev/null", RS_ERR_INVALID);
}

static void devices_absent_here_fail_cleanly(void **state)
{
	/* No HID/USB trackers on a CI machine (and maybe no USB access at all): the open
	 * must fail with a status and message, never crash. Vendor 0xfffe is reserved. */
	const char *uris[] = {"hid:fffe:fffe", "usb:fffe:fffe"};
	for (int i = 0; i < 2; i++) {
		struct rs_track_source *src = NULL;
		struct rs_error err;
		enum rs_status st = rs_tracker_open(uris[i], &src, &err);
		assert_true(st == RS_ERR_NOT_FOUND || st == RS_ERR_DEVICE ||
		            st == RS_ERR_UNSUPPORTED);
		assert_null(src);
	}
}

static void sim_uri_opens_and_ends(void **state)
{
	struct rs_track_source *src = NULL;
	assert_int_equal(
	    rs_tracker_open("sim:seed=3&rate=240&duration=0.1&noise=0.1mm", &src, NULL), RS_OK);
	struct rs_marker_sample s;
	int n = 0;
	while (rs_track_source_read(src, &s, 0, NULL) == RS_OK)
		n++;
	assert_int_equal(n, 24);
	rs_track_source_destroy(&src);
}

static void replay_uri_reads_recording(void **state)
{
	char path[64], uri[96];
	snprintf(path, sizeof path, "test_tracker_uri_%d.rec", (int)getpid());
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	for (uint32_t i = 0; i < 5; i++) {
		struct rs_marker_sample s = {.sequence = 40 + i, .marker_count = 3};
		assert_int_equal(rs_track_recorder_write(rec, &s, NULL), RS_OK);
	}
	assert_int_equal(rs_track_recorder_destroy(&rec, NULL), RS_OK);
	snprintf(uri, sizeof uri, "replay:%s", path);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_tracker_open(uri, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	for (uint32_t i = 0; i < 5; i++) {
		assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
		assert_int_equal(s.sequence, 40 + i);
	}
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_END);
	rs_track_source_destroy(&src);
	/* The query is options, never part of the file name; unknown or bad ones are a
	 * malformed URI, not a missing file. */
	const char *good[] = {"?realtime=0", "?realtime=1"};
	for (int i = 0; i < 2; i++) {
		snprintf(uri, sizeof uri, "replay:%s%s", path, good[i]);
		assert_int_equal(rs_tracker_open(uri, &src, NULL), RS_OK);
		rs_track_source_destroy(&src);
	}
	const char *bad[] = {"?realtime=2", "?speed=1", "?", "?realtime=1&x=1", "?realtime="};
	for (int i = 0; i < 5; i++) {
		struct rs_error err;
		snprintf(uri, sizeof uri, "replay:%s%s", path, bad[i]);
		assert_int_equal(rs_tracker_open(uri, &src, &err), RS_ERR_PARSE);
		assert_null(src);
	}
	assert_int_equal(rs_tracker_open("replay:?realtime=1", &src, NULL), RS_ERR_PARSE);
	remove(path);
}

static void serial_uri_reads_pty(void **state)
{
	struct rs_serial_pty *pty = NULL;
	assert_int_equal(rs_serial_pty_create(&pty, NULL), RS_OK);
	char uri[160];
	snprintf(uri, sizeof uri, "serial:%s?baud=230400", rs_serial_pty_path(pty));
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_tracker_open(uri, &src, NULL), RS_OK);
	struct rs_marker_sample s = {.sequence = 9, .marker_count = 3};
	uint8_t f[RS_PROTO_FRAME_SIZE];
	assert_int_equal(rs_proto_encode(&s, f, NULL), RS_OK);
	assert_int_equal(rs_serial_pty_write(pty, f, sizeof f, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 2000, NULL), RS_OK);
	assert_int_equal(s.sequence, 9);
	rs_track_source_destroy(&src);
	rs_serial_pty_destroy(&pty);
}

static void schemes_are_reported(void **state)
{
	assert_true(rs_tracker_has_scheme("sim"));
	assert_true(rs_tracker_has_scheme("replay"));
	assert_true(rs_tracker_has_scheme("serial"));
	assert_false(rs_tracker_has_scheme("bogus"));
	assert_false(rs_tracker_has_scheme(NULL));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(malformed_uris_are_parse_errors),
	    cmocka_unit_test(malformed_device_uris),
	    cmocka_unit_test(null_uri_is_a_contract_violation),
	    cmocka_unit_test(missing_things_are_not_found),
	    cmocka_unit_test(devices_absent_here_fail_cleanly),
	    cmocka_unit_test(sim_uri_opens_and_ends),
	    cmocka_unit_test(replay_uri_reads_recording),
	    cmocka_unit_test(serial_uri_reads_pty),
	    cmocka_unit_test(schemes_are_reported),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
