/*
 * raystream-bench --animate N SCENE...: what moving a scene costs per frame. For each frame
 * 1..N of a scene that moves (animated, cowN, cowNi), one renderer takes it by
 * rs_renderer_update_vertices() (refit or rebuild, repack, upload of the changed rows; cowNi
 * by rs_renderer_update_instances(), which takes that path on backends without a two-level
 * update) and
 * a second by a full rs_renderer_set_scene() (build, pack, upload, kernels); the two are
 * timed alternately, frame by frame, in the same window, so load changes hit both alike.
 * Scenes are made before the clock starts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"
#include "tool_common.h"

#define MAX_ANIMATE 240u

struct animate_figures {
	double update_ms[MAX_ANIMATE], refit_ms[MAX_ANIMATE], pack_ms[MAX_ANIMATE];
	double upload_ms[MAX_ANIMATE], set_ms[MAX_ANIMATE], bytes[MAX_ANIMATE];
	uint32_t rebuilds;
	uint64_t full_bytes;
};

static enum rs_status open_two(const struct bench_options *o, struct rs_renderer *r[2],
                               struct rs_error *err)
{
	struct rs_render_desc d = o->render;
	d.width = d.height = o->size;
	enum rs_status st = rs_renderer_open(o->backend, &d, &r[0], err);
	if (st == RS_OK)
		st = rs_renderer_open(o->backend, &d, &r[1], err);
	return st;
}

static enum rs_status run_scene(const struct bench_options *o, const char *name,
                                struct rs_renderer *r[2], struct animate_figures *f,
                                struct rs_error *err)
{
	struct rs_scene *cur = NULL, *next = NULL;
	enum rs_status st = rs_scenegen_load_frame(name, 0, 0, &cur, err);
	for (int i = 0; st == RS_OK && i < 2; ++i)
		st = rs_renderer_set_scene(r[i], cur, err);
	if (st == RS_OK)
		f->full_bytes = rs_renderer_stats(r[0])->upload_bytes;
	for (uint32_t k = 0; st == RS_OK && k < o->animate; ++k) {
		st = rs_scenegen_load_frame(name, k + 1, 0, &next, err);
		double t0 = rs_now_ms();
		/* an instanced herd (cowNi) moves by its instance transforms */
		if (st == RS_OK)
			st = rs_scene_instance_count(next)
			         ? rs_renderer_update_instances(r[0], next, err)
			         : rs_renderer_update_vertices(r[0], next, err);
		double t1 = rs_now_ms();
		if (st == RS_OK)
			st = rs_renderer_set_scene(r[1], next, err);
		double t2 = rs_now_ms();
		if (st != RS_OK)
			break;
		const struct rs_render_stats *s = rs_renderer_stats(r[0]);
		f->update_ms[k] = t1 - t0;
		f->set_ms[k] = t2 - t1;
		f->refit_ms[k] = s->update_rebuilt ? s->build_ms : s->refit_ms;
		f->pack_ms[k] = s->pack_ms;
		f->upload_ms[k] = s->upload_ms;
		f->bytes[k] = (double)s->upload_bytes;
		f->rebuilds += s->update_rebuilt;
		rs_scene_destroy(&cur);
		cur = next;
		next = NULL;
		bench_progress("--animate %s: frame %u of %u", name, k + 1, o->animate);
	}
	/* both renderers hold `cur`: it goes only after them (the caller destroys them) */
	rs_renderer_destroy(&r[0]);
	rs_renderer_destroy(&r[1]);
	rs_scene_destroy(&cur);
	rs_scene_destroy(&next);
	return st;
}

static void report(const struct bench_options *o, const char *name, const char *renderer,
                   const struct animate_figures *f)
{
	uint32_t n = o->animate;
	struct bench_summary up = bench_summarize(f->update_ms, n);
	struct bench_summary set = bench_summarize(f->set_ms, n);
	struct bench_summary bytes = bench_summarize(f->bytes, n);
	double refit = bench_summarize(f->refit_ms, n).median;
	double pack = bench_summarize(f->pack_ms, n).median;
	double upload = bench_summarize(f->upload_ms, n).median;
	printf("%-8s %-6s %u frames: update %.2f ms (%.2f-%.2f; refit/build %.2f + pack %.2f + "
	       "upload %.2f), %u rebuilt; set_scene %.2f ms (%.2f-%.2f): %.1fx",
	       name, o->backend, n, up.median, up.min, up.max, refit, pack, upload, f->rebuilds,
	       set.median, set.min, set.max, set.median / up.median);
	if (f->full_bytes) /* the CPU backend uploads nothing */
		printf("; uploaded %.0f of %llu bytes (median, %.1f%%)", bytes.median,
		       (unsigned long long)f->full_bytes,
		       100.0 * bytes.median / (double)f->full_bytes);
	printf("\n  renderer: %s\n", renderer);
	fflush(stdout);
	if (!o->json)
		return;
	cJSON *row = cJSON_CreateObject();
	cJSON_AddStringToObject(row, "scene", name);
	cJSON_AddStringToObject(row, "backend", o->backend);
	cJSON_AddStringToObject(row, "renderer", renderer);
	cJSON_AddNumberToObject(row, "frames", n);
	cJSON_AddItemToObject(row, "update_ms", bench_json_summary(up));
	cJSON_AddItemToObject(row, "set_scene_ms", bench_json_summary(set));
	cJSON_AddItemToObject(row, "upload_bytes", bench_json_summary(bytes));
	cJSON_AddNumberToObject(row, "full_bytes", (double)f->full_bytes);
	cJSON_AddNumberToObject(row, "rebuilds", f->rebuilds);
	cJSON_AddItemToArray(cJSON_GetObjectItem(o->json, "rows"), row);
}

int bench_animate(const struct bench_options *o)
{
	const struct rs_cli cli = {.prog = "raystream-bench"};
	struct rs_error err = {0};
	if (o->animate > MAX_ANIMATE) {
		rs_error_set(&err, RS_ERR_INVALID, "--animate: %u frames (at most %u)", o->animate,
		             MAX_ANIMATE);
		return rs_cli_fail(&cli, &err);
	}
	for (size_t i = 0; i < o->scene_count; ++i) {
		if (!rs_scenegen_moves(o->scenes[i])) {
			rs_error_set(&err, RS_ERR_INVALID,
			             "--animate: scene '%s' does not move (animated, cowN, cowNi)",
			             o->scenes[i]);
			return rs_cli_fail(&cli, &err);
		}
		struct rs_renderer *r[2] = {NULL, NULL};
		struct animate_figures *f = calloc(1, sizeof *f);
		char renderer[128] = "";
		enum rs_status st = f ? open_two(o, r, &err)
		                      : rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		if (st == RS_OK)
			snprintf(renderer, sizeof renderer, "%s",
			         rs_renderer_stats(r[0])->renderer);
		if (st == RS_OK)
			st = run_scene(o, o->scenes[i], r, f, &err);
		rs_renderer_destroy(&r[0]);
		rs_renderer_destroy(&r[1]);
		if (st == RS_OK)
			report(o, o->scenes[i], renderer, f);
		free(f);
		if (st != RS_OK)
			return rs_cli_fail(&cli, &err);
	}
	return 0;
}
