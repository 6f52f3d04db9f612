/* rs_stream link emulation: the token bucket passes the configured rate over time (plus
 * one burst), never more, and says how long to wait. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "raystream/rs_stream.h"

static void test_rate_is_kept(void **state)
{
	(void)state;
	struct rs_stream_link l;
	struct rs_stream_link_desc d = {.rate_bits_per_s = 25e6, .latency_s = 0.005};
	assert_int_equal(rs_stream_link_init(&l, &d, NULL), RS_OK);
	/* a greedy sender over 2 simulated seconds in 0.1 ms steps */
	double sent = 0.0;
	for (int i = 0; i <= 20000; ++i) {
		double now = 100.0 + i * 1e-4;
		size_t n = rs_stream_link_allow(&l, now, 50000);
		rs_stream_link_spend(&l, n);
		sent += (double)n;
	}
	double want = 25e6 / 8.0 * 2.0, burst = 25e6 / 8.0 * 0.01;
	assert_true(sent <= want + burst + 1.0);
	assert_true(sent >= want + burst - 2000.0);
}

static void test_wait_and_unlimited(void **state)
{
	(void)state;
	struct rs_stream_link l;
	struct rs_stream_link_desc d = {.rate_bits_per_s = 8e6, .burst_bytes = 10000};
	assert_int_equal(rs_stream_link_init(&l, &d, NULL), RS_OK);
	assert_int_equal(rs_stream_link_allow(&l, 1.0, 20000), 10000);
	rs_stream_link_spend(&l, 10000);
	assert_int_equal(rs_stream_link_allow(&l, 1.0, 20000), 0);
	/* 1 MB/s: 5000 bytes take 5 ms */
	assert_true(fabs(rs_stream_link_wait_s(&l, 1.0, 5000) - 0.005) < 1e-9);
	size_t n = rs_stream_link_allow(&l, 1.005, 20000); /* 5000 up to rounding of 1.005 */
	assert_true(n >= 4999 && n <= 5000);
	assert_true(rs_stream_link_wait_s(&l, 1.005, 100) == 0.0);
	struct rs_stream_link u;
	assert_int_equal(rs_stream_link_init(&u, NULL, NULL), RS_OK);
	assert_int_equal(rs_stream_link_allow(&u, 0.0, 1u << 30), 1u << 30);
	assert_true(rs_stream_link_wait_s(&u, 0.0, 1u << 30) == 0.0);
	struct rs_stream_link_desc bad = {.rate_bits_per_s = -1};
	assert_int_equal(rs_stream_link_init(&u, &bad, NULL), RS_ERR_INVALID);
	bad = (struct rs_stream_link_desc){.latency_s = NAN};
	assert_int_equal(rs_stream_link_init(&u, &bad, NULL), RS_ERR_INVALID);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_rate_is_kept),
	    cmocka_unit_test(test_wait_and_unlimited),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
