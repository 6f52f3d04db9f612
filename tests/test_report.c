/* The Pareto front and the budget pick on hand-made tables. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "raystream/rs_report.h"

/* time, error; the front worked out by hand: A(1,9) C(2,5) E(4,1) F(8,0); B(2,9) loses to A
 * and C, D(3,6) to C, G(9,0) to F, H(NaN) is unusable, I(4,1) equals E (both kept). */
static const struct rs_report_point table[] = {
    {1, 9}, {2, 9}, {2, 5}, {3, 6}, {4, 1}, {8, 0}, {9, 0}, {NAN, 0}, {4, 1},
};
#define N (sizeof table / sizeof table[0])

static void front_matches_the_hand_made_table(void **state)
{
	(void)state;
	bool on[N];
	const bool want[N] = {true, false, true, false, true, true, false, false, true};
	assert_int_equal(rs_report_pareto(table, N, on), 5);
	for (size_t i = 0; i < N; ++i)
		assert_int_equal(on[i], want[i]);
}

static void front_of_one_point_and_of_none(void **state)
{
	(void)state;
	bool on[1] = {false};
	assert_int_equal(rs_report_pareto(table, 1, on), 1);
	assert_true(on[0]);
	assert_int_equal(rs_report_pareto(table, 0, on), 0);
}

static void pick_is_the_fastest_within_budget(void **state)
{
	(void)state;
	size_t i = 99;
	assert_true(rs_report_pick(table, N, 9.0, &i));
	assert_int_equal(i, 0); /* A */
	assert_true(rs_report_pick(table, N, 5.5, &i));
	assert_int_equal(i, 2); /* C, not B at the same time */
	assert_true(rs_report_pick(table, N, 1.0, &i));
	assert_int_equal(i, 4); /* E, the first of the equal pair */
	assert_true(rs_report_pick(table, N, 0.0, &i));
	assert_int_equal(i, 5); /* F, not the NaN-timed H */
	i = 99;
	assert_false(rs_report_pick(table, N, -1.0, &i));
	assert_int_equal(i, 99);
}

static void picked_point_is_on_the_front(void **state)
{
	(void)state;
	bool on[N];
	rs_report_pareto(table, N, on);
	const double budgets[] = {0.0, 0.5, 1.0, 3.0, 5.0, 6.0, 8.9, 9.0, 100.0};
	for (size_t b = 0; b < sizeof budgets / sizeof budgets[0]; ++b) {
		size_t i;
		assert_true(rs_report_pick(table, N, budgets[b], &i));
		assert_true(on[i]);
		assert_true(table[i].error <= budgets[b]);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(front_matches_the_hand_made_table),
	    cmocka_unit_test(front_of_one_point_and_of_none),
	    cmocka_unit_test(pick_is_the_fastest_within_budget),
	    cmocka_unit_test(picked_point_is_on_the_front),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
