/* rs_core: status names and the caller-owned error record. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_status.h"

static void error_set_returns_status_and_formats(void **state)
{
	struct rs_error err;
	rs_error_clear(&err);
	assert_int_equal(rs_error_set(&err, RS_ERR_PARSE, "line %d: bad token", 7), RS_ERR_PARSE);
	assert_int_equal(err.status, RS_ERR_PARSE);
	assert_string_equal(err.message, "line 7: bad token");
}

static void error_message_is_one_line(void **state)
{
	struct rs_error err;
	rs_error_set(&err, RS_ERR_IO, "first\nsecond\r");
	assert_null(strchr(err.message, '\n'));
	assert_null(strchr(err.message, '\r'));
}

static void error_message_truncates(void **state)
{
	struct rs_error err;
	char long_text[1000];
	memset(long_text, 'x', sizeof long_text - 1);
	long_text[sizeof long_text - 1] = '\0';
	rs_error_set(&err, RS_ERR_IO, "%s", long_text);
	assert_int_equal(strlen(err.message), RS_ERROR_MESSAGE_MAX - 1);
}

static void error_null_is_allowed(void **state)
{
	assert_int_equal(rs_error_set(NULL, RS_ERR_INVALID, "ignored"), RS_ERR_INVALID);
	rs_error_clear(NULL);
}

static void status_names_are_distinct(void **state)
{
	assert_string_equal(rs_status_name(RS_OK), "RS_OK");
	assert_string_equal(rs_status_name(RS_ERR_DEGENERATE), "RS_ERR_DEGENERATE");
	assert_string_equal(rs_status_name((enum rs_status)12345), "RS_UNKNOWN_STATUS");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(error_set_returns_status_and_formats),
	    cmocka_unit_test(error_message_is_one_line),
	    cmocka_unit_test(error_message_truncates),
	    cmocka_unit_test(error_null_is_allowed),
	    cmocka_unit_test(status_names_are_distinct),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
