/*
 * raystream-render: render a scene (box, mirrors, animated, cowN or a mesh file) with a
 * backend and write the image (PNG or JPEG), the primary-hit depth and a stats file, each
 * named on stdout; a scene that moves at any --frame, or --animate frames in a row through
 * rs_renderer_update_vertices() (an instanced one through rs_renderer_update_instances()). Options
 * through rs_cli and rs_render_desc_set (docs/tools.md). Every failure is one line on stderr and
 * exit status 1 (2 for usage errors); no output file is ever left half-written.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_codec.h"
#include "raystream/rs_renderers.h"
#include "tool_common.h"

static const struct rs_cli prog = {.prog = "raystream-render"}; /* messages after parsing */

struct options {
	const char *scene, *out, *stats, *depth;
	bool jpeg; /* --out ends in .jpg or .jpeg */
	uint32_t frame, animate, fps;
	uint32_t samples; /* --samples: refinement frames averaged (0 and 1: one frame) */
	struct rs_render_desc desc;
};

static const char about[] =
    "Renders SCENE (box, mirrors, animated, cowN with N 1..1024, cowNi: CowN as instances of\n"
    "one cow, or an OBJ/PLY file; a FILE.json beside it, from raystream-scene, sets camera,\n"
    "lights and environment) and names every file it writes on stdout. The backend auto\n"
    "renders on the GPU where a GL context opens and says so on stderr when it falls back\n"
    "to cpu, the double-precision reference. Render options are the library's\n"
    "(rs_render_desc_set), docs/render.md.\n"
    "Scenes that move (animated, cowN, cowNi): --frame N renders frame N; --animate COUNT renders\n"
    "COUNT frames from it, moving the vertices between frames (refit, partial upload; cowNi:\n"
    "the instance transforms), and names each image and depth FILE-NNNN.ext; frame N of a\n"
    "run is --frame N's image.\n";

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse_args(int argc, char **argv, struct options *o)
{
	*o = (struct options){.fps = 30};
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--scene", &o->scene, "SCENE", "what to render (required)"),
	    {.name = "--out",
	     .kind = RS_CLI_STRING,
	     .out = &o->out,
	     .arg = "FILE.png|FILE.jpg",
	     .help = "the image, PNG or JPEG by its name",
	     .fallback = "out.png"},
	    RS_CLI_STRING_OPT("--stats", &o->stats, "FILE.json", "what the frame cost and counted"),
	    RS_CLI_STRING_OPT("--depth", &o->depth, "FILE.pfm", "primary-hit distance per pixel"),
	    RS_CLI_U32_OPT("--frame", &o->frame, 0, 10000000, "the frame of a scene that moves"),
	    RS_CLI_U32_OPT("--animate", &o->animate, 0, 100000,
	                   "frames to render from --frame (0: one, no numbered names)"),
	    RS_CLI_U32_OPT("--fps", &o->fps, 1, 1000, "frames per second of the scene's motion"),
	    RS_CLI_U32_OPT("--samples", &o->samples, 1, 4096,
	                   "average N frames of the sub-pixel sequence (what a still viewer "
	                   "converges to)"),
	};
	struct rs_cli cli = {.prog = prog.prog,
	                     .usage = "--scene SCENE [options]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = &o->desc,
	                     .render_keys = "*"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	if (!o->scene)
		return rs_cli_usage_error(&cli, "--scene is required");
	if (!rs_renderer_has_backend(o->desc.backend ? o->desc.backend : "auto"))
		return rs_cli_usage_error(&cli,
		                          "--backend: '%s' is not part of this build (have: %s)",
		                          o->desc.backend, rs_renderer_backends());
	if (!o->out && !o->stats && !o->depth)
		o->out = "out.png";
	if ((o->frame || o->animate > 1) && !rs_scenegen_moves(o->scene))
		return rs_cli_usage_error(
		    &cli, "--frame/--animate: scene '%s' does not move (animated, cowN, cowNi)",
		    o->scene);
	if (o->out) {
		const char *dot = strrchr(o->out, '.');
		o->jpeg = dot && (!strcasecmp(dot, ".jpg") || !strcasecmp(dot, ".jpeg"));
		if (!o->jpeg && !(dot && !strcasecmp(dot, ".png")))
			return rs_cli_usage_error(
			    &cli, "--out: '%s' does not end in .png, .jpg or .jpeg", o->out);
	}
	return 0;
}

/* The number of lights a descriptor uses on `scene` (0 means all of them). */
static uint32_t lights_used(const struct rs_render_desc *d, const struct rs_scene *scene)
{
	return d->lights ? d->lights : (uint32_t)rs_scene_light_count(scene);
}

/* A render option of `d` into doc as the command line spells it. */
static void add_option(cJSON *doc, const char *name, const struct rs_render_desc *d,
                       const char *key)
{
	char text[64];
	if (rs_render_desc_get(d, key, text, sizeof text, NULL) == RS_OK)
		cJSON_AddStringToObject(doc, name, text);
}

static cJSON *stats_json(const struct options *o, const struct rs_scene *scene,
                         const struct rs_renderer *renderer, double ms)
{
	const struct rs_render_desc *d = rs_renderer_desc(renderer);
	const struct rs_render_stats *st = rs_renderer_stats(renderer);
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "scene", o->scene);
	cJSON_AddStringToObject(doc, "backend", st->backend);
	cJSON_AddStringToObject(doc, "renderer", st->renderer);
	cJSON_AddNumberToObject(doc, "triangles", (double)rs_scene_triangle_count(scene));
	cJSON_AddStringToObject(doc, "bvh", rs_bvh_builder_name(d->bvh.builder));
	add_option(doc, "nodes", d, "nodes");
	if (strcmp(st->backend, "cpu") != 0) /* the storage set_scene chose */
		add_option(doc, "scene_storage",
		           &(struct rs_render_desc){.scene_storage = st->scene_storage},
		           "scene-storage");
	cJSON_AddNumberToObject(doc, "passes", d->passes);
	cJSON_AddNumberToObject(doc, "lights", (double)lights_used(d, scene));
	cJSON_AddNumberToObject(doc, "width", d->width);
	cJSON_AddNumberToObject(doc, "height", d->height);
	add_option(doc, "triangle_test", d, "triangle-test");
	add_option(doc, "primary", d, "primary");
	add_option(doc, "shadows", d, "shadows");
	if (strcmp(st->backend, "cpu") != 0) /* "kernels" is the per-kernel times' list */
		add_option(doc, "kernel_stage", d, "kernels");
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
	if (o->animate) {
		cJSON_AddNumberToObject(doc, "frame", o->frame + o->animate - 1);
		cJSON_AddNumberToObject(doc, "updates", st->updates);
		cJSON_AddNumberToObject(doc, "update_rebuilds", st->update_rebuilds);
		cJSON_AddNumberToObject(doc, "update_sah_ratio", st->update_sah_ratio);
		cJSON_AddNumberToObject(doc, "refit_ms", st->refit_ms);
		cJSON_AddNumberToObject(doc, "upload_bytes", (double)st->upload_bytes);
		cJSON_AddNumberToObject(doc, "instance_updates", st->instance_updates);
		cJSON_AddNumberToObject(doc, "tlas_build_ms", st->tlas_build_ms);
	}
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

/* `path` for frame `frame` of an --animate run: FILE-NNNN.ext (as given without --animate). */
static const char *frame_path(const struct options *o, const char *path, uint32_t frame, char *buf,
                              size_t cap)
{
	if (!o->animate)
		return path;
	const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
	if (!dot || (slash && dot < slash))
		dot = path + strlen(path);
	snprintf(buf, cap, "%.*s-%04u%s", (int)(dot - path), path, frame, dot);
	return buf;
}

/* The image as --out names it: PNG from the linear floats, JPEG from RGBA8. */
static enum rs_status write_image(const struct options *o, const char *path,
                                  const struct rs_frame *f, uint32_t w, uint32_t h,
                                  struct rs_error *err)
{
	if (o->jpeg)
		return rs_jpeg_write(path, f->rgba8, w, h, 95, err);
	return rs_image_write_png(path, f->rgb, w, h, err);
}

/* One sample as refinement averages it: what a frame shows, clamped to [0, 1] (NaN: 0). */
static double shown(float c)
{
	return c > 0.0f ? (c < 1.0f ? (double)c : 1.0) : 0.0;
}

/* --samples N: frames 0..N-1 of the camera's sub-pixel sequence (rs_camera.sample) averaged
 * in double, the image a still viewer's refinement converges to: the mean of what each
 * frame shows (docs/view.md). `f` holds frame 0. */
static enum rs_status average_samples(const struct options *o, const struct rs_scene *scene,
                                      struct rs_renderer *renderer, const struct rs_frame *f,
                                      uint32_t w, uint32_t h, struct rs_error *err)
{
	size_t n = (size_t)w * h * 3;
	double *sum = malloc(n * sizeof *sum);
	if (!sum)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory for a %ux%u image", w, h);
	for (size_t i = 0; i < n; ++i)
		sum[i] = shown(f->rgb[i]);
	struct rs_camera cam = *rs_scene_camera(scene);
	struct rs_frame one = {.rgb = f->rgb};
	enum rs_status st = RS_OK;
	for (uint32_t k = 1; k < o->samples && st == RS_OK; ++k) {
		cam.sample = k;
		st = rs_renderer_render(renderer, &cam, &one, err);
		for (size_t i = 0; st == RS_OK && i < n; ++i)
			sum[i] += shown(f->rgb[i]);
	}
	for (size_t i = 0; st == RS_OK && i < n; ++i)
		f->rgb[i] = (float)(sum[i] / o->samples);
	if (st == RS_OK && f->rgba8)
		rs_image_quantize(f->rgb, w, h, f->rgba8);
	free(sum);
	return st;
}

static int run(const struct options *o)
{
	struct rs_error err = {0}, note = {0};
	struct rs_scene *scene = NULL;
	struct rs_renderer *renderer = NULL;
	float *rgb = NULL, *depth = NULL;
	uint8_t *rgba8 = NULL;
	const char *written[3] = {NULL, NULL, NULL}; /* outputs of this run, removed on failure */
	int code = 1;
	struct rs_scene *next = NULL;
	if (rs_scenegen_load_frame(o->scene, o->frame, o->fps, &scene, &err) != RS_OK)
		goto done;
	struct rs_render_desc desc = o->desc;
	/* The paper's hit numbers are counted, except with compute kernels: a counting frame
	 * runs the separate chain in fragment passes, so counting would not run what was
	 * asked for (the line and the stats then say "not counted"). */
	desc.counters = desc.kernels != RS_KERNELS_COMPUTE;
	long online = sysconf(_SC_NPROCESSORS_ONLN);
	if (!desc.threads) /* named in the stats: the count the CPU backend will use */
		desc.threads =
		    online > 0 && online <= (long)RS_RENDER_MAX_THREADS ? (uint32_t)online : 1u;
	enum rs_status st = rs_renderer_open_noted(NULL, &desc, &renderer, &note, &err);
	rs_cli_note(&prog, note.message);
	if (st != RS_OK || rs_renderer_set_scene(renderer, scene, &err) != RS_OK)
		goto done;
	const struct rs_render_desc *d = rs_renderer_desc(renderer);
	uint32_t w = d->width, h = d->height;
	rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
	depth = malloc((size_t)w * h * sizeof *depth);
	rgba8 = o->jpeg ? malloc((size_t)w * h * 4) : NULL;
	if (!rgb || !depth || (o->jpeg && !rgba8)) {
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory for a %ux%u image", w, h);
		goto done;
	}
	struct rs_frame frame = {.rgb = rgb, .rgba8 = rgba8, .depth = o->depth ? depth : NULL};
	double ms = 0.0;
	uint32_t frames = o->animate ? o->animate : 1u;
	for (uint32_t k = 0; k < frames; ++k) {
		uint32_t f = o->frame + k;
		/* the next frame's scene replaces this one's only once the renderer holds it */
		if (k > 0) {
			if (rs_scenegen_load_frame(o->scene, f, o->fps, &next, &err) != RS_OK)
				goto done;
			/* an instanced herd (cowNi) moves by its instance transforms */
			if ((rs_scene_instance_count(next)
			         ? rs_renderer_update_instances(renderer, next, &err)
			         : rs_renderer_update_vertices(renderer, next, &err)) != RS_OK)
				goto done;
			rs_scene_destroy(&scene);
			scene = next;
			next = NULL;
		}
		double t0 = rs_now_ms();
		if (rs_renderer_render(renderer, NULL, &frame, &err) != RS_OK)
			goto done;
		if (o->samples > 1 &&
		    average_samples(o, scene, renderer, &frame, w, h, &err) != RS_OK)
			goto done;
		ms = rs_now_ms() - t0;
		char names[2][4096];
		const char *out =
		    o->out ? frame_path(o, o->out, f, names[0], sizeof names[0]) : NULL;
		const char *dpath =
		    o->depth ? frame_path(o, o->depth, f, names[1], sizeof names[1]) : NULL;
		if (out && write_image(o, out, &frame, w, h, &err) != RS_OK)
			goto done;
		if (dpath && rs_image_write_pfm(dpath, depth, w, h, 1, &err) != RS_OK)
			goto done;
		if (o->animate) { /* every frame's files are named as they are written */
			if (out)
				rs_cli_wrote(out);
			if (dpath)
				rs_cli_wrote(dpath);
			continue;
		}
		written[0] = o->out;
		written[1] = o->depth;
	}
	if (o->stats) {
		cJSON *doc = stats_json(o, scene, renderer, ms);
		enum rs_status s = doc ? rs_tool_write_json(o->stats, doc, &err)
		                       : rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory");
		cJSON_Delete(doc);
		if (s != RS_OK)
			goto done;
	}
	written[2] = o->stats;
	const struct rs_render_stats *rst = rs_renderer_stats(renderer);
	printf("%s: %zu triangles, %s (%s), bvh %s (%.1f ms), %ux%u, %u pass(es), %u light(s): "
	       "%.1f ms",
	       o->scene, rs_scene_triangle_count(scene), rst->backend, rst->renderer,
	       rs_bvh_builder_name(d->bvh.builder), rst->build_ms, w, h, d->passes,
	       lights_used(d, scene), ms);
	if (rst->counters_valid)
		printf(", hit numbers %.3f (box %.3f + triangle %.3f)", rst->total_per_pixel,
		       rst->box_per_pixel, rst->triangle_per_pixel);
	else if (d->kernels == RS_KERNELS_COMPUTE && strcmp(rst->backend, "cpu") != 0)
		printf(", compute kernels (hit numbers not counted)");
	printf("\n");
	for (int i = 0; i < 3; ++i)
		if (written[i])
			rs_cli_wrote(written[i]);
	code = 0;
done:
	if (code != 0) {
		rs_cli_fail(&prog, &err);
		/* A failed run leaves none of its outputs: a PNG without the stats or depth
		 * the caller asked for would pass for a complete result. */
		for (int i = 0; i < 2; ++i)
			if (written[i])
				unlink(written[i]);
	}
	free(rgb);
	free(rgba8);
	free(depth);
	rs_renderer_destroy(&renderer);
	rs_scene_destroy(&next);
	rs_scene_destroy(&scene);
	return code;
}

int main(int argc, char **argv)
{
	struct options o;
	int code = parse_args(argc, argv, &o);
	if (code)
		return code < 0 ? 0 : code;
	return run(&o);
}
