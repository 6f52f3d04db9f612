/* raystream-bench: the one timing loop, median and progress line every mode uses. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "tool_common.h"

struct bench_summary bench_summarize(const double *v, uint32_t n)
{
	double tmp[BENCH_MAX_FRAMES];
	n = n < sizeof tmp / sizeof tmp[0] ? n : (uint32_t)(sizeof tmp / sizeof tmp[0]);
	memcpy(tmp, v, n * sizeof *tmp);
	struct bench_summary s = {.median = rs_tool_median(tmp, n), .min = tmp[0], .max = tmp[0]};
	for (uint32_t i = 1; i < n; ++i) {
		s.min = tmp[i] < s.min ? tmp[i] : s.min;
		s.max = tmp[i] > s.max ? tmp[i] : s.max;
	}
	return s;
}

enum rs_status bench_time_frames(struct rs_renderer *r, struct rs_frame *frame, uint32_t n,
                                 struct bench_frames *out, struct rs_error *err)
{
	out->n = 0;
	out->kernel_count = 0;
	for (uint32_t f = 0; f < n && f < BENCH_MAX_FRAMES; ++f) {
		double c0 = rs_tool_cpu_ms(), t0 = rs_now_ms();
		enum rs_status st = rs_renderer_render(r, NULL, frame, err);
		if (st != RS_OK)
			return st;
		out->wall_ms[f] = rs_now_ms() - t0;
		out->cpu_ms[f] = rs_tool_cpu_ms() - c0;
		const struct rs_render_stats *s = rs_renderer_stats(r);
		out->render_ms[f] = s->render_ms;
		out->readback_ms[f] = s->readback_ms;
		if (f == 0)
			out->kernel_count = s->kernel_count;
		for (uint32_t k = 0; k < out->kernel_count && k < s->kernel_count; ++k) {
			memcpy(out->kernels[k].name, s->kernels[k].name,
			       sizeof out->kernels[k].name);
			out->kernels[k].name[sizeof out->kernels[k].name - 1] = '\0';
			out->kernels[k].calls = s->kernels[k].calls;
			out->kernels[k].ms[f] = s->kernels[k].ms;
		}
		out->n = f + 1;
	}
	return RS_OK;
}

void bench_progress(const char *fmt, ...)
{
	static double start = -1.0;
	double now = rs_now_ms();
	if (start < 0)
		start = now;
	if (now - start < 2000.0)
		return;
	va_list ap;
	va_start(ap, fmt);
	fputs("raystream-bench: ", stderr);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
}

cJSON *bench_json_summary(struct bench_summary s)
{
	cJSON *o = cJSON_CreateObject();
	cJSON_AddNumberToObject(o, "median", s.median);
	cJSON_AddNumberToObject(o, "min", s.min);
	cJSON_AddNumberToObject(o, "max", s.max);
	return o;
}
