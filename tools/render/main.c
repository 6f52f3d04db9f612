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

#include "raystream/rs_renderers.h"
#include "tool_common.h"

struct options {
	const char *scene, *backend, *out, *stats, *depth;
	enum rs_bvh_builder builder;
	enum rs_triangle_test triangle_test;
	struct rs_pack_desc pack; /* --nodes */
	enum rs_scene_storage storage;
	enum rs_primary_mode primary;
	enum rs_reflection_mode reflections;
	uint32_t bounces; /* --reflections interreflect:N */
	enum rs_shadow_mode shadows;
	uint32_t shadow_map_size, shadow_filter;
	uint32_t passes, lights, width, height, threads;
};

static void usage(FILE *to)
{
	fputs("usage: raystream-render --scene box|mirrors|cow1|cow2|cow5|cow9|cow17|cowN|FILE\n"
	      "         [--backend cpu|egl|osmesa] [--bvh none|linear|paper|sah] [--passes N]\n"
	      "         [--lights N] [--size WxH] [--out FILE.png] [--stats FILE.json]\n"
	      "         [--depth FILE.pfm] [--triangle-test watertight|mt] [--threads N]\n"
	      "         [--primary trace|raster] [--shadows rays|map[:RESOLUTION[:FILTER]]]\n"
	      "         [--reflections trace|envmap|interreflect[:BOUNCES]]\n"
	      "         [--nodes compact|paper[:directional|single]]\n"
	      "         [--scene-storage auto|2d|buffer]\n"
	      "Renders with the chosen backend (default cpu, the double-precision reference).\n"
	      "FILE is an OBJ or PLY mesh; a FILE.json beside it (from raystream-scene) sets\n"
	      "camera, lights and environment. --triangle-test defaults to watertight; mt is the\n"
	      "paper's Moller-Trumbore. --lights defaults to 1 (0 for a scene without lights).\n"
	      "--nodes: BVH node texture format and orders, default compact:directional;\n"
	      "paper:single is the paper's layout (docs/bvh.md). --scene-storage: GL backends\n"
	      "hold the scene in buffer textures where the context has them (auto) or in\n"
	      "GLES 3.0's 2D textures (2d); the images are the same (docs/gles.md).\n",
	      to);
}

static int fail_usage(const char *fmt, const char *arg)
{
	fprintf(stderr, "raystream-render: ");
	fprintf(stderr, fmt, arg);
	fputs(" (see --help)\n", stderr);
	return 2;
}

/* "rays", "map", "map:RES" or "map:RES:FILTER"; 0 on success. */
static int parse_shadows(const char *v, struct options *o)
{
	if (!strcmp(v, "rays")) {
		o->shadows = RS_SHADOW_RAYS;
		return 0;
	}
	if (strncmp(v, "map", 3) != 0 || (v[3] != '\0' && v[3] != ':'))
		return -1;
	o->shadows = RS_SHADOW_MAP;
	if (v[3] == '\0')
		return 0;
	char res[16];
	const char *colon = strchr(v + 4, ':');
	size_t n = colon ? (size_t)(colon - (v + 4)) : strlen(v + 4);
	if (n == 0 || n >= sizeof res)
		return -1;
	memcpy(res, v + 4, n);
	res[n] = '\0';
	if (!rs_tool_parse_u32(res, 8, 16384, &o->shadow_map_size))
		return -1;
	if (colon && !rs_tool_parse_u32(colon + 1, 1, 64, &o->shadow_filter))
		return -1;
	return 0;
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
			if (rs_bvh_builder_parse(v, &o->builder, NULL) != RS_OK)
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
		} else if (!strcmp(a, "--primary")) {
			if (!strcmp(v, "trace"))
				o->primary = RS_PRIMARY_TRACE;
			else if (!strcmp(v, "raster"))
				o->primary = RS_PRIMARY_RASTER;
			else
				return fail_usage("--primary wants trace or raster, not '%s'", v);
		} else if (!strcmp(a, "--reflections")) {
			if (!rs_tool_parse_reflections(v, &o->reflections, &o->bounces))
				return fail_usage("--reflections wants trace, envmap or "
				                  "interreflect[:1..8], not '%s'",
				                  v);
		} else if (!strcmp(a, "--shadows")) {
			if (parse_shadows(v, o) != 0)
				return fail_usage(
				    "--shadows wants rays or map[:RESOLUTION[:FILTER]], "
				    "not '%s'",
				    v);
		} else if (!strcmp(a, "--nodes")) {
			if (!rs_tool_parse_nodes(v, &o->pack))
				return fail_usage(
				    "--nodes wants compact|paper[:directional|single], not '%s'",
				    v);
		} else if (!strcmp(a, "--scene-storage")) {
			if (!rs_tool_parse_storage(v, &o->storage))
				return fail_usage(
				    "--scene-storage wants auto, 2d or buffer, not '%s'", v);
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
	if (!rs_renderer_has_backend(o->backend)) {
		fprintf(stderr, "raystream-render: unknown backend '%s' (this build has: %s)\n",
		        o->backend, rs_renderer_backends());
		return 2;
	}
	if (!o->out && !o->stats && !o->depth)
		o->out = "out.png";
	return 0;
}

static const char *shadow_name(const struct rs_render_desc *d, char *buf, size_t cap)
{
	if (d->shadows == RS_SHADOW_RAYS)
		return "rays";
	snprintf(buf, cap, "map:%u:%u", d->shadow_map_size, d->shadow_filter);
	return buf;
}

static cJSON *stats_json(const struct options *o, const struct rs_scene *scene,
                         const struct rs_renderer *renderer, double ms)
{
	const struct rs_render_desc *d = rs_renderer_desc(renderer);
	const struct rs_render_stats *st = rs_renderer_stats(renderer);
	char shadows[32];
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "scene", o->scene);
	cJSON_AddStringToObject(doc, "backend", st->backend);
	cJSON_AddStringToObject(doc, "renderer", st->renderer);
	cJSON_AddNumberToObject(doc, "triangles", (double)rs_scene_triangle_count(scene));
	cJSON_AddStringToObject(doc, "bvh", rs_bvh_builder_name(d->bvh.builder));
	char nodes[32];
	cJSON_AddStringToObject(doc, "nodes", rs_tool_nodes_name(&d->pack, nodes, sizeof nodes));
	if (strcmp(st->backend, "cpu") != 0)
		cJSON_AddStringToObject(doc, "scene_storage",
		                        rs_tool_storage_name(st->scene_storage));
	cJSON_AddNumberToObject(doc, "passes", d->passes);
	cJSON_AddNumberToObject(doc, "lights", d->lights);
	cJSON_AddNumberToObject(doc, "width", d->width);
	cJSON_AddNumberToObject(doc, "height", d->height);
	cJSON_AddStringToObject(doc, "triangle_test",
	                        d->triangle_test == RS_TRIANGLE_WATERTIGHT ? "watertight" : "mt");
	cJSON_AddStringToObject(doc, "primary",
	                        d->primary == RS_PRIMARY_RASTER ? "raster" : "trace");
	cJSON_AddStringToObject(doc, "shadows", shadow_name(d, shadows, sizeof shadows));
	if (st->counters_valid) {
		cJSON *hits = cJSON_AddObjectToObject(doc, "hit_numbers");
		cJSON_AddNumberToObject(hits, "box", st->box_per_pixel);
		cJSON_AddNumberToObject(hits, "triangle", st->triangle_per_pixel);
		cJSON_AddNumberToObject(hits, "total", st->total_per_pixel);
	}
	cJSON_AddNumberToObject(doc, "primary_rays", (double)st->primary_rays);
	cJSON_AddNumberToObject(doc, "secondary_rays", (double)st->secondary_rays);
	cJSON_AddNumberToObject(doc, "rays", (double)(st->primary_rays + st->secondary_rays));
	cJSON_AddNumberToObject(doc, "shadow_rays", (double)st->shadow_rays);
	cJSON_AddNumberToObject(doc, "ms", ms);
	cJSON_AddNumberToObject(doc, "render_ms", st->render_ms);
	cJSON_AddNumberToObject(doc, "readback_ms", st->readback_ms);
	cJSON_AddNumberToObject(doc, "build_ms", st->build_ms);
	cJSON_AddNumberToObject(doc, "pack_ms", st->pack_ms);
	cJSON_AddNumberToObject(doc, "upload_ms", st->upload_ms);
	if (!strcmp(st->backend, "cpu"))
		cJSON_AddNumberToObject(doc, "threads", d->threads);
	if (st->kernel_count) {
		cJSON *k = cJSON_AddArrayToObject(doc, "kernels");
		for (uint32_t i = 0; i < st->kernel_count; ++i) {
			cJSON *e = cJSON_CreateObject();
			cJSON_AddStringToObject(e, "name", st->kernels[i].name);
			cJSON_AddNumberToObject(e, "calls", st->kernels[i].calls);
			cJSON_AddNumberToObject(e, "ms", st->kernels[i].ms);
			cJSON_AddItemToArray(k, e);
		}
	}
	return doc;
}

static int run(const struct options *o)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	struct rs_renderer *renderer = NULL;
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
	long online = sysconf(_SC_NPROCESSORS_ONLN);
	struct rs_render_desc desc = {
	    .width = o->width,
	    .height = o->height,
	    .passes = o->passes,
	    .lights = lights, /* 0 means "all": right for a scene without lights */
	    .triangle_test = o->triangle_test,
	    .pack = o->pack,
	    .scene_storage = o->storage,
	    .primary = o->primary,
	    .reflections = o->reflections,
	    .reflection_bounces = o->bounces,
	    .shadows = o->shadows,
	    .shadow_map_size = o->shadow_map_size,
	    .shadow_filter = o->shadow_filter,
	    .counters = true,
	    .bvh = {.builder = o->builder},
	    .threads = o->threads                    ? o->threads
	               : online > 0 && online <= 256 ? (uint32_t)online
	                                             : 1u,
	};
	if (rs_renderer_open(o->backend, &desc, &renderer, &err) != RS_OK ||
	    rs_renderer_set_scene(renderer, scene, &err) != RS_OK)
		goto done;
	const struct rs_render_desc *d = rs_renderer_desc(renderer);
	uint32_t w = d->width, h = d->height;
	rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
	depth = malloc((size_t)w * h * sizeof *depth);
	if (!rgb || !depth) {
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory for a %ux%u image", w, h);
		goto done;
	}
	struct rs_frame frame = {.rgb = rgb, .depth = o->depth ? depth : NULL};
	double t0 = rs_now_ms();
	if (rs_renderer_render(renderer, NULL, &frame, &err) != RS_OK)
		goto done;
	double ms = rs_now_ms() - t0;
	if (o->out && rs_image_write_png(o->out, rgb, w, h, &err) != RS_OK)
		goto done;
	written[0] = o->out;
	if (o->depth && rs_image_write_pfm(o->depth, depth, w, h, 1, &err) != RS_OK)
		goto done;
	written[1] = o->depth;
	if (o->stats) {
		cJSON *doc = stats_json(o, scene, renderer, ms);
		enum rs_status s = doc ? rs_tool_write_json(o->stats, doc, &err)
		                       : rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		cJSON_Delete(doc);
		if (s != RS_OK)
			goto done;
	}
	const struct rs_render_stats *st = rs_renderer_stats(renderer);
	printf("%s: %zu triangles, %s (%s), bvh %s (%.1f ms), %ux%u, %u pass(es), %u light(s): "
	       "%.1f ms",
	       o->scene, rs_scene_triangle_count(scene), st->backend, st->renderer,
	       rs_bvh_builder_name(o->builder), st->build_ms, w, h, d->passes, lights, ms);
	if (st->counters_valid)
		printf(", hit numbers %.3f (box %.3f + triangle %.3f)", st->total_per_pixel,
		       st->box_per_pixel, st->triangle_per_pixel);
	printf("\n");
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
	rs_renderer_destroy(&renderer);
	rs_scene_destroy(&scene);
	return code;
}

int main(int argc, char **argv)
{
	struct options o;
	int code = parse_args(argc, argv, &o);
	return code ? code : run(&o);
}
