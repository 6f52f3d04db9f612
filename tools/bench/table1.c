/*
 * raystream-bench --table 1: the paper's Table 1 for this project. Hit numbers (mean box +
 * triangle tests per pixel over all rays of the pixel, 2 passes) per scene and builder beside
 * the paper's figures, the two triangle tests' speed against error, and BVH build times
 * (median of several builds).
 *
 * Hit numbers are means per pixel, so the flat builders, whose cost grows with the triangle
 * count, may be measured on a coarser image of the same camera (--flat-size): the mean is
 * the same in expectation, and the table says which size was used.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "raystream/rs_render.h"
#include "tool_common.h"

/* Bae & Hong, Table 1 (hit numbers, 2 passes); 0 = "overload" (not measured). */
static const struct paper_row {
	const char *scene;
	double none, linear, tree;
} paper[] = {
    {"box", 174.652, 24.315, 3.407},     {"cow1", 12937.57, 1615.989, 49.053},
    {"cow2", 26524.78, 3211.53, 68.417}, {"cow5", 0, 8007.67, 138.311},
    {"cow9", 0, 14018.847, 238.444},     {"cow17", 0, 20760.26, 361.564},
};
static const enum rs_bvh_builder builders[] = {RS_BVH_NONE, RS_BVH_LINEAR, RS_BVH_PAPER,
                                               RS_BVH_SAH};

/* Stats of one frame on the CPU reference with `desc` (the BVH is built again inside). */
/* The paper's hit numbers count the paper's layout (three float texels, one order) unless
 * --nodes asks for another. */
static struct rs_pack_desc table1_pack(const struct bench_options *o)
{
	struct rs_pack_desc layout = {.nodes = RS_PACK_NODES_PAPER,
	                              .orders = RS_PACK_ORDERS_SINGLE};
	return o->pack_set ? o->pack : layout;
}

static enum rs_status render_cpu(const struct rs_scene *scene, const struct rs_render_desc *desc,
                                 struct rs_render_stats *out_stats, struct rs_error *err)
{
	struct rs_renderer *renderer = NULL;
	struct rs_frame frame = {0}; /* counts only: no image wanted */
	enum rs_status status = rs_renderer_create_cpu(desc, &renderer, err);
	if (status == RS_OK)
		status = rs_renderer_set_scene(renderer, scene, err);
	if (status == RS_OK)
		status = rs_renderer_render(renderer, NULL, &frame, err);
	if (status == RS_OK)
		*out_stats = *rs_renderer_stats(renderer);
	rs_renderer_destroy(&renderer);
	return status;
}

static void print_paper(double v)
{
	if (v > 0)
		printf(" %10.3f |", v);
	else
		printf(" %10s |", "overload");
}

static int bench_scene(const struct bench_options *o, const struct paper_row *row, double *build_ms)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	if (rs_scenegen_load(row->scene, &scene, &err) != RS_OK) {
		fprintf(stderr, "raystream-bench: %s\n", err.message);
		return 1;
	}
	size_t tris = rs_scene_triangle_count(scene);
	double hits[4], box[4];
	uint32_t sizes[4];
	for (int b = 0; b < 4; ++b) {
		struct rs_bvh_desc desc = {.builder = builders[b]};
		double times[32];
		struct rs_render_accel accel;
		for (uint32_t r = 0; r < o->repeats; ++r) {
			if (rs_render_accel_build(scene, &desc, NULL, &accel, &err) != RS_OK) {
				fprintf(stderr, "raystream-bench: %s\n", err.message);
				rs_scene_destroy(&scene);
				return 1;
			}
			times[r] = accel.build_ms;
			if (r + 1 < o->repeats)
				rs_render_accel_free(&accel);
		}
		build_ms[b] = rs_tool_median(times, o->repeats);
		hits[b] = box[b] = NAN;
		sizes[b] = builders[b] == RS_BVH_NONE || builders[b] == RS_BVH_LINEAR ? o->flat_size
		                                                                      : o->size;
		if (builders[b] == RS_BVH_NONE && tris > o->none_max_tris) {
			rs_render_accel_free(&accel);
			continue;
		}
		rs_render_accel_free(&accel);
		struct rs_render_desc rd = {.width = sizes[b],
		                            .height = sizes[b],
		                            .passes = o->passes,
		                            .lights = o->lights,
		                            .counters = true,
		                            .bvh = desc,
		                            .pack = table1_pack(o),
		                            .threads = o->threads};
		struct rs_render_stats st;
		if (render_cpu(scene, &rd, &st, &err) != RS_OK) {
			fprintf(stderr, "raystream-bench: %s\n", err.message);
			rs_scene_destroy(&scene);
			return 1;
		}
		hits[b] = st.total_per_pixel;
		box[b] = st.box_per_pixel;
	}
	printf("| %-5s | %6zu |", row->scene, tris);
	for (int b = 0; b < 4; ++b) {
		if (isnan(hits[b]))
			printf(" %10s |", "skipped");
		else
			printf(" %10.3f |", hits[b]);
		if (b < 3)
			print_paper(b == 0 ? row->none : b == 1 ? row->linear : row->tree);
	}
	printf(" %5.1f%% | %6.3f |\n", 100.0 * hits[3] / hits[2], box[3]);
	fflush(stdout);
	if (o->json) {
		static const char *const names[] = {"none", "linear", "paper", "sah"};
		cJSON *r = cJSON_CreateObject();
		cJSON_AddStringToObject(r, "scene", row->scene);
		cJSON_AddNumberToObject(r, "triangles", (double)tris);
		cJSON *h = cJSON_AddObjectToObject(r, "hit_numbers");
		cJSON *ms = cJSON_AddObjectToObject(r, "build_ms");
		for (int b = 0; b < 4; ++b) {
			if (!isnan(hits[b]))
				cJSON_AddNumberToObject(h, names[b], hits[b]);
			cJSON_AddNumberToObject(ms, names[b], build_ms[b]);
		}
		cJSON *pp = cJSON_AddObjectToObject(r, "paper_hit_numbers");
		if (row->none > 0)
			cJSON_AddNumberToObject(pp, "none", row->none);
		cJSON_AddNumberToObject(pp, "linear", row->linear);
		cJSON_AddNumberToObject(pp, "paper", row->tree);
		cJSON_AddItemToArray(cJSON_GetObjectItem(o->json, "rows"), r);
	}
	rs_scene_destroy(&scene);
	return 0;
}

/* Speed against error of the two triangle tests in one run: Moller-Trumbore against the
 * watertight test, whose image is taken as the reference (it cannot miss through edges). */
static int bench_triangle_tests(const struct bench_options *o, const char *name)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	size_t n = (size_t)o->size * o->size;
	float *rgb[2] = {malloc(n * 3 * sizeof(float)), malloc(n * 3 * sizeof(float))};
	float *depth[2] = {malloc(n * sizeof(float)), malloc(n * sizeof(float))};
	struct rs_bvh_desc bvh = {.builder = RS_BVH_SAH};
	int code = 1;
	if (!rgb[0] || !rgb[1] || !depth[0] || !depth[1])
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
	else if (rs_scenegen_load(name, &scene, &err) == RS_OK)
		code = 0;
	double ms[2] = {0, 0};
	for (int t = 0; t < 2 && code == 0; ++t) {
		struct rs_render_desc rd = {.width = o->size,
		                            .height = o->size,
		                            .passes = o->passes,
		                            .lights = o->lights,
		                            .triangle_test = t ? RS_TRIANGLE_WATERTIGHT
		                                               : RS_TRIANGLE_MOLLER_TRUMBORE,
		                            .bvh = bvh,
		                            .pack = table1_pack(o),
		                            .threads = o->threads};
		struct rs_renderer *renderer = NULL;
		struct rs_frame frame = {.rgb = rgb[t], .depth = depth[t]};
		double times[32];
		if (rs_renderer_create_cpu(&rd, &renderer, &err) != RS_OK ||
		    rs_renderer_set_scene(renderer, scene, &err) != RS_OK)
			code = 1;
		for (uint32_t r = 0; r < o->repeats && code == 0; ++r) {
			double t0 = rs_now_ms();
			if (rs_renderer_render(renderer, NULL, &frame, &err) != RS_OK)
				code = 1;
			times[r] = rs_now_ms() - t0;
		}
		rs_renderer_destroy(&renderer);
		ms[t] = code == 0 ? rs_tool_median(times, o->repeats) : 0.0;
	}
	if (code == 0) {
		struct rs_image_diff c, d;
		rs_image_compare(rgb[0], rgb[1], o->size, o->size, 3, 1.0, 1.0 / 255.0, &c);
		rs_image_compare(depth[0], depth[1], o->size, o->size, 1, 1.0, 1e-6, &d);
		printf("| %-5s | %.1f | %.1f | %.3f | %.2f | %.4f | %.4f%% | %zu | %.2e |\n", name,
		       ms[0], ms[1], ms[1] / ms[0], c.psnr_db, c.max_abs_error, 100.0 * c.bad_share,
		       d.mismatched, d.max_abs_error);
	} else {
		fprintf(stderr, "raystream-bench: %s\n", err.message);
	}
	for (int t = 0; t < 2; ++t) {
		free(rgb[t]);
		free(depth[t]);
	}
	rs_scene_destroy(&scene);
	return code;
}

int bench_table1(const struct bench_options *op)
{
	const struct bench_options o = *op;
	printf("Hit numbers, %u pass(es), %u light(s): sah/paper at %ux%u, none/linear at %ux%u "
	       "(none skipped above %u triangles)\n\n",
	       o.passes, o.lights, o.size, o.size, o.flat_size, o.flat_size, o.none_max_tris);
	printf("| scene | tris | none | paper's none | linear | paper's linear | paper tree | "
	       "paper's tree | sah | sah / paper tree | sah box tests |\n");
	printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	double build[6][4];
	int rows = 0;
	const char *names[6];
	for (size_t s = 0; s < sizeof paper / sizeof paper[0]; ++s) {
		if (o.only && strcmp(o.only, paper[s].scene) != 0)
			continue;
		bench_progress("table 1: %s", paper[s].scene);
		if (bench_scene(&o, &paper[s], build[rows]))
			return 1;
		names[rows++] = paper[s].scene;
	}
	printf("\nTriangle test, speed against error: Moller-Trumbore vs watertight (reference), "
	       "sah, %ux%u, %u pass(es), %u light(s), %u thread(s), median of %u renders\n\n",
	       o.size, o.size, o.passes, o.lights, o.threads, o.repeats);
	printf("| scene | MT ms | watertight ms | watertight/MT | PSNR dB | max err | pixels off "
	       "> 1/255 | depth hit/miss mismatches | depth max err |\n"
	       "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	for (int r = 0; r < rows; ++r) {
		bench_progress("table 1: %s, triangle tests", names[r]);
		if (bench_triangle_tests(&o, names[r]))
			return 1;
	}
	printf("\nBVH build time, ms (median of %u builds, one thread)\n\n", o.repeats);
	printf("| scene | none | linear | paper | sah |\n|---|---:|---:|---:|---:|\n");
	for (int r = 0; r < rows; ++r)
		printf("| %-5s | %.3f | %.3f | %.3f | %.3f |\n", names[r], build[r][0], build[r][1],
		       build[r][2], build[r][3]);
	return 0;
}
