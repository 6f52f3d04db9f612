/*
 * raystream-bench --table 2: the paper's Table 2 on any render backend, through the render
 * interface: fps and hit numbers for tree BVH 1 pass, raster + BVH 1 pass and raster + BVH
 * 2 passes (plus traced 2 passes, the target setting), with rays per second and where
 * the time goes per kernel, beside the paper's figures. Settings a backend refuses are left
 * out of the table and named once under it. Every image is compared with the CPU double reference
 * of the same setting.
 *
 * Frames are timed on the wall clock around rs_renderer_render() into RGBA8 host memory
 * (what a viewer gets, readback included); hit numbers come from a separate counting frame
 * when the timed frames did not count (counters cost time on GPUs).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "raystream/rs_renderers.h"
#include "table2.h"
#include "tool_common.h"

/* Bae & Hong, Table 2: fps (hit numbers) per setting, in the order of `settings`. */
static const struct paper2_row {
	const char *scene;
	double fps[3], hits[3];
} paper2[BENCH_SCENE_COUNT] = {
    {"box", {443.34, 646.73, 268.77}, {3.056, 0.541, 1.044}},
    {"cow1", {85.71, 153.54, 48.22}, {35.055, 12.846, 26.845}},
    {"cow2", {51.23, 85.62, 30.54}, {47.079, 18.660, 39.998}},
    {"cow5", {32.48, 37.43, 16.93}, {87.545, 36.332, 138.311}},
    {"cow9", {18.42, 22.63, 10.50}, {160.157, 69.270, 238.444}},
    {"cow17", {12.24, 14.53, 7.31}, {248.820, 99.822, 361.564}},
};

/* 0 and 3 are the traced settings the peer runs beside (t2_traced()) */
const struct t2_setting t2_settings[T2_SETTINGS] = {
    {"tree BVH, 1 pass", RS_PRIMARY_TRACE, 1, 0},
    {"raster + BVH, 1 pass", RS_PRIMARY_RASTER, 1, 1},
    {"raster + BVH, 2 passes", RS_PRIMARY_RASTER, 2, 2},
    {"tree BVH, 2 passes", RS_PRIMARY_TRACE, 2, -1},
};

static struct t2_scene results[BENCH_SCENE_COUNT];

static const char *builder_name(enum rs_bvh_builder b)
{
	return b == RS_BVH_NONE     ? "none"
	       : b == RS_BVH_LINEAR ? "linear"
	       : b == RS_BVH_PAPER  ? "paper"
	                            : "sah";
}

struct rs_render_desc t2_desc(const struct bench_options *o, enum rs_primary_mode primary,
                              uint32_t passes)
{
	return (struct rs_render_desc){.width = o->size,
	                               .height = o->size,
	                               .passes = passes,
	                               .lights = o->lights,
	                               .primary = primary,
	                               .shadows = RS_SHADOW_RAYS,
	                               .bvh = {.builder = o->builder},
	                               .pack = o->pack,
	                               .scene_storage = o->storage,
	                               .kernels = o->kernels,
	                               .threads = o->threads};
}

/* The CPU double reference of one pass count (what every image is compared with). */
static int reference(const struct bench_options *o, const struct rs_scene *scene, uint32_t passes,
                     float *rgb, struct rs_render_stats *out_stats)
{
	struct rs_render_desc d = t2_desc(o, RS_PRIMARY_TRACE, passes);
	struct rs_renderer *r = NULL;
	struct rs_error err = {0};
	struct rs_frame frame = {.rgb = rgb};
	if (rs_renderer_create_cpu(&d, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &frame, &err) != RS_OK) {
		fprintf(stderr, "raystream-bench: reference: %s\n", err.message);
		rs_renderer_destroy(&r);
		return 1;
	}
	*out_stats = *rs_renderer_stats(r);
	rs_renderer_destroy(&r);
	return 0;
}

static uint64_t rays_of(const struct rs_render_stats *s)
{
	return s->primary_rays + s->secondary_rays + s->shadow_rays;
}

/* Rays per frame for Mrays/s: the backend's own counts, unless it reports no secondary or
 * shadow rays where the reference (the same work when the images agree) has some; then
 * the counting frame's, else the reference's, and the table says which. */
static void choose_rays(struct t2_result *r, const struct rs_render_stats *counted,
                        const struct rs_render_stats *ref)
{
	r->rays_stats = r->stats;
	r->rays_from = "";
	bool partial = r->stats.secondary_rays + r->stats.shadow_rays == 0 &&
	               ref->secondary_rays + ref->shadow_rays > 0;
	if (partial && counted && counted->secondary_rays + counted->shadow_rays > 0) {
		r->rays_stats = *counted;
		r->rays_from = " (counting frame's)";
	} else if (partial) {
		r->rays_stats = *ref;
		r->rays_from = " (reference's: the backend reports none)";
	}
	r->rays = rays_of(&r->rays_stats);
}

enum rs_status t2_open(const char *backend, const struct rs_render_desc *d,
                       const struct rs_scene *scene, struct rs_renderer **out, struct rs_error *err)
{
	enum rs_status s = rs_renderer_open(backend, d, out, err);
	if (s == RS_OK)
		s = rs_renderer_set_scene(*out, scene, err);
	if (s != RS_OK)
		rs_renderer_destroy(out);
	return s;
}

/* Hit numbers of one counting frame, when the backend can count. */
static int count_hits(const struct bench_options *o, const struct rs_scene *scene,
                      const struct t2_setting *set, struct t2_result *r,
                      struct rs_render_stats *out_counted)
{
	struct rs_render_desc d = t2_desc(o, set->primary, set->passes);
	d.counters = true;
	struct rs_renderer *rn = NULL;
	struct rs_error err = {0};
	enum rs_status s = t2_open(o->backend, &d, scene, &rn, &err);
	struct rs_frame frame = {.rgba8 = r->rgba8};
	if (s == RS_OK)
		s = rs_renderer_render(rn, NULL, &frame, &err);
	if (s == RS_OK && rs_renderer_stats(rn)->counters_valid) {
		r->hits = rs_renderer_stats(rn)->total_per_pixel;
		r->hits_valid = true;
		*out_counted = *rs_renderer_stats(rn);
	}
	rs_renderer_destroy(&rn);
	if (s != RS_OK && s != RS_ERR_UNSUPPORTED) {
		fprintf(stderr, "raystream-bench: %s, %s, counting: %s\n", o->backend, set->name,
		        err.message);
		return 1;
	}
	return 0;
}

static int run_setting(const struct bench_options *o, const struct rs_scene *scene,
                       const struct t2_setting *set, const float *ref,
                       const struct rs_render_stats *ref_stats, struct t2_result *r, char *renderer,
                       size_t renderer_cap)
{
	struct rs_render_desc d = t2_desc(o, set->primary, set->passes);
	struct rs_renderer *rn = NULL;
	struct rs_error err = {0};
	enum rs_status s = t2_open(o->backend, &d, scene, &rn, &err);
	if (s == RS_ERR_UNSUPPORTED) {
		r->refused = true;
		snprintf(r->why, sizeof r->why, "%s", err.message);
		return 0;
	}
	/* A warm-up frame in floats, compared with the reference (shaders compile, caches
	 * fill), then the timed frames into RGBA8. */
	struct rs_frame warm = {.rgb = r->rgb};
	if (s == RS_OK)
		s = rs_renderer_render(rn, NULL, &warm, &err);
	if (s == RS_OK) {
		rs_image_compare(r->rgb, ref, o->size, o->size, 3, 1.0, 8.0 / 255.0, &r->diff);
		snprintf(renderer, renderer_cap, "%s", rs_renderer_stats(rn)->renderer);
	}
	struct rs_frame frame = {.rgba8 = r->rgba8};
	if (s == RS_OK)
		s = bench_time_frames(rn, &frame, o->repeats, &r->frames, &err);
	if (s != RS_OK) {
		fprintf(stderr, "raystream-bench: %s, %s: %s\n", o->backend, set->name,
		        err.message);
		rs_renderer_destroy(&rn);
		return 1;
	}
	r->stats = *rs_renderer_stats(rn);
	rs_renderer_destroy(&rn);
	r->hits = r->stats.total_per_pixel;
	r->hits_valid = r->stats.counters_valid;
	struct bench_summary wall = bench_summarize(r->frames.wall_ms, r->frames.n);
	r->ms_median = wall.median;
	r->ms_min = wall.min;
	r->ms_max = wall.max;
	struct rs_render_stats counted = {0};
	int code = r->hits_valid ? 0 : count_hits(o, scene, set, r, &counted);
	choose_rays(r, counted.pixels ? &counted : NULL, ref_stats);
	return code;
}

static void print_row(const struct bench_options *o, const struct t2_scene *sc, int si)
{
	const struct t2_setting *set = &t2_settings[si];
	const struct t2_result *r = &sc->settings[si];
	const struct paper2_row *p = &paper2[sc->paper_index];
	char paper[40] = "-";
	if (set->paper >= 0)
		snprintf(paper, sizeof paper, "%.2f (%.3f)", p->fps[set->paper],
		         p->hits[set->paper]);
	if (r->refused) /* left out here; named once under the table (print_refused) */
		return;
	char hits[24] = "n/a";
	if (r->hits_valid)
		snprintf(hits, sizeof hits, "%.3f", r->hits);
	double mrays = (double)r->rays / (r->ms_median * 1e3);
	printf("| %-5s | %s | %.1f (%.1f–%.1f) | %.2f | %s | %.2f | %llu + %llu + %llu%s | %.1f "
	       "dB, %.3f%%, %s | %s |\n",
	       sc->name, set->name, r->ms_median, r->ms_min, r->ms_max, 1e3 / r->ms_median, hits,
	       mrays, (unsigned long long)r->rays_stats.primary_rays,
	       (unsigned long long)r->rays_stats.secondary_rays,
	       (unsigned long long)r->rays_stats.shadow_rays, r->rays_from, r->diff.psnr_db,
	       100.0 * r->diff.bad_share, t2_verdict(&r->diff), paper);
	(void)o;
}

/* Settings the backend cannot render (the CPU backend traces primary rays only): one line
 * under the table instead of a row per scene. */
static void print_refused(const struct bench_options *o, uint32_t scenes)
{
	const char *why = NULL;
	for (int si = 0; si < T2_SETTINGS; ++si)
		for (uint32_t i = 0; i < scenes; ++i)
			if (results[i].settings[si].refused) {
				printf("%s%s", why ? "; " : "\nLeft out on this backend: ",
				       t2_settings[si].name);
				why = results[i].settings[si].why;
				break;
			}
	if (why)
		printf(" (%s: %s)\n", o->backend, why);
}

static cJSON *json_row(const struct t2_scene *sc, int si)
{
	const struct t2_setting *set = &t2_settings[si];
	const struct t2_result *r = &sc->settings[si];
	cJSON *row = cJSON_CreateObject();
	cJSON_AddStringToObject(row, "scene", sc->name);
	cJSON_AddStringToObject(row, "setting", set->name);
	if (set->paper >= 0) {
		cJSON_AddNumberToObject(row, "paper_fps", paper2[sc->paper_index].fps[set->paper]);
		cJSON_AddNumberToObject(row, "paper_hit_numbers",
		                        paper2[sc->paper_index].hits[set->paper]);
	}
	if (r->refused) {
		cJSON_AddStringToObject(row, "refused", r->why);
		return row;
	}
	cJSON_AddItemToObject(row, "wall_ms",
	                      bench_json_summary(bench_summarize(r->frames.wall_ms, r->frames.n)));
	cJSON_AddNumberToObject(row, "fps", 1e3 / r->ms_median);
	if (r->hits_valid)
		cJSON_AddNumberToObject(row, "hit_numbers", r->hits);
	cJSON_AddNumberToObject(row, "rays", (double)r->rays);
	cJSON_AddNumberToObject(row, "mrays_per_s", (double)r->rays / (r->ms_median * 1e3));
	cJSON_AddNumberToObject(row, "psnr_db", r->diff.psnr_db);
	cJSON_AddNumberToObject(row, "bad_share", r->diff.bad_share);
	cJSON_AddStringToObject(row, "verdict", t2_verdict(&r->diff));
	cJSON_AddStringToObject(row, "renderer", r->stats.renderer);
	return row;
}

static void print_kernels(const struct bench_options *o, uint32_t scenes)
{
	printf("\nWhere the time goes, ms per frame, median (min–max) over %u frames "
	       "(the CPU backend has one fused kernel: the whole render)\n\n",
	       o->repeats);
	printf("| scene | setting | kernel | calls | ms | share of frame |\n"
	       "|---|---|---|---:|---:|---:|\n");
	for (uint32_t i = 0; i < scenes; ++i) {
		for (int si = 0; si < T2_SETTINGS; ++si) {
			struct t2_result *r = &results[i].settings[si];
			if (r->refused)
				continue;
			const struct bench_frames *f = &r->frames;
			uint32_t n = f->kernel_count;
			for (uint32_t k = 0; k <= n + 1; ++k) {
				const double *v = k < n    ? f->kernels[k].ms
				                  : k == n ? f->render_ms
				                           : f->readback_ms;
				const char *name = k < n    ? f->kernels[k].name
				                   : k == n ? "render (total)"
				                            : "readback";
				struct bench_summary m = bench_summarize(v, f->n);
				printf("| %-5s | %s | %s | %u | %.2f (%.2f–%.2f) | %.0f%% |\n",
				       results[i].name, t2_settings[si].name, name,
				       k < n ? f->kernels[k].calls : 1u, m.median, m.min, m.max,
				       100.0 * m.median / r->ms_median);
			}
		}
	}
}

static void print_load(const char *when)
{
	double load[3];
	if (getloadavg(load, 3) == 3)
		printf("load average %s: %.2f %.2f %.2f\n", when, load[0], load[1], load[2]);
}

int bench_table2(const struct bench_options *o)
{
	size_t px = (size_t)o->size * o->size;
	float *ref[3] = {NULL, malloc(px * 3 * sizeof(float)), malloc(px * 3 * sizeof(float))};
	float *rgb = malloc(px * 3 * sizeof(float));
	uint8_t *rgba8 = malloc(px * 4);
	if (!ref[1] || !ref[2] || !rgb || !rgba8) {
		fprintf(stderr, "raystream-bench: out of memory for %ux%u images\n", o->size,
		        o->size);
		return 1;
	}
	char renderer[sizeof results[0].settings[0].stats.renderer] = "";
	printf("Table 2 on backend %s, %ux%u, %u light(s), %s BVH, exact shadow rays, %u CPU "
	       "thread(s), median (min–max) of %u frames\n",
	       o->backend, o->size, o->size, o->lights, builder_name(o->builder), o->threads,
	       o->repeats);
	print_load("at start");
	printf("\n| scene | setting | ms per frame | fps | hit numbers | Mrays/s | rays: primary + "
	       "secondary + shadow | vs CPU reference: PSNR, pixels off > 8/255 | paper: fps "
	       "(hit numbers) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
	int code = 0;
	uint32_t scenes = 0;
	for (int i = 0; i < BENCH_SCENE_COUNT && code == 0; ++i) {
		if (o->only && strcmp(o->only, bench_scenes[i]) != 0)
			continue;
		struct t2_scene *sc = &results[scenes];
		struct rs_error err = {0};
		*sc = (struct t2_scene){.name = bench_scenes[i], .paper_index = i};
		if (rs_scenegen_load(sc->name, &sc->scene, &err) != RS_OK) {
			fprintf(stderr, "raystream-bench: %s\n", err.message);
			code = 1;
			break;
		}
		sc->triangles = rs_scene_triangle_count(sc->scene);
		code = reference(o, sc->scene, 1, ref[1], &sc->reference[1]) ||
		       reference(o, sc->scene, 2, ref[2], &sc->reference[2]);
		for (int si = 0; si < T2_SETTINGS && code == 0; ++si) {
			bench_progress("table 2: %s, %s", sc->name, t2_settings[si].name);
			struct t2_result *r = &sc->settings[si];
			r->rgb = rgb;
			r->rgba8 = rgba8;
			code = run_setting(
			    o, sc->scene, &t2_settings[si], ref[t2_settings[si].passes],
			    &sc->reference[t2_settings[si].passes], r, renderer, sizeof renderer);
			if (code == 0)
				print_row(o, sc, si);
			if (code == 0 && o->json)
				cJSON_AddItemToArray(cJSON_GetObjectItem(o->json, "rows"),
				                     json_row(sc, si));
			fflush(stdout);
		}
		if (code == 0 && o->peer) {
			bench_progress("table 2: %s, the peer", sc->name);
			code = t2_peer_scene(o, sc, ref);
		}
		++scenes;
	}
	if (code == 0) {
		print_refused(o, scenes);
		char nodes[32], kernels[16];
		rs_render_desc_get(&(struct rs_render_desc){.kernels = o->kernels}, "kernels",
		                   kernels, sizeof kernels, NULL);
		printf("\nrenderer: %s; BVH nodes %s; scene storage %s; kernels %s\n", renderer,
		       rs_tool_nodes_name(&o->pack, nodes, sizeof nodes),
		       rs_tool_storage_name(results[0].settings[0].stats.scene_storage), kernels);
		print_kernels(o, scenes);
		if (o->peer)
			t2_peer_print(o, results, scenes);
		printf("\n");
		print_load("at end");
	}
	for (uint32_t i = 0; i < scenes; ++i)
		rs_scene_destroy(&results[i].scene);
	free(ref[1]);
	free(ref[2]);
	free(rgb);
	free(rgba8);
	return code;
}
