/*
 * raystream-bench --instance-updates [COUNT...]: what moving every instance of a scene costs
 * per frame, for COUNT instances (default 17, 1000 and 10000) of one small prototype (a UV
 * sphere of 96 triangles, so 10,000 baked instances fit the default 2048-texel
 * textures) on a grid over a plain floor. Each timed frame gives every
 * instance a new transform in place (rs_scene_set_instance_transform, timed: "move"), then,
 * in the same window so load hits all alike:
 *   - the two-level packing's update (rs_pack_instances_update): the TLAS's build and pack,
 *     and the bytes a GPU re-uploads for it (the TLAS's four textures and six RGBA32F texels
 *     of transforms an instance; no BLAS);
 *   - one renderer on --backend takes the frame by rs_renderer_update_instances() (its own
 *     top-level update, or the update_vertices path, "baked", where the backend has none);
 *   - a second renderer takes it by a full rs_renderer_set_scene().
 * Scenes are made before the clock starts; --repeats frames are timed (medians).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "raystream/rs_renderers.h"
#include "tool_common.h"

#define SPHERE_SEGMENTS 8u
#define SPHERE_RINGS 6u
#define SPACING 3.0

static const uint32_t default_counts[] = {17, 1000, 10000};

/* Instance i's transform at frame k: a turn about y and a bob, on a grid of `cols`. */
static void instance_transform(uint32_t i, uint32_t cols, uint32_t k, double m[3][4])
{
	double a = 0.37 * i + 0.1 * k, c = cos(a), s = sin(a);
	const double rows[3][4] = {
	    {c, 0.0, s, SPACING * (double)(i % cols)},
	    {0.0, 1.0, 0.0, 1.0 + 0.25 * sin(0.2 * k + i)},
	    {-s, 0.0, c, SPACING * (double)(i / cols)},
	};
	memcpy(m, rows, sizeof rows);
}

/* n instances of a squashed UV sphere (their own material) over a floor (a plain mesh). */
static enum rs_status make_scene(uint32_t n, struct rs_scene **out, struct rs_error *err)
{
	static double pos[(SPHERE_RINGS + 1) * SPHERE_SEGMENTS * 3];
	static uint32_t idx[SPHERE_RINGS * SPHERE_SEGMENTS * 6];
	size_t nv = 0, nt = 0;
	for (uint32_t r = 0; r <= SPHERE_RINGS; r++)
		for (uint32_t g = 0; g < SPHERE_SEGMENTS; g++, nv++) {
			double th = RS_PI * r / SPHERE_RINGS,
			       ph = 2.0 * RS_PI * g / SPHERE_SEGMENTS;
			pos[nv * 3] = sin(th) * cos(ph);
			pos[nv * 3 + 1] = 0.8 * cos(th);
			pos[nv * 3 + 2] = sin(th) * sin(ph);
		}
	for (uint32_t r = 0; r < SPHERE_RINGS; r++)
		for (uint32_t g = 0; g < SPHERE_SEGMENTS; g++, nt += 2) {
			uint32_t a = r * SPHERE_SEGMENTS + g,
			         b = r * SPHERE_SEGMENTS + (g + 1) % SPHERE_SEGMENTS;
			const uint32_t t[6] = {
			    a, b, a + SPHERE_SEGMENTS, b, b + SPHERE_SEGMENTS, a + SPHERE_SEGMENTS};
			memcpy(idx + nt * 3, t, sizeof t);
		}
	uint32_t cols = (uint32_t)ceil(sqrt((double)n));
	double side = SPACING * cols;
	const double fp[4 * 3] = {-2, 0, -2, side, 0, -2, side, 0, side, -2, 0, side};
	const uint32_t fi[6] = {0, 2, 1, 0, 3, 2};
	const struct rs_material grey = {.diffuse = {0.6f, 0.6f, 0.6f}};
	const struct rs_material red = {.diffuse = {0.8f, 0.2f, 0.1f}, .specular = 0.3f};
	struct rs_mesh_desc sphere = {.positions_f64 = pos,
	                              .vertex_count = nv,
	                              .indices = idx,
	                              .triangle_count = nt,
	                              .material = 1};
	struct rs_mesh_desc floor = {
	    .positions_f64 = fp, .vertex_count = 4, .indices = fi, .triangle_count = 2};
	struct rs_camera cam = {.eye = {0.5 * side, 0.6 * side + 4.0, 1.4 * side + 6.0},
	                        .target = {0.5 * side, 0.0, 0.5 * side},
	                        .up = {0.0, 1.0, 0.0}};
	const struct rs_light light = {.position = {0.5 * side, side + 10.0, 0.5 * side},
	                               .color = {1.0, 1.0, 1.0}};
	enum rs_status st = rs_scene_create(NULL, out, err);
	if (st == RS_OK)
		st = rs_scene_add_material(*out, &grey, NULL, err);
	if (st == RS_OK)
		st = rs_scene_add_material(*out, &red, NULL, err);
	if (st == RS_OK)
		st = rs_scene_add_mesh(*out, &floor, err);
	if (st == RS_OK)
		st = rs_scene_add_prototype(*out, &sphere, NULL, err);
	for (uint32_t i = 0; st == RS_OK && i < n; i++) {
		struct rs_instance_desc d = {0};
		instance_transform(i, cols, 0, d.transform);
		st = rs_scene_add_instance(*out, &d, NULL, err);
	}
	if (st == RS_OK)
		st = rs_scene_set_camera(*out, &cam, err);
	if (st == RS_OK)
		st = rs_scene_add_light(*out, &light, err);
	if (st != RS_OK)
		rs_scene_destroy(out);
	return st;
}

struct instance_figures {
	double move_ms[BENCH_MAX_FRAMES], tlas_build_ms[BENCH_MAX_FRAMES];
	double tlas_pack_ms[BENCH_MAX_FRAMES], update_ms[BENCH_MAX_FRAMES];
	double refit_ms[BENCH_MAX_FRAMES], pack_ms[BENCH_MAX_FRAMES];
	double upload_ms[BENCH_MAX_FRAMES], upload_bytes[BENCH_MAX_FRAMES];
	double set_ms[BENCH_MAX_FRAMES];
	size_t tlas_bytes, triangles;
	uint64_t full_bytes;
	bool baked;
};

/* One timed frame k: move, two-level update, renderer update, full set_scene. */
static enum rs_status time_frame(struct rs_scene *scene, uint32_t n, uint32_t k,
                                 struct rs_packed_instances *two, const struct rs_bvh_desc *bvh,
                                 struct rs_renderer *r[2], struct instance_figures *f,
                                 struct rs_error *err)
{
	uint32_t cols = (uint32_t)ceil(sqrt((double)n)), j = k - 1;
	enum rs_status st = RS_OK;
	double t0 = rs_now_ms();
	for (uint32_t i = 0; st == RS_OK && i < n; i++) {
		double m[3][4];
		instance_transform(i, cols, k, m);
		st = rs_scene_set_instance_transform(scene, i, m, err);
	}
	double t1 = rs_now_ms();
	if (st == RS_OK)
		st = rs_pack_instances_update(two, scene, bvh, err);
	double t2 = rs_now_ms();
	if (st == RS_OK)
		st = rs_renderer_update_instances(r[0], scene, err);
	double t3 = rs_now_ms();
	if (st == RS_OK)
		st = rs_renderer_set_scene(r[1], scene, err);
	double t4 = rs_now_ms();
	if (st != RS_OK)
		return st;
	const struct rs_render_stats *s = rs_renderer_stats(r[0]);
	f->move_ms[j] = t1 - t0;
	f->tlas_build_ms[j] = two->top_build_ms;
	f->tlas_pack_ms[j] = two->top_pack_ms;
	f->update_ms[j] = t3 - t2;
	f->refit_ms[j] = s->instance_update_baked ? (s->update_rebuilt ? s->build_ms : s->refit_ms)
	                                          : s->tlas_build_ms;
	f->pack_ms[j] = s->pack_ms;
	f->upload_ms[j] = s->upload_ms;
	f->upload_bytes[j] = (double)s->upload_bytes;
	f->set_ms[j] = t4 - t3;
	f->baked = s->instance_update_baked;
	f->tlas_bytes = rs_pack_bytes(&two->top) + (size_t)two->instance_count * 6u * 16u;
	return RS_OK;
}

static enum rs_status run_count(const struct bench_options *o, uint32_t n,
                                struct instance_figures *f, char *renderer, size_t cap,
                                struct rs_error *err)
{
	struct rs_scene *scene = NULL;
	struct rs_renderer *r[2] = {NULL, NULL};
	struct rs_packed_instances two = {0};
	struct rs_render_desc d = o->render;
	d.width = d.height = o->size;
	struct rs_bvh_desc bvh = rs_render_bvh_desc(&d);
	enum rs_status st = make_scene(n, &scene, err);
	for (int i = 0; st == RS_OK && i < 2; i++)
		st = rs_renderer_open(o->backend, &d, &r[i], err);
	for (int i = 0; st == RS_OK && i < 2; i++)
		st = rs_renderer_set_scene(r[i], scene, err);
	if (st == RS_OK)
		st = rs_pack_instances(scene, &bvh, &o->pack, &two, err);
	if (st == RS_OK) {
		snprintf(renderer, cap, "%s", rs_renderer_stats(r[0])->renderer);
		f->full_bytes = rs_renderer_stats(r[0])->upload_bytes;
		f->triangles = rs_scene_triangle_count(scene);
	}
	for (uint32_t k = 1; st == RS_OK && k <= o->repeats; k++) {
		st = time_frame(scene, n, k, &two, &bvh, r, f, err);
		bench_progress("--instance-updates %u: frame %u of %u", n, k, o->repeats);
	}
	rs_pack_instances_free(&two);
	rs_renderer_destroy(&r[0]);
	rs_renderer_destroy(&r[1]);
	rs_scene_destroy(&scene);
	return st;
}

static void report(const struct bench_options *o, uint32_t n, const char *renderer,
                   const struct instance_figures *f)
{
	uint32_t k = o->repeats;
	double move = bench_summarize(f->move_ms, k).median;
	double tb = bench_summarize(f->tlas_build_ms, k).median;
	double tp = bench_summarize(f->tlas_pack_ms, k).median;
	struct bench_summary up = bench_summarize(f->update_ms, k);
	double refit = bench_summarize(f->refit_ms, k).median;
	double pack = bench_summarize(f->pack_ms, k).median;
	double upload = bench_summarize(f->upload_ms, k).median;
	double bytes = bench_summarize(f->upload_bytes, k).median;
	struct bench_summary set = bench_summarize(f->set_ms, k);
	printf("%9u %9zu %8.2f | %8.3f %8.3f %10zu | %-6s %5s %9.1f %9.1f %8.1f %8.1f %11.0f | "
	       "%9.1f %5.1fx\n",
	       n, f->triangles, move, tb, tp, f->tlas_bytes, o->backend,
	       f->baked ? "baked" : "tlas", up.median, refit, pack, upload, bytes, set.median,
	       set.median / up.median);
	fflush(stdout);
	if (!o->json)
		return;
	cJSON *row = cJSON_CreateObject();
	cJSON_AddNumberToObject(row, "instances", n);
	cJSON_AddNumberToObject(row, "triangles", (double)f->triangles);
	cJSON_AddStringToObject(row, "backend", o->backend);
	cJSON_AddStringToObject(row, "renderer", renderer);
	cJSON_AddNumberToObject(row, "frames", k);
	cJSON_AddNumberToObject(row, "move_ms", move);
	cJSON_AddNumberToObject(row, "tlas_build_ms", tb);
	cJSON_AddNumberToObject(row, "tlas_pack_ms", tp);
	cJSON_AddNumberToObject(row, "tlas_upload_bytes", (double)f->tlas_bytes);
	cJSON_AddStringToObject(row, "update_path", f->baked ? "baked" : "tlas");
	cJSON_AddItemToObject(row, "update_ms", bench_json_summary(up));
	cJSON_AddNumberToObject(row, "update_refit_or_build_ms", refit);
	cJSON_AddNumberToObject(row, "update_pack_ms", pack);
	cJSON_AddNumberToObject(row, "update_upload_ms", upload);
	cJSON_AddNumberToObject(row, "update_upload_bytes", bytes);
	cJSON_AddNumberToObject(row, "set_scene_upload_bytes", (double)f->full_bytes);
	cJSON_AddItemToObject(row, "set_scene_ms", bench_json_summary(set));
	cJSON_AddItemToArray(cJSON_GetObjectItem(o->json, "rows"), row);
}

int bench_instance_updates(const struct bench_options *o)
{
	const struct rs_cli cli = {.prog = "raystream-bench"};
	struct rs_error err = {0};
	uint32_t counts[BENCH_MAX_SCENES];
	size_t nc = o->scene_count;
	for (size_t i = 0; i < nc; i++) /* checked when parsed */
		rs_tool_parse_u32(o->scenes[i], 1, BENCH_MAX_INSTANCES, &counts[i]);
	if (nc == 0) {
		nc = sizeof default_counts / sizeof default_counts[0];
		memcpy(counts, default_counts, sizeof default_counts);
	}
	printf("Per-frame instance updates: every instance moves each frame; %u frames each, "
	       "medians, ms\n",
	       o->repeats);
	printf("%9s %9s %8s | %8s %8s %10s | %-6s %5s %9s %9s %8s %8s %11s | %9s %6s\n",
	       "instances", "triangles", "move", "TLAS bld", "TLAS pck", "TLAS bytes", "update",
	       "path", "ms", "refit/bld", "pack", "upload", "bytes", "set_scene", "ratio");
	for (size_t i = 0; i < nc; i++) {
		struct instance_figures *f = calloc(1, sizeof *f);
		char renderer[128] = "";
		enum rs_status st = f ? run_count(o, counts[i], f, renderer, sizeof renderer, &err)
		                      : rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		if (st == RS_OK)
			report(o, counts[i], renderer, f);
		free(f);
		if (st != RS_OK)
			return rs_cli_fail(&cli, &err);
		if (i + 1 == nc)
			printf("  renderer: %s\n", renderer);
	}
	return 0;
}
