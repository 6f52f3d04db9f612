/* raystream-report's files: the CSV, the Markdown table with the Pareto front and the
 * pick per error budget, and the gnuplot plot of time against error. Every file goes
 * through a temporary and a rename, so a reader never sees half of one. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "report.h"
#include "tool_common.h"

const double report_budgets[] = {0.0, 0.001, 0.01, 0.05, 0.20};
const uint32_t report_budget_count = sizeof report_budgets / sizeof report_budgets[0];

struct text {
	char *s;
	size_t len, cap;
	bool failed;
};

static void put(struct text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(struct text *t, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	if (t->failed || n < 0)
		return;
	if (t->len + (size_t)n + 1 > t->cap) {
		size_t cap = (t->cap ? t->cap * 2 : 4096) + (size_t)n;
		char *s = realloc(t->s, cap);
		if (!s) {
			t->failed = true;
			return;
		}
		t->s = s;
		t->cap = cap;
	}
	va_start(ap, fmt);
	vsnprintf(t->s + t->len, (size_t)n + 1, fmt, ap);
	va_end(ap);
	t->len += (size_t)n;
}

static const char *bvh_name(enum rs_bvh_builder b)
{
	return b == RS_BVH_SAH      ? "sah"
	       : b == RS_BVH_PAPER  ? "paper"
	       : b == RS_BVH_LINEAR ? "linear"
	                            : "none";
}

static enum rs_status save(const char *dir, const char *name, struct text *t, struct rs_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	enum rs_status st = t->failed
	                        ? rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory for %s", path)
	                        : rs_tool_write_text(path, t->s ? t->s : "", err);
	if (st == RS_OK)
		rs_cli_wrote(path);
	free(t->s);
	*t = (struct text){0};
	return st;
}

static void csv(const struct report *rep, struct text *t)
{
	put(t, "setting,backend,primary,shadows,shadow_map,shadow_filter,passes,bvh,triangle_test,"
	       "reflections,"
	       "ms_median,ms_min,ms_max,cpu_ms_median,psnr_db,mean_abs_error,max_abs_error,"
	       "share_off_8,pareto\n");
	for (uint32_t i = 0; i < rep->count; ++i) {
		const struct report_row *r = &rep->rows[i];
		const struct rs_render_desc *d = &r->desc;
		bool map = d->shadows == RS_SHADOW_MAP;
		char refl[32];
		if (r->refused) {
			put(t,
			    "%s,%s,%s,%s,%u,%u,%u,%s,%s,%s,refused,refused,refused,refused,"
			    "refused,refused,refused,refused,0\n",
			    r->label, r->backend,
			    d->primary == RS_PRIMARY_RASTER ? "raster" : "trace",
			    rs_tool_shadows_name(d->shadows), map ? d->shadow_map_size : 0,
			    map ? d->shadow_filter : 0, d->passes, bvh_name(d->bvh.builder),
			    d->triangle_test == RS_TRIANGLE_MOLLER_TRUMBORE ? "moller"
			                                                    : "watertight",
			    rs_tool_reflections_name(d, refl, sizeof refl));
			continue;
		}
		put(t, "%s,%s,%s,%s,%u,%u,%u,%s,%s,%s,%.3f,%.3f,%.3f,%.3f,%.4f,%.6g,%.6g,%.6g,%d\n",
		    r->label, r->backend, d->primary == RS_PRIMARY_RASTER ? "raster" : "trace",
		    rs_tool_shadows_name(d->shadows), map ? d->shadow_map_size : 0,
		    map ? d->shadow_filter : 0, d->passes, bvh_name(d->bvh.builder),
		    d->triangle_test == RS_TRIANGLE_MOLLER_TRUMBORE ? "moller" : "watertight",
		    rs_tool_reflections_name(d, refl, sizeof refl), r->ms_med, r->ms_min, r->ms_max,
		    r->cpu_med, r->diff.psnr_db, r->diff.mean_abs_error, r->diff.max_abs_error,
		    r->diff.bad_share, r->front);
	}
}

static void markdown(const struct report *rep, struct text *t)
{
	put(t, "# Speed against error: %s, %ux%u\n\n", rep->scene, rep->size, rep->size);
	put(t,
	    "Machine: %s; load average %.2f at the start. Renderer: %s. Times: wall ms of "
	    "one frame with readback, median (min-max) of %u after a warm-up frame; CPU ms: "
	    "process CPU time per frame, all threads. Error against the CPU double reference "
	    "(%u passes, exact shadow feelers, %u light(s), SAH, watertight).\n\n",
	    rep->machine, rep->load1, rep->renderer, rep->frames, rep->max_passes, rep->lights);
	put(t,
	    "| setting | ms | min-max | CPU ms | PSNR dB | mean abs | max abs | off > 8/255 "
	    "| Pareto (%s ms) |\n|---|---:|---:|---:|---:|---:|---:|---:|:-:|\n",
	    rep->by_cpu ? "CPU" : "wall");
	for (uint32_t i = 0; i < rep->count; ++i) {
		const struct report_row *r = &rep->rows[i];
		if (r->refused) {
			put(t, "| %s | refused: %s | | | | | | | |\n", r->label, r->why);
			continue;
		}
		put(t, "| %s | %.1f | %.1f-%.1f | %.1f | %.2f | %.5f | %.4f | %.3f %% | %s |\n",
		    r->label, r->ms_med, r->ms_min, r->ms_max, r->cpu_med, r->diff.psnr_db,
		    r->diff.mean_abs_error, r->diff.max_abs_error, 100.0 * r->diff.bad_share,
		    r->front ? "yes" : "");
	}
	if (rep->diffs) {
		put(t, "\nDifference images (|setting - reference| x 8 per channel: 8/255 off "
		       "shows as "
		       "64/255):\n\n");
		for (uint32_t i = 0; i < rep->count; ++i)
			if (!rep->rows[i].refused)
				put(t, "- `diff-%02u.png`: %s\n", i, rep->rows[i].label);
	}
	struct rs_report_point pts[REPORT_MAX_ROWS];
	for (uint32_t i = 0; i < rep->count; ++i)
		pts[i] = (struct rs_report_point){report_time(rep, &rep->rows[i]),
		                                  rep->rows[i].diff.bad_share};
	put(t,
	    "\nWhat to pick for an error budget (share of pixels off by more than 8/255): "
	    "the fastest setting within it (by %s ms).\n\n| budget | pick | ms | off > 8/255 |\n"
	    "|---:|---|---:|---:|\n",
	    rep->by_cpu ? "process CPU" : "wall");
	for (uint32_t b = 0; b < report_budget_count; ++b) {
		size_t i;
		if (rs_report_pick(pts, rep->count, report_budgets[b], &i))
			put(t, "| %.1f %% | %s | %.1f | %.3f %% |\n", 100.0 * report_budgets[b],
			    rep->rows[i].label, report_time(rep, &rep->rows[i]),
			    100.0 * rep->rows[i].diff.bad_share);
		else
			put(t, "| %.1f %% | none meets it | | |\n", 100.0 * report_budgets[b]);
	}
}

/* gnuplot draws into a temporary; it becomes report.png only when gnuplot succeeded. */
static enum rs_status plot(const struct report *rep, const char *dir, struct rs_error *err)
{
	char path[4096], tmp[4200];
	snprintf(path, sizeof path, "%s/report.png", dir);
	snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
	if (strchr(tmp, '\'') || strchr(tmp, '\n'))
		return rs_error_set(err, RS_ERR_INVALID, "%s: quotes in the path", dir);
	FILE *gp = popen("gnuplot 2>&1", "w");
	if (!gp)
		return rs_error_set(err, RS_ERR_IO, "cannot run gnuplot (install gnuplot-nox)");
	char title[200];
	snprintf(title, sizeof title, "%s %ux%u, %s", rep->scene, rep->size, rep->size,
	         rep->renderer);
	for (char *c = title; *c; ++c)
		*c = *c == '\'' || *c == '"' ? ' ' : *c;
	fprintf(gp,
	        "set terminal pngcairo size 1100,750 noenhanced font ',10'\n"
	        "set output '%s'\nset title '%s'\nset logscale x\nset grid\n"
	        "set xlabel '%s ms per frame (median, log scale)'\n"
	        "set ylabel 'pixels off by more than 8/255, %%'\nset key top right\n"
	        "$all << EOD\n",
	        tmp, title, rep->by_cpu ? "process CPU" : "wall");
	const struct report_row *order[REPORT_MAX_ROWS];
	uint32_t shown = 0;
	for (uint32_t i = 0; i < rep->count; ++i) {
		const struct report_row *r = &rep->rows[i];
		if (r->refused)
			continue;
		order[shown++] = r;
		fprintf(gp, "%.6g %.6g \"%s\"\n", report_time(rep, r), 100.0 * r->diff.bad_share,
		        r->label);
	}
	fprintf(gp, "EOD\n$front << EOD\n");
	for (uint32_t i = 1; i < shown; ++i) /* by time, for the front's line */
		for (uint32_t j = i;
		     j > 0 && report_time(rep, order[j]) < report_time(rep, order[j - 1]); --j) {
			const struct report_row *t = order[j];
			order[j] = order[j - 1];
			order[j - 1] = t;
		}
	for (uint32_t i = 0; i < shown; ++i)
		if (order[i]->front)
			fprintf(gp, "%.6g %.6g\n", report_time(rep, order[i]),
			        100.0 * order[i]->diff.bad_share);
	fprintf(gp, "EOD\nplot $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb "
	            "'#d62728' title 'Pareto front', $all using 1:2 with points pt 7 ps 1.1 lc "
	            "rgb '#1f77b4' title 'setting', $all using 1:2:3 with labels left offset "
	            "0.8,0.4 font ',8' notitle\n");
	int rc = pclose(gp);
	FILE *f = rc == 0 ? fopen(tmp, "rb") : NULL;
	unsigned char magic[8] = {0};
	bool png = f && fread(magic, 1, 8, f) == 8 && !memcmp(magic, "\x89PNG\r\n\x1a\n", 8);
	if (f)
		fclose(f);
	if (!png || rename(tmp, path) != 0) {
		remove(tmp);
		return rs_error_set(err, RS_ERR_IO, "gnuplot could not write %s (exit %d)", path,
		                    rc);
	}
	rs_cli_wrote(path);
	return RS_OK;
}

enum rs_status report_write(const struct report *rep, const char *dir, bool with_plot,
                            struct rs_error *err)
{
	struct text t = {0};
	csv(rep, &t);
	enum rs_status st = save(dir, "report.csv", &t, err);
	if (st == RS_OK) {
		markdown(rep, &t);
		st = save(dir, "report.md", &t, err);
	}
	if (st == RS_OK && with_plot)
		st = plot(rep, dir, err);
	return st;
}
