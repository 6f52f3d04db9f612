/* rs_core: status names, the caller-owned error record, the always-on contract check, and
 * the one copy of each shared mechanism (clock, little-endian codec, pi, vectors). */
/* Every build the scripts make defines NDEBUG; the contract check must not care. */
#ifndef NDEBUG
#define NDEBUG 1
#endif
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdio.h>
#include <dirent.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "contract.h"
#include "private/rs_atomic_file.h"
#include "private/rs_le.h"
#include "private/rs_vec.h"
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

/* Entries in `dir` other than . and .. */
static int entries(const char *dir)
{
	DIR *d = opendir(dir);
	assert_non_null(d);
	int n = 0;
	for (struct dirent *e; (e = readdir(d)) != NULL;)
		n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
	closedir(d);
	return n;
}

/* The file appears under its name only on a good commit; a failed one leaves nothing, and
 * a target that is not a regular file is refused and kept. */
static void atomic_file_is_all_or_nothing(void **state)
{
	char dir[] = "/tmp/rs_core_XXXXXX", path[64], text[16] = {0};
	assert_non_null(mkdtemp(dir));
	snprintf(path, sizeof path, "%s/out.txt", dir);
	struct rs_atomic_file af;
	struct rs_error err = {0};
	assert_int_equal(rs_atomic_open(&af, path, &err), RS_OK);
	fputs("half", af.f);
	assert_int_equal(access(path, F_OK), -1); /* not there while being written */
	rs_error_set(&err, RS_ERR_BAD_DATA, "caller gave up");
	assert_int_equal(rs_atomic_commit(&af, false, &err), RS_ERR_BAD_DATA);
	assert_int_equal(entries(dir), 0);
	assert_int_equal(rs_atomic_open(&af, path, &err), RS_OK);
	fputs("whole", af.f);
	assert_int_equal(rs_atomic_finish(&af, true, &err), RS_OK);
	assert_int_equal(rs_atomic_commit(&af, true, &err), RS_OK);
	FILE *f = fopen(path, "r");
	assert_non_null(f);
	assert_non_null(fgets(text, sizeof text, f));
	fclose(f);
	assert_string_equal(text, "whole");
	assert_int_equal(entries(dir), 1);
	assert_int_equal(rs_atomic_open(&af, dir, &err), RS_ERR_IO); /* a directory */
	assert_non_null(strstr(err.message, "not a regular file"));
	assert_int_equal(unlink(path), 0);
	assert_int_equal(rmdir(dir), 0);
}

/* The shared quaternion helpers: a quarter turn about z maps x to y, composes to a half
 * turn, and log/exp are inverse (tolerance 1e-12). */
static void vector_helpers_rotate_and_compose(void **state)
{
	const double v[3] = {0, 0, RS_PI / 2}, x[3] = {1, 0, 0};
	double q[4], qq[4], r[3], back[3];
	rs_q_exp(v, q);
	rs_q_rotate(q, x, r);
	assert_true(fabs(r[0]) < 1e-12 && fabs(r[1] - 1.0) < 1e-12 && fabs(r[2]) < 1e-12);
	rs_q_mul(q, q, qq);
	rs_q_rotate(qq, x, r);
	assert_true(fabs(r[0] + 1.0) < 1e-12 && fabs(r[1]) < 1e-12);
	rs_q_log(q, back);
	assert_true(fabs(back[2] - RS_PI / 2) < 1e-12 && fabs(back[0]) < 1e-12);
	double w[3] = {3, 4, 0};
	assert_true(rs_v3_normalize(w) == 5.0 && w[0] == 0.6);
	double zero[3] = {0, 0, 0};
	assert_true(rs_v3_normalize(zero) == 0.0);
}

/* The clock never goes back, and a sleep of 20 ms reads as at least that much (a lower
 * bound: how much longer a loaded machine took is not asserted). */
static void clock_is_monotonic_milliseconds(void **state)
{
	(void)state;
	double t = rs_now_ms(), last = t;
	for (int i = 0; i < 100000; ++i) {
		double now = rs_now_ms();
		assert_true(now >= last);
		last = now;
	}
	struct timespec nap = {0, 20 * 1000 * 1000};
	while (nanosleep(&nap, &nap) != 0) {
	}
	assert_true(rs_now_ms() - t >= 19.9);
}

/* Little-endian whatever the host: the bytes in order, and every width round-trips. */
static void le_codec_writes_least_significant_byte_first(void **state)
{
	(void)state;
	uint8_t b[8];
	rs_le_put16(b, 0x0201);
	assert_true(b[0] == 1 && b[1] == 2);
	rs_le_put32(b, 0x04030201u);
	assert_true(b[0] == 1 && b[1] == 2 && b[2] == 3 && b[3] == 4);
	rs_le_put64(b, 0x0807060504030201ull);
	for (int i = 0; i < 8; ++i)
		assert_int_equal(b[i], i + 1);
	assert_true(rs_le_get16(b) == 0x0201);
	assert_true(rs_le_get32(b) == 0x04030201u);
	assert_true(rs_le_get64(b) == 0x0807060504030201ull);
	const uint64_t v = 0xF1E2D3C4B5A69788ull; /* high bits set in every byte */
	rs_le_put64(b, v);
	assert_true(rs_le_get64(b) == v && rs_le_get32(b) == (uint32_t)v &&
	            rs_le_get16(b) == (uint16_t)v && rs_le_get32(b + 4) == (uint32_t)(v >> 32));
}

static void pi_is_pi(void **state)
{
	(void)state;
	assert_true(RS_PI == acos(-1.0));
	assert_true(fabs(sin(RS_PI)) < 1e-15 && cos(RS_PI) == -1.0);
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
	    cmocka_unit_test(atomic_file_is_all_or_nothing),
	    cmocka_unit_test(vector_helpers_rotate_and_compose),
	    cmocka_unit_test(clock_is_monotonic_milliseconds),
	    cmocka_unit_test(le_codec_writes_least_significant_byte_first),
	    cmocka_unit_test(pi_is_pi),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
