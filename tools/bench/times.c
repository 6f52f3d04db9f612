/*
 * raystream-bench --times (was raystream-glbench): frame times of one render setting per
 * scene, for tuning a backend (the GLES kernels above all): median and min-max of the
 * timed frames after one warm-up frame, fps, Mrays/s (rays counted in one extra counting
 * frame, not timed), the median time of each kernel, and the process CPU time per frame.
 * With --error the warm-up frame, in floats, is compared with the CPU reference tracer's
 * image at the same size, passes and lights (traced primaries and reflections, exact
 * feelers: what correct is), as table 2 compares: an approximation's speed beside its error.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "raystream/rs_image.h"
#include "raystream/rs_renderers.h"
#include "tool_common.h"

/* The chain, and "fused compute" for the fused chain's compute kernels. */
static const char *chain_name(const struct rs_render_desc *d)
{
	return d->chain == RS_CHAIN_PAPER         ? "paper"
	       : d->chain == RS_CHAIN_SEPARATE    ? "separate"
	       : d->kernels == RS_KERNELS_COMPUTE ? "fused compute"
	                                          : "fused";
}

static void print_row(const char *name, const struct rs_render_desc *d,
                      const struct rs_render_stats *s, const struct bench_frames *t, uint64_t rays,
                      double hits)
{
	struct bench_summary wall = bench_summarize(t->wall_ms, t->n);
	struct bench_summary cpu = bench_summarize(t->cpu_ms, t->n);
	char refl[32] = "", nodes[32], inst[32] = "";
	if (d->reflections != RS_REFLECT_TRACE) {
		refl[0] = ' ';
		rs_tool_reflections_name(d, refl + 1, sizeof refl - 1);
	}
	/* an instance mode asked for is named: a two-level row must not read as a flat one */
	if (d->instances != RS_INSTANCES_AUTO) {
		memcpy(inst, " instances ", 11);
		rs_render_desc_get(d, "instances", inst + 11, sizeof inst - 11, NULL);
	}
	printf("%-6s %-6s %ux%u passes %u lights %u %s %s %s%s%s nodes %s storage %s: cpu %.1f ms "
	       "(%.1f-%.1f), wall %.1f ms (%.1f-%.1f) = %.2f fps, %.2f Mrays/s (%llu rays), hit "
	       "numbers %.1f;",
	       name, s->backend, d->width, d->height, d->passes, d->lights, chain_name(d),
	       d->primary == RS_PRIMARY_RASTER ? "raster" : "trace",
	       rs_tool_shadows_name(d->shadows), refl, inst,
	       rs_tool_nodes_name(&d->pack, nodes, sizeof nodes),
	       rs_tool_storage_name(s->scene_storage), cpu.median, cpu.min, cpu.max, wall.median,
	       wall.min, wall.max, 1000.0 / wall.median, (double)rays / (wall.median * 1000.0),
	       (unsigned long long)rays, hits);
	for (uint32_t k = 0; k < t->kernel_count; ++k)
		printf(" %s %.1f", t->kernels[k].name,
		       bench_summarize(t->kernels[k].ms, t->n).median);
	printf("\n  renderer: %s\n", s->renderer);
	fflush(stdout);
}

static cJSON *json_row(const char *name, const struct rs_render_desc *d,
                       const struct rs_render_stats *s, const struct bench_frames *t, uint64_t rays,
                       double hits)
{
	cJSON *row = cJSON_CreateObject();
	char text[64];
	cJSON_AddStringToObject(row, "scene", name);
	cJSON_AddStringToObject(row, "backend", s->backend);
	cJSON_AddStringToObject(row, "renderer", s->renderer);
	static const char *const keys[] = {"size",    "passes",  "lights",   "chain",
	                                   "kernels", "primary", "shadows",  "reflections",
	                                   "bvh",     "nodes",   "instances"};
	for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i)
		if (rs_render_desc_get(d, keys[i], text, sizeof text, NULL) == RS_OK)
			cJSON_AddStringToObject(row, keys[i], text);
	cJSON_AddStringToObject(row, "scene_storage", rs_tool_storage_name(s->scene_storage));
	struct bench_summary wall = bench_summarize(t->wall_ms, t->n);
	cJSON_AddNumberToObject(row, "frames", t->n);
	cJSON_AddItemToObject(row, "wall_ms", bench_json_summary(wall));
	cJSON_AddItemToObject(row, "cpu_ms", bench_json_summary(bench_summarize(t->cpu_ms, t->n)));
	cJSON_AddNumberToObject(row, "fps", 1000.0 / wall.median);
	cJSON_AddNumberToObject(row, "rays", (double)rays);
	cJSON_AddNumberToObject(row, "mrays_per_s", (double)rays / (wall.median * 1000.0));
	cJSON_AddNumberToObject(row, "hit_numbers", hits);
	cJSON *k = cJSON_AddObjectToObject(row, "kernel_ms");
	for (uint32_t i = 0; i < t->kernel_count; ++i)
		cJSON_AddNumberToObject(k, t->kernels[i].name,
		                        bench_summarize(t->kernels[i].ms, t->n).median);
	return row;
}

/* The error of `rgb` (desc's size) against the CPU reference tracer at desc's size, passes,
 * lights, BVH, nodes and triangle test with everything exact: traced primaries and
 * reflections, shadow feelers. Compared as table 2 compares (linear, peak 1, 8/255). */
static enum rs_status reference_error(const struct rs_render_desc *desc,
                                      const struct rs_scene *scene, const float *rgb,
                                      struct rs_image_diff *out, struct rs_error *err)
{
	struct rs_render_desc ref = {.width = desc->width,
	                             .height = desc->height,
	                             .passes = desc->passes,
	                             .lights = desc->lights,
	                             .triangle_test = desc->triangle_test,
	                             .bvh = desc->bvh,
	                             .pack = desc->pack,
	                             .threads = desc->threads,
	                             .instances = desc->instances};
	size_t n = (size_t)desc->width * desc->height * 3;
	float *want = malloc(n * sizeof *want);
	struct rs_renderer *cpu = NULL;
	struct rs_frame frame = {.rgb = want};
	enum rs_status st = want ? rs_renderer_create_cpu(&ref, &cpu, err)
	                         : rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
	if (st == RS_OK)
		st = rs_renderer_set_scene(cpu, scene, err);
	if (st == RS_OK)
		st = rs_renderer_render(cpu, NULL, &frame, err);
	if (st == RS_OK)
		rs_image_compare(rgb, want, desc->width, desc->height, 3, 1.0, 8.0 / 255.0, out);
	rs_renderer_destroy(&cpu);
	free(want);
	return st;
}

static void print_error(const struct rs_image_diff *e)
{
	printf("  error against the CPU reference tracer (trace, trace, rays): %.2f dB PSNR, max "
	       "%.4f, %.3f%% pixels off by > 8/255\n",
	       e->psnr_db, e->max_abs_error, 100.0 * e->bad_share);
	fflush(stdout);
}

static cJSON *json_error(const struct rs_image_diff *e)
{
	cJSON *o = cJSON_CreateObject();
	/* identical images: +INFINITY dB, which JSON cannot spell; null then */
	if (isfinite(e->psnr_db))
		cJSON_AddNumberToObject(o, "psnr_db", e->psnr_db);
	else
		cJSON_AddNullToObject(o, "psnr_db");
	cJSON_AddNumberToObject(o, "max_abs_error", e->max_abs_error);
	cJSON_AddNumberToObject(o, "mean_abs_error", e->mean_abs_error);
	cJSON_AddNumberToObject(o, "bad_share", e->bad_share);
	return o;
}

static int one_scene(const struct bench_options *o, const char *name, struct rs_render_desc desc)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	struct rs_renderer *r = NULL;
	uint8_t *px = malloc((size_t)desc.width * desc.height * 4);
	float *rgb = o->error ? malloc((size_t)desc.width * desc.height * 3 * sizeof *rgb) : NULL;
	static struct bench_frames t;
	struct rs_image_diff e = {0};
	int code = 1;
	if (!px || (o->error && !rgb)) {
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		goto done;
	}
	if (rs_scenegen_load(name, &scene, &err) != RS_OK)
		goto done;
	if (desc.lights > rs_scene_light_count(scene)) {
		rs_error_set(&err, RS_ERR_INVALID, "--lights %u: %s has %zu", desc.lights, name,
		             rs_scene_light_count(scene));
		goto done;
	}
	/* one counting frame for the ray numbers, then the timed frames without counters */
	struct rs_render_desc counting = desc;
	counting.counters = true;
	struct rs_frame frame = {.rgba8 = px};
	if (rs_renderer_open(o->backend, &counting, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		goto done;
	const struct rs_render_stats *s = rs_renderer_stats(r);
	uint64_t rays = s->primary_rays + s->secondary_rays + s->shadow_rays;
	double hits = s->total_per_pixel;
	rs_renderer_destroy(&r);
	/* the warm-up frame in floats where its error is asked for */
	struct rs_frame warm = {.rgb = rgb, .rgba8 = rgb ? NULL : px};
	if (rs_renderer_open(o->backend, &desc, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &warm, &err) != RS_OK ||
	    bench_time_frames(r, &frame, o->repeats, &t, &err) != RS_OK)
		goto done;
	s = rs_renderer_stats(r);
	print_row(name, &desc, s, &t, rays, hits);
	if (rgb && reference_error(&desc, scene, rgb, &e, &err) != RS_OK)
		goto done;
	if (rgb)
		print_error(&e);
	if (o->json) {
		cJSON *row = json_row(name, &desc, s, &t, rays, hits);
		if (rgb)
			cJSON_AddItemToObject(row, "error", json_error(&e));
		cJSON_AddItemToArray(cJSON_GetObjectItem(o->json, "rows"), row);
	}
	code = 0;
done:
	if (code)
		fprintf(stderr, "raystream-bench: %s: %s\n", name, err.message);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
	free(rgb);
	free(px);
	return code;
}

int bench_times(const struct bench_options *o)
{
	struct rs_render_desc desc = o->render;
	desc.width = desc.height = o->size;
	desc.passes = o->passes;
	desc.lights = o->lights;
	desc.threads = o->render.threads;
	int code = 0;
	for (size_t i = 0; i < o->scene_count; ++i) {
		bench_progress("--times: %s (%zu/%zu)", o->scenes[i], i + 1, o->scene_count);
		code |= one_scene(o, o->scenes[i], desc);
	}
	return code;
}
