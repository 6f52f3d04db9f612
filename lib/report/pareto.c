/* The Pareto front of (time, error) points and the pick for an error budget. O(n^2): a
 * report has tens of settings, and the quadratic form is obviously right. */
#include <math.h>

#include "raystream/rs_report.h"

static bool usable(const struct rs_report_point *p)
{
	return !isnan(p->time_ms) && !isnan(p->error);
}

/* a beats b: no worse in both, strictly better in one. */
static bool beats(const struct rs_report_point *a, const struct rs_report_point *b)
{
	return a->time_ms <= b->time_ms && a->error <= b->error &&
	       (a->time_ms < b->time_ms || a->error < b->error);
}

size_t rs_report_pareto(const struct rs_report_point *points, size_t count, bool *out_on_front)
{
	size_t front = 0;
	for (size_t i = 0; i < count; ++i) {
		bool on = usable(&points[i]);
		for (size_t j = 0; j < count && on; ++j)
			if (j != i && usable(&points[j]) && beats(&points[j], &points[i]))
				on = false;
		out_on_front[i] = on;
		front += on;
	}
	return front;
}

bool rs_report_pick(const struct rs_report_point *points, size_t count, double error_budget,
                    size_t *out_index)
{
	size_t best = count;
	for (size_t i = 0; i < count; ++i) {
		const struct rs_report_point *p = &points[i];
		if (!usable(p) || !(p->error <= error_budget))
			continue;
		if (best == count || p->time_ms < points[best].time_ms ||
		    (p->time_ms == points[best].time_ms && p->error < points[best].error))
			best = i;
	}
	if (best == count)
		return false;
	*out_index = best;
	return true;
}
