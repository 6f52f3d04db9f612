/*
 * raystream-report: speed against error. For one scene and size, every setting the
 * render interface offers that trades accuracy for speed (passes, traced or rasterised
 * primary, exact shadow feelers, shadow maps of several sizes and box filters or no
 * shadows, environment maps, BVH builder, triangle test) is rendered by a backend and timed, and
 * its image compared with the CPU double-precision reference at the most passes measured with exact
 * shadows. Out: report.csv, report.md (with the Pareto front and the setting to pick per error
 * budget) and report.png (gnuplot). Progress goes to stderr, one line per setting.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_renderers.h"
#include "report.h"
#include "tool_common.h"

#define MAX_FRAMES 64

struct options {
	const char *scene, *backend, *out;
	uint32_t size, frames, lights, max_passes, threads;
	bool plot, by_cpu, diffs;
};

static void add(struct report *rep, const char *backend, struct rs_render_desc d, const char *label)
{
	if (rep->count == REPORT_MAX_ROWS)
		return;
	struct report_row *r = &rep->rows[rep->count++];
	memset(r, 0, sizeof *r);
	snprintf(r->label, sizeof r->label, "%s", label);
	r->backend = backend;
	r->desc = d;
}

/* The settings: row 0 is the reference setting on the CPU (its error must be exactly 0);
 * then each axis varied from the 2-pass default (or every pass count). */
static void settings(struct report *rep, const struct options *o)
{
	const struct rs_render_desc base = {.width = o->size,
	                                    .height = o->size,
	                                    .passes = 2,
	                                    .lights = o->lights,
	                                    .threads = o->threads,
	                                    .bvh = {.builder = RS_BVH_SAH}};
	bool gl = strcmp(o->backend, "cpu") != 0;
	const char *b = o->backend;
	char label[48];
	struct rs_render_desc d = base;
	d.passes = o->max_passes;
	add(rep, "cpu", d, "cpu reference (self)");
	for (uint32_t p = 1; p <= o->max_passes; ++p) {
		d = base;
		d.passes = p;
		snprintf(label, sizeof label, "%s trace %up", b, p);
		add(rep, b, d, label);
		if (gl) {
			d.primary = RS_PRIMARY_RASTER;
			snprintf(label, sizeof label, "%s raster %up", b, p);
			add(rep, b, d, label);
		}
	}
	/* no shadows at all: what a scene without occluders needs, and the error it costs one
	 * that has them */
	d = base;
	d.shadows = RS_SHADOW_NONE;
	snprintf(label, sizeof label, "%s trace 2p no shadows", b);
	add(rep, b, d, label);
	if (gl) {
		/* shadow map side, box filter; the quick run keeps the plumbing, not the sizes */
		static const uint32_t maps[][2] = {
		    {256, 1}, {256, 3}, {512, 3}, {1024, 3}, {1024, 5}};
		static const uint32_t quick_maps[][2] = {{64, 1}, {128, 3}};
		bool quick = o->size < 128;
		size_t n = quick ? 2 : 5;
		for (size_t m = 0; m < n; ++m) {
			d = base;
			d.shadows = RS_SHADOW_MAP;
			d.shadow_map_size = quick ? quick_maps[m][0] : maps[m][0];
			d.shadow_filter = quick ? quick_maps[m][1] : maps[m][1];
			snprintf(label, sizeof label, "%s trace 2p map %u/%u", b, d.shadow_map_size,
			         d.shadow_filter);
			add(rep, b, d, label);
		}
		for (uint32_t p = 1; p <= 2; ++p) {
			d = base;
			d.passes = p;
			d.primary = RS_PRIMARY_RASTER;
			d.shadows = RS_SHADOW_MAP;
			d.shadow_map_size = quick ? 128 : 512;
			d.shadow_filter = 3;
			snprintf(label, sizeof label, "%s raster %up map %u/3", b, p,
			         d.shadow_map_size);
			add(rep, b, d, label);
		}
	}
	if (gl) {
		/* classic environment mapping: the second pass reads a cube map, no later pass */
		d = base;
		d.reflections = RS_REFLECT_ENVMAP;
		snprintf(label, sizeof label, "%s trace 2p envmap", b);
		add(rep, b, d, label);
		d.shadows = RS_SHADOW_MAP;
		d.shadow_map_size = o->size < 128 ? 128 : 512;
		d.shadow_filter = 3;
		snprintf(label, sizeof label, "%s trace 2p envmap map %u/3", b, d.shadow_map_size);
		add(rep, b, d, label);
		/* the paper's classic method: reflections from the map, no shadows */
		d.shadows = RS_SHADOW_NONE;
		snprintf(label, sizeof label, "%s trace 2p envmap no shadows", b);
		add(rep, b, d, label);
		/* inter-reflection: a map per mirror object, re-captured every frame */
		for (uint32_t k = 1; k <= 2; ++k) {
			d = base;
			d.reflections = RS_REFLECT_INTERREFLECT;
			d.reflection_bounces = k;
			snprintf(label, sizeof label, "%s trace 2p interreflect:%u", b, k);
			add(rep, b, d, label);
		}
	}
	d = base;
	d.bvh.builder = RS_BVH_PAPER;
	snprintf(label, sizeof label, "%s trace 2p paper-bvh", b);
	add(rep, b, d, label);
	d = base;
	d.triangle_test = RS_TRIANGLE_MOLLER_TRUMBORE;
	snprintf(label, sizeof label, "%s trace 2p moller", b);
	add(rep, b, d, label);
}

/* Render `frames` timed frames after a warm-up one; the last frame's colour in `rgb`. */
static enum rs_status measure(const struct rs_scene *scene, struct report_row *row, uint32_t frames,
                              float *rgb, char *renderer, size_t cap, struct rs_error *err)
{
	struct rs_renderer *r = NULL;
	struct rs_frame frame = {.rgb = rgb};
	double ms[MAX_FRAMES], cpu[MAX_FRAMES];
	enum rs_status st = rs_renderer_open(row->backend, &row->desc, &r, err);
	if (st == RS_OK)
		st = rs_renderer_set_scene(r, scene, err);
	if (st == RS_OK)
		st = rs_renderer_render(r, NULL, &frame, err);
	for (uint32_t f = 0; f < frames && st == RS_OK; ++f) {
		double c0 = rs_tool_cpu_ms(), t0 = rs_now_ms();
		st = rs_renderer_render(r, NULL, &frame, err);
		ms[f] = rs_now_ms() - t0;
		cpu[f] = rs_tool_cpu_ms() - c0;
	}
	if (st == RS_OK) {
		qsort(ms, frames, sizeof ms[0], rs_tool_cmp_double);
		qsort(cpu, frames, sizeof cpu[0], rs_tool_cmp_double);
		row->ms_med =
		    frames % 2 ? ms[frames / 2] : 0.5 * (ms[frames / 2 - 1] + ms[frames / 2]);
		row->ms_min = ms[0];
		row->ms_max = ms[frames - 1];
		row->cpu_med = cpu[frames / 2];
		if (renderer)
			snprintf(renderer, cap, "%s", rs_renderer_stats(r)->renderer);
	}
	rs_renderer_destroy(&r);
	return st;
}

/* DIR/diff-NN.png: |setting - reference| x 8 per channel, so an error of 8/255 (the
 * "off" threshold) shows as 64/255 and anything off by 1/8 or more saturates. `img` is
 * overwritten (the next setting renders into it again). */
static enum rs_status write_diff(const char *dir, uint32_t index, float *img, const float *ref,
                                 uint32_t size, struct rs_error *err)
{
	char path[4096];
	size_t n = (size_t)size * size * 3;
	for (size_t k = 0; k < n; ++k)
		img[k] = fminf(8.0f * fabsf(img[k] - ref[k]), 1.0f);
	snprintf(path, sizeof path, "%s/diff-%02u.png", dir, index);
	enum rs_status st = rs_image_write_png(path, img, size, size, err);
	if (st == RS_OK)
		rs_cli_wrote(path);
	return st;
}

static enum rs_status parse_time(void *out, const char *v, struct rs_error *err)
{
	if (strcmp(v, "wall") != 0 && strcmp(v, "cpu") != 0)
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not wall|cpu", v);
	*(bool *)out = !strcmp(v, "cpu");
	return RS_OK;
}

static const char about[] =
    "Renders every setting that trades accuracy for speed on --backend (auto: the GPU\n"
    "where a GL context opens, else cpu, said on stderr), times it and compares it with\n"
    "the CPU reference; writes DIR/report.csv, report.md (Pareto front, pick per error\n"
    "budget) and report.png (gnuplot), making DIR if needed, and names each file on\n"
    "stdout. --quick: box at 32x32, 1 frame, 2 passes (options after it still apply).\n";

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse(int argc, char **argv, struct options *o, struct rs_render_desc *render)
{
	*o = (struct options){
	    .scene = "cow1", .size = 512, .frames = 5, .lights = 1, .max_passes = 5, .plot = true};
	*render = (struct rs_render_desc){0};
	bool quick = false, no_plot = false;
	for (int i = 1; i < argc; ++i)
		quick |= !strcmp(argv[i], "--quick");
	if (quick) /* the defaults of a quick run; options given still win */
		*o = (struct options){
		    .scene = "box", .size = 32, .frames = 1, .lights = 1, .max_passes = 2};
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--out", &o->out, "DIR", "the report's folder (required; made)"),
	    RS_CLI_FLAG_OPT("--quick", &quick, "box, 32x32, 1 frame, 2 passes: the plumbing"),
	    RS_CLI_STRING_OPT("--scene", &o->scene, "SCENE",
	                      "box, mirrors, animated, cowN, cowNi or a mesh file"),
	    RS_CLI_U32_OPT("--size", &o->size, 8, 4096, "image side, pixels"),
	    RS_CLI_U32_OPT("--frames", &o->frames, 1, 64, "timed frames per setting"),
	    RS_CLI_U32_OPT("--lights", &o->lights, 1, 4, "the scene's first N lights"),
	    RS_CLI_U32_OPT("--max-passes", &o->max_passes, 1, 5, "pass counts measured: 1..N"),
	    {.name = "--time",
	     .kind = RS_CLI_CALL,
	     .out = &o->by_cpu,
	     .call = parse_time,
	     .arg = "wall|cpu",
	     .help = "the time the front and the picks use",
	     .fallback = "wall"},
	    RS_CLI_FLAG_OPT("--no-plot", &no_plot, "no report.png"),
	    RS_CLI_FLAG_OPT("--diffs", &o->diffs, "DIR/diff-NN.png: |setting - reference| x 8"),
	};
	struct rs_cli cli = {.prog = "raystream-report",
	                     .usage = "--out DIR [options]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = render,
	                     .render_keys = "backend,threads"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	o->plot = !no_plot;
	o->threads = render->threads;
	if (!o->out)
		return rs_cli_usage_error(&cli, "--out DIR is required");
	const char *b = render->backend ? render->backend : "auto";
	if (!rs_renderer_has_backend(b))
		return rs_cli_usage_error(&cli,
		                          "--backend: '%s' is not part of this build (have: %s)", b,
		                          rs_renderer_backends());
	/* The folder is made (and checked) before a long run, not found missing after it. */
	struct rs_error err = {0};
	struct stat st;
	if (rs_cli_make_dir(o->out, &err) != RS_OK)
		return rs_cli_fail(&cli, &err);
	if (stat(o->out, &st) != 0 || !S_ISDIR(st.st_mode) || access(o->out, W_OK) != 0) {
		rs_error_set(&err, RS_ERR_IO, "%s: not a writable folder", o->out);
		return rs_cli_fail(&cli, &err);
	}
	if (!(o->backend = rs_tool_backend_name(&cli, render, &err)))
		return rs_cli_fail(&cli, &err);
	return 0;
}

static void describe_machine(struct report *rep)
{
	struct utsname u;
	char model[96] = "unknown CPU";
	FILE *f = fopen("/proc/cpuinfo", "r");
	char line[256];
	while (f && fgets(line, sizeof line, f))
		if (!strncmp(line, "model name", 10) && strchr(line, ':')) {
			snprintf(model, sizeof model, "%s", strchr(line, ':') + 2);
			model[strcspn(model, "\n")] = '\0';
			break;
		}
	if (f)
		fclose(f);
	double load[1] = {NAN};
	f = fopen("/proc/loadavg", "r");
	if (f && fscanf(f, "%lf", &load[0]) != 1)
		load[0] = NAN;
	if (f)
		fclose(f);
	rep->load1 = load[0];
	int n = snprintf(rep->machine, sizeof rep->machine, "%s, %ld cores, %s",
	                 uname(&u) == 0 ? u.machine : "?", sysconf(_SC_NPROCESSORS_ONLN), model);
	(void)(n >= (int)sizeof rep->machine); /* a long CPU model name is cut: a label only */
}

int main(int argc, char **argv)
{
	struct options o;
	struct rs_render_desc render;
	int code = parse(argc, argv, &o, &render);
	if (code)
		return code < 0 ? 0 : code;
	static struct report rep;
	rep = (struct report){.scene = o.scene,
	                      .size = o.size,
	                      .frames = o.frames,
	                      .lights = o.lights,
	                      .by_cpu = o.by_cpu,
	                      .diffs = o.diffs,
	                      .max_passes = o.max_passes};
	describe_machine(&rep);
	settings(&rep, &o);
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	size_t n = (size_t)o.size * o.size * 3;
	float *ref = malloc(n * sizeof(float)), *img = malloc(n * sizeof(float));
	code = 1;
	if (!ref || !img) {
		rs_error_set(&err, RS_ERR_NO_MEMORY, "out of memory for %ux%u images", o.size,
		             o.size);
		goto done;
	}
	if (rs_scenegen_load(o.scene, &scene, &err) != RS_OK)
		goto done;
	if (o.lights > rs_scene_light_count(scene)) {
		rs_error_set(&err, RS_ERR_INVALID, "%s has %zu lights, --lights %u", o.scene,
		             rs_scene_light_count(scene), o.lights);
		goto done;
	}
	/* The reference: its own renderer and frame; row 0 renders the same setting again. */
	struct report_row reference = rep.rows[0];
	if (measure(scene, &reference, 1, ref, NULL, 0, &err) != RS_OK)
		goto done;
	struct rs_report_point pts[REPORT_MAX_ROWS];
	for (uint32_t i = 0; i < rep.count; ++i) {
		struct report_row *row = &rep.rows[i];
		bool own = i == 1 || (i > 0 && strcmp(row->backend, rep.rows[i - 1].backend) != 0);
		enum rs_status ms = measure(scene, row, o.frames, img, own ? rep.renderer : NULL,
		                            sizeof rep.renderer, &err);
		if (ms == RS_ERR_UNSUPPORTED || ms == RS_ERR_LIMIT) {
			/* A setting this scene cannot have (more mirror objects than the
			 * inter-reflection maps hold) is a row of the report, not a failure. */
			row->refused = true;
			snprintf(row->why, sizeof row->why, "%s", err.message);
			row->ms_med = row->ms_min = row->ms_max = row->cpu_med = NAN;
			row->diff.bad_share = NAN;
			pts[i] = (struct rs_report_point){NAN, NAN};
			fprintf(stderr, "[%u/%u] %-28s refused: %s\n", i + 1, rep.count, row->label,
			        row->why);
			continue;
		}
		if (ms != RS_OK) {
			rs_error_prefix(&err, err.status, "%s", row->label);
			goto done;
		}
		rs_image_compare(img, ref, o.size, o.size, 3, 1.0, 8.0 / 255.0, &row->diff);
		if (o.diffs && write_diff(o.out, i, img, ref, o.size, &err) != RS_OK)
			goto done;
		pts[i] = (struct rs_report_point){report_time(&rep, row), row->diff.bad_share};
		fprintf(stderr, "[%u/%u] %-28s %9.1f ms  PSNR %6.2f dB  off>8/255 %6.3f%%\n", i + 1,
		        rep.count, row->label, row->ms_med, row->diff.psnr_db,
		        100.0 * row->diff.bad_share);
	}
	bool front[REPORT_MAX_ROWS];
	rs_report_pareto(pts, rep.count, front);
	for (uint32_t i = 0; i < rep.count; ++i)
		rep.rows[i].front = front[i];
	if (report_write(&rep, o.out, o.plot, &err) == RS_OK)
		code = 0;
done:
	if (code)
		fprintf(stderr, "raystream-report: %s\n", err.message);
	rs_scene_destroy(&scene);
	free(ref);
	free(img);
	return code;
}
