/* rs_track: the VID:PID prefix shared by the hid: and usb: device URIs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "raystream/rs_track.h"

static void vid_pid_with_and_without_tail(void **state)
{
	uint16_t vid = 0, pid = 0;
	const char *tail = NULL;
	assert_int_equal(rs_track_parse_vid_pid("046d:C52B", &vid, &pid, &tail, NULL), RS_OK);
	assert_int_equal(vid, 0x046d);
	assert_int_equal(pid, 0xc52b);
	assert_string_equal(tail, "");
	assert_int_equal(rs_track_parse_vid_pid("1:ffff:SER:1", &vid, &pid, &tail, NULL), RS_OK);
	assert_int_equal(vid, 1);
	assert_int_equal(pid, 0xffff);
	assert_string_equal(tail, ":SER:1");
}

static void malformed_vid_pid_is_refused_untouched(void **state)
{
	const char *bad[] = {"",       "046d",  "046d:", ":c52b", "12345:1", "1:12345",
	                     "0x12:1", "1:0x1", "g:1",   " 1:1",  "1:1 ",    "1\t:1"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
		uint16_t vid = 7, pid = 9;
		const char *tail = NULL;
		assert_int_equal(rs_track_parse_vid_pid(bad[i], &vid, &pid, &tail, NULL),
		                 RS_ERR_PARSE);
		assert_int_equal(vid, 7);
		assert_int_equal(pid, 9);
		assert_null(tail);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(vid_pid_with_and_without_tail),
	    cmocka_unit_test(malformed_vid_pid_is_refused_untouched),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
