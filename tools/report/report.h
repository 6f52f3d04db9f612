/* raystream-report: shared between measuring (main.c) and writing (output.c). */
#ifndef RS_REPORT_TOOL_H
#define RS_REPORT_TOOL_H

#include <stdbool.h>
#include <stdint.h>

#include "raystream/rs_image.h"
#include "raystream/rs_render.h"
#include "raystream/rs_report.h"

#define REPORT_MAX_ROWS 48

/* One measured setting. */
struct report_row {
	char label[48];
	const char *backend;
	struct rs_render_desc desc;
	double ms_med, ms_min, ms_max;  /* wall time of rs_renderer_render, readback included */
	double cpu_med;                 /* process CPU time per frame (all threads) */
	struct rs_image_diff diff;      /* last frame against the CPU reference */
	bool front;                     /* on the Pareto front of (ms_med, bad share) */
	bool refused;                   /* the backend refused the setting for this scene */
	char why[RS_ERROR_MESSAGE_MAX]; /* its one-line reason */
};

struct report {
	const char *scene;
	uint32_t size, frames, lights, max_passes;
	char renderer[128]; /* the GL renderer string of the measured backend (or the CPU's) */
	char machine[160];
	double load1;
	bool diffs;  /* diff-NN.png written beside the report */
	bool by_cpu; /* the front and the pick use CPU ms (steadier for llvmpipe), else wall ms */
	struct report_row rows[REPORT_MAX_ROWS];
	uint32_t count;
};

/* The time the front, the pick and the plot use for a row. */
static inline double report_time(const struct report *rep, const struct report_row *row)
{
	return rep->by_cpu ? row->cpu_med : row->ms_med;
}

/* Error budgets (share of pixels off by more than 8/255) the report names a pick for. */
extern const double report_budgets[];
extern const uint32_t report_budget_count;

/* Write DIR/report.csv, DIR/report.md and (unless !plot) DIR/report.png through gnuplot;
 * each file complete or absent. */
enum rs_status report_write(const struct report *rep, const char *dir, bool plot,
                            struct rs_error *err);

#endif
