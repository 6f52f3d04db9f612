/* rs_core: status names, the caller-owned error record and the always-on contract check. */
/* Every build the scripts make defines NDEBUG; the contract check must not care. */
#ifndef NDEBUG
#define NDEBUG 1
#endif
#include <setjmp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "contract.h"
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

static void error_prefix_adds_context(void **state)
{
	struct rs_error err;
	rs_error_set(&err, RS_ERR_BAD_DATA, "vertex 2 is NaN");
	assert_int_equal(rs_error_prefix(&err, RS_ERR_BAD_DATA, "mesh %d", 3), RS_ERR_BAD_DATA);
	assert_string_equal(err.message, "mesh 3: vertex 2 is NaN");
	assert_int_equal(rs_error_prefix(NULL, RS_ERR_IO, "x"), RS_ERR_IO);
}

/* With NDEBUG defined and no handler installed, a failed check still stops the process
 * (SIGABRT) after one line naming the condition on stderr. */
static void assert_aborts_with_ndebug(void **state)
{
	int fds[2];
	assert_int_equal(pipe(fds), 0);
	fflush(NULL);
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		dup2(fds[1], 2);
		const char *volatile handle = NULL;
		RS_ASSERT(handle != NULL);
		_exit(0); /* reached only when the check is compiled out */
	}
	close(fds[1]);
	char text[512] = {0};
	size_t got = 0;
	ssize_t n;
	while (got < sizeof text - 1 && (n = read(fds[0], text + got, sizeof text - 1 - got)) > 0)
		got += (size_t)n;
	close(fds[0]);
	int status = 0;
	assert_int_equal(waitpid(pid, &status, 0), pid);
	assert_true(WIFSIGNALED(status));
	assert_int_equal(WTERMSIG(status), SIGABRT);
	assert_non_null(strstr(text, "contract violated: handle != NULL"));
}

static int g_calls;
static void counting_handler(const char *expr, const char *file, int line, void *user)
{
	g_calls++;
	*(int *)user = line;
	longjmp(rs_contract_jump, 1);
}

static void assert_calls_installed_handler(void **state)
{
	int line = 0;
	g_calls = 0;
	rs_set_assert_handler(counting_handler, &line);
	if (setjmp(rs_contract_jump) == 0)
		RS_ASSERT(g_calls < 0);
	rs_set_assert_handler(NULL, NULL);
	assert_int_equal(g_calls, 1);
	assert_true(line > 0);
	RS_EXPECT_CONTRACT_VIOLATION(RS_ASSERT(1 == 2));
	assert_string_equal(rs_contract_last_expr(), "1 == 2");
	RS_ASSERT(g_calls == 1); /* a passing check does nothing */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(error_set_returns_status_and_formats),
	    cmocka_unit_test(error_message_is_one_line),
	    cmocka_unit_test(error_message_truncates),
	    cmocka_unit_test(error_null_is_allowed),
	    cmocka_unit_test(status_names_are_distinct),
	    cmocka_unit_test(error_prefix_adds_context),
	    cmocka_unit_test(assert_aborts_with_ndebug),
	    cmocka_unit_test(assert_calls_installed_handler),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
