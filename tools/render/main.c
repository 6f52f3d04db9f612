/*
 * raystream-render: render a scene (box, cowN or a mesh file) with a backend and write the
 * image, the primary-hit depth and a stats file. Every failure is one line on stderr and
 * exit status 1 (2 for usage errors); no output file is ever left half-written.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tool_common.h"

struct options {
	const char *scene, *backend, *out, *stats, *depth;
	enum rs_bvh_builder builder;
	enum rs_triangle_test triangle_test;
	uint32_t passes, lights, width, height, threads;
};

static void usage(FILE *to)
{
	fputs(
	    "usage: raystream-render --scene box|cow1|cow2|cow5|cow9|cow17|cowN|FILE\n"
	    "         [--backend cpu] [--bvh none|linear|paper|sah] [--passes N] [--lights N]\n"
	    "         [--size WxH] [--out FILE.png] [--stats FILE.json] [--depth FILE.pfm]\n"
	    "         [--triangle-test watertight|mt] [--threads N]\n"
	    "Renders with the double-precision CPU reference tracer. FILE is an OBJ or PLY mesh;\n"
	    "--triangle-test defaults to watertight; mt is the paper's Moller-Trumbore.\n"
	    "a FILE.json beside it (from raystream-scene) sets camera, lights and environment.\n"
	    "--lights defaults to 1 (0 for a scene without lights).\n",
	    to);
}

static int fail_usage(const char *fmt, const char *arg)
{
	fprintf(stderr, "raystream-render: ");
	fprintf(stderr, fmt, arg);
	fputs(" (see --help)\n", stderr);
	return 2;
}

static int parse_args(int argc, char **argv, struct options *o)
{
	/* lights 0: not given; run() makes it 1, or 0 for a scene without lights. */
	*o = (struct options){.backend = "cpu", .builder = RS_BVH_SAH, .passes = 2};
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i];
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			exit(0);
		}
		if (strncmp(a, "--", 2) != 0)
			return fail_usage("unexpected argument '%s'", a);
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!v)
			return fail_usage("option %s needs a value", a);
		++i;
		if (!strcmp(a, "--scene"))
			o->scene = v;
		else if (!strcmp(a, "--backend"))
			o->backend = v;
		else if (!strcmp(a, "--out"))
			o->out = v;
		else if (!strcmp(a, "--stats"))
			o->stats = v;
		else if (!strcmp(a, "--depth"))
			o->depth = v;
		else if (!strcmp(a, "--bvh")) {
			if (rs_bvh_builder_parse(v, &o->builder) != RS_OK)
				return fail_usage("unknown BVH builder '%s'", v);
		} else if (!strcmp(a, "--passes")) {
			if (!rs_tool_parse_u32(v, 1, 64, &o->passes))
				return fail_usage("--passes wants a whole number 1..64, not '%s'",
				                  v);
		} else if (!strcmp(a, "--lights")) {
			if (!rs_tool_parse_u32(v, 1, 64, &o->lights))
				return fail_usage("--lights wants a whole number 1..64, not '%s'",
				                  v);
		} else if (!strcmp(a, "--threads")) {
			if (!rs_tool_parse_u32(v, 1, 256, &o->threads))
				return fail_usage("--threads wants a whole number 1..256, not '%s'",
				                  v);
		} else if (!strcmp(a, "--size")) {
			if (!rs_tool_parse_size(v, &o->width, &o->height))
				return fail_usage("--size wants WxH within 1..16384, not '%s'", v);
		} else if (!strcmp(a, "--triangle-test")) {
			if (!strcmp(v, "mt"))
				o->triangle_test = RS_TRIANGLE_MOLLER_TRUMBORE;
			else if (!strcmp(v, "watertight"))
				o->triangle_test = RS_TRIANGLE_WATERTIGHT;
			else
				return fail_usage("unknown triangle test '%s'", v);
		} else
			return fail_usage("unknown option '%s'", a);
	}
	if (!o->scene)
		return fail_usage("%s", "--scene is required");
	if (strcmp(o->backend, "cpu") != 0)
		return fail_usage("unknown backend '%s' (this build has: cpu)", o->backend);
	if (!o->out && !o->stats && !o->depth)
		o->out = "out.png";
	return 0;
}

static cJSON *stats_json(const struct options *o, const struct rs_scene *scene,
                         const struct rs_tool_accel *accel, const struct rs_trace_stats *st,
                         uint32_t w, uint32_t h, uint32_t lights, double ms)
{
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "scene", o->scene);
	cJSON_AddStringToObject(doc, "backend", o->backend);
	cJSON_AddNumberToObject(doc, "triangles", (double)rs_scene_triangle_count(scene));
	cJSON_AddStringToObject(doc, "bvh", rs_bvh_builder_name(o->builder));
	cJSON_AddNumberToObject(doc, "bvh_nodes", (double)accel->node_count);
	cJSON_AddNumberToObject(doc, "passes", o->passes);
	cJSON_AddNumberToObject(doc, "lights", lights);
	cJSON_AddNumberToObject(doc, "width", w);
	cJSON_AddNumberToObject(doc, "height", h);
	cJSON_AddStringToObject(doc, "triangle_test",
	                        o->triangle_test == RS_TRIANGLE_WATERTIGHT ? "watertight" : "mt");
	cJSON *hits = cJSON_AddObjectToObject(doc, "hit_numbers");
	cJSON_AddNumberToObject(hits, "box", st->box_per_pixel);
	cJSON_AddNumberToObject(hits, "triangle", st->triangle_per_pixel);
	cJSON_AddNumberToObject(hits, "total", st->total_per_pixel);
	cJSON_AddNumberToObject(doc, "rays", (double)st->rays);
	cJSON_AddNumberToObject(doc, "shadow_rays", (double)st->shadow_rays);
	cJSON_AddNumberToObject(doc, "ms", ms);
	cJSON_AddNumberToObject(doc, "build_ms", accel->build_ms);
	cJSON_AddNumberToObject(doc, "pack_ms", accel->pack_ms);
	cJSON_AddNumberToObject(doc, "threads", o->threads);
	return doc;
}

static int run(const struct options *o)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	struct rs_tool_accel accel = {0};
	float *rgb = NULL, *depth = NULL;
	const char *written[2] = {NULL, NULL}; /* outputs of this run, removed on failure */
	int code = 1;
	if (rs_tool_load_scene(o->scene, &scene, &err) != RS_OK)
		goto done;
	uint32_t scene_lights = (uint32_t)rs_scene_light_count(scene);
	/* Unasked, a scene without lights (a view file may list none) renders with ambient
	 * light only instead of failing on a limit the user never set. */
	uint32_t lights = o->lights ? o->lights : scene_lights ? 1u : 0u;
	if (lights > scene_lights) {
		rs_error_set(&err, RS_ERR_INVALID, "--lights %u but scene '%s' has %u light(s)",
		             o->lights, o->scene, scene_lights);
		goto done;
	}
	struct rs_camera cam;
	rs_camera_resolve(rs_scene_camera(scene), &cam);
	uint32_t w = o->width ? o->width : cam.width, h = o->height ? o->height : cam.height;
	struct rs_bvh_desc bvh = {.builder = o->builder};
	if (rs_tool_accel_build(scene, &bvh, &accel, &err) != RS_OK)
		goto done;
	rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
	depth = malloc((size_t)w * h * sizeof *depth);
	if (!rgb || !depth) {
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory for a %ux%u image", w, h);
		goto done;
	}
	struct rs_trace_desc desc = {
	    .width = w, .height = h, .passes = o->passes, .triangle_test = o->triangle_test};
	/* rs_trace_desc.lights 0 means "all": right for a scene without lights. */
	desc.lights = lights;
	struct rs_trace_stats stats;
	long online = sysconf(_SC_NPROCESSORS_ONLN);
	uint32_t threads = o->threads                    ? o->threads
	                   : online > 0 && online <= 256 ? (uint32_t)online
	                                                 : 1u;
	double t0 = rs_tool_now_ms();
	if (rs_tool_render_cpu(scene, &accel.packed, &desc, threads, rgb, depth, &stats, &err) !=
	    RS_OK)
		goto done;
	double ms = rs_tool_now_ms() - t0;
	if (o->out && rs_image_write_png(o->out, rgb, w, h, &err) != RS_OK)
		goto done;
	written[0] = o->out;
	if (o->depth && rs_image_write_pfm(o->depth, depth, w, h, 1, &err) != RS_OK)
		goto done;
	written[1] = o->depth;
	if (o->stats) {
		struct options shown = *o;
		shown.threads = threads;
		cJSON *doc = stats_json(&shown, scene, &accel, &stats, w, h, lights, ms);
		enum rs_status s = doc ? rs_tool_write_json(o->stats, doc, &err)
		                       : rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		cJSON_Delete(doc);
		if (s != RS_OK)
			goto done;
	}
	printf("%s: %zu triangles, bvh %s (%zu nodes, %.1f ms), %ux%u, %u pass(es), %u light(s): "
	       "%.1f ms, hit numbers %.3f (box %.3f + triangle %.3f)\n",
	       o->scene, rs_scene_triangle_count(scene), rs_bvh_builder_name(o->builder),
	       accel.node_count, accel.build_ms, w, h, o->passes, lights, ms, stats.total_per_pixel,
	       stats.box_per_pixel, stats.triangle_per_pixel);
	code = 0;
done:
	if (code != 0) {
		fprintf(stderr, "raystream-render: %s\n",
		        err.message[0] ? err.message : "failed (no message)");
		/* A failed run leaves none of its outputs: a PNG without the stats or depth
		 * the caller asked for would pass for a complete result. */
		for (int i = 0; i < 2; ++i)
			if (written[i])
				unlink(written[i]);
	}
	free(rgb);
	free(depth);
	rs_tool_accel_free(&accel);
	rs_scene_destroy(&scene);
	return code;
}

int main(int argc, char **argv)
{
	struct options o;
	int code = parse_args(argc, argv, &o);
	return code ? code : run(&o);
}
