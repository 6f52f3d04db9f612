/*
 * raystream-report: speed against error. For one scene and size, every setting the
 * render interface offers that trades accuracy for speed (passes, traced or rasterised
 * primary, exact shadow feelers or shadow maps of several sizes and box filters, BVH
 * builder, triangle test) is rendered by a backend and timed, and its image compared with
 * the CPU double-precision reference at the most passes measured with exact shadows. Out:
 * report.csv, report.md (with the Pareto front and the setting to pick per error budget)
 * and report.png (gnuplot). Progress goes to stderr, one line per setting.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "raystream/rs_renderers.h"
#include "report.h"
#include "tool_common.h"

#define MAX_FRAMES 64

struct options {
	const char *scene, *backend, *out;
	uint32_t size, frames, lights, max_passes, threads;
	bool plot, by_cpu, diffs;
};

static int usage(void)
{
	fprintf(stderr, "usage: raystream-report [--quick] [--scene NAME] [--size N] "
	                "[--backend cpu|egl|osmesa] [--frames N] [--lights N] [--max-passes N] "
	                "[--threads N] [--time wall|cpu] [--no-plot] [--diffs] --out DIR\n");
	return 2;
}

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
	return rs_image_write_png(path, img, size, size, err);
}

static int parse(int argc, char **argv, struct options *o)
{
	*o = (struct options){
	    .scene = "cow1", .size = 512, .frames = 5, .lights = 1, .max_passes = 5, .plot = true};
	o->backend = rs_renderer_has_backend("egl") ? "egl" : "cpu";
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "--quick")) {
			o->scene = "box";
			o->size = 32;
			o->frames = 1;
			o->max_passes = 2;
			continue;
		}
		if (!strcmp(a, "--no-plot")) {
			o->plot = false;
			continue;
		}
		if (!strcmp(a, "--diffs")) {
			o->diffs = true;
			continue;
		}
		if (!strcmp(a, "--time")) {
			if (!v || (strcmp(v, "wall") != 0 && strcmp(v, "cpu") != 0)) {
				fprintf(stderr,
				        "raystream-report: --time wants wall or cpu, not '%s'\n",
				        v ? v : "");
				return 2;
			}
			o->by_cpu = !strcmp(v, "cpu");
			++i;
			continue;
		}
		if (!strcmp(a, "--help"))
			return usage();
		uint32_t *dst = !strcmp(a, "--size")         ? &o->size
		                : !strcmp(a, "--frames")     ? &o->frames
		                : !strcmp(a, "--lights")     ? &o->lights
		                : !strcmp(a, "--max-passes") ? &o->max_passes
		                : !strcmp(a, "--threads")    ? &o->threads
		                                             : NULL;
		const char **sdst = !strcmp(a, "--scene")     ? &o->scene
		                    : !strcmp(a, "--backend") ? &o->backend
		                    : !strcmp(a, "--out")     ? &o->out
		                                              : NULL;
		if (!dst && !sdst) {
			fprintf(stderr, "raystream-report: unknown option '%s'\n", a);
			return 2;
		}
		if (!v) {
			fprintf(stderr, "raystream-report: %s needs a value\n", a);
			return 2;
		}
		++i;
		uint32_t max = dst == &o->frames       ? MAX_FRAMES
		               : dst == &o->max_passes ? 5
		               : dst == &o->lights     ? 4
		               : dst == &o->threads    ? RS_RENDER_MAX_THREADS
		                                       : 4096;
		if (sdst)
			*sdst = v;
		else if (!rs_tool_parse_u32(v, dst == &o->size ? 8 : 1, max, dst)) {
			fprintf(stderr, "raystream-report: bad value for %s: '%s' (1..%u)\n", a, v,
			        max);
			return 2;
		}
	}
	if (!o->out) {
		fprintf(stderr, "raystream-report: --out DIR is required\n");
		return 2;
	}
	if (!rs_renderer_has_backend(o->backend)) {
		fprintf(stderr, "raystream-report: unknown backend '%s' (this build has %s)\n",
		        o->backend, rs_renderer_backends());
		return 2;
	}
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
	int code = parse(argc, argv, &o);
	if (code)
		return code;
	static struct report rep;
	rep = (struct report){.scene = o.scene,
	                      .size = o.size,
	                      .frames = o.frames,
	                      .lights = o.lights,
	                      .by_cpu = o.by_cpu,
	                      .diffs = o.diffs,
	                      .max_passes = o.max_passes};
	/* A long run must not end in an unwritable folder. */
	struct stat st;
	if (stat(o.out, &st) != 0 || !S_ISDIR(st.st_mode) || access(o.out, W_OK) != 0) {
		fprintf(stderr, "raystream-report: %s: not a writable folder\n", o.out);
		return 1;
	}
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
