/**
 * @file rs_report.h
 * Speed against error: which measured settings are worth picking. A setting is a point
 * (time, error), both smaller-is-better; the Pareto front holds the settings no other one
 * beats on both. Plain functions over caller-owned arrays; no allocation, no errors.
 * raystream-report (tools/report) measures the points; docs/benchmarks.md shows them.
 */
#ifndef RS_REPORT_H
#define RS_REPORT_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** One measured setting: frame time and an error measure, both smaller-is-better. */
struct rs_report_point {
	double time_ms;
	double error;
};

/**
 * Mark the Pareto front: out_on_front[i] is true when no other point is at least as good
 * in both time and error and strictly better in one. Equal points are all on the front
 * (none beats another). A point with a NaN coordinate is never on the front and never
 * beats another. out_on_front: caller-owned, `count` entries; may not alias `points`.
 * @return the number of points on the front.
 */
size_t rs_report_pareto(const struct rs_report_point *points, size_t count, bool *out_on_front);

/**
 * The setting to pick for an error budget: the fastest point with error <= budget (ties in
 * time: the smaller error, then the lower index). Such a point is always on the Pareto
 * front. NaN points are never picked.
 * @return false (and *out_index untouched) when no point meets the budget.
 */
bool rs_report_pick(const struct rs_report_point *points, size_t count, double error_budget,
                    size_t *out_index);

#ifdef __cplusplus
}
#endif
#endif
