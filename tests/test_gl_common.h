/* Shared by test_gl_*.c: GL renderers opened by name, the paper's scenes, and a frame
 * rendered by a GL backend and by the CPU double reference with the same descriptor.
 * A case that cannot get a context skips (gl_skip), and the executable then exits 77
 * (gl_exit), which ctest reports as Skipped (SKIP_RETURN_CODE 77 in tests/CMakeLists.txt),
 * never as Passed; CI has llvmpipe, and tools/test-all.sh fails there on any skip. */
#ifndef TEST_GL_COMMON_H
#define TEST_GL_COMMON_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_image.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"

/* Set once a case could not get a GL context: the run then did not test what it names. */
static bool gl_no_context;

/* Skip this case: no GL context here (gl_open or gl_frame said so). */
#define gl_skip()                                                                                  \
	do {                                                                                       \
		gl_no_context = true;                                                              \
		skip();                                                                            \
	} while (0)

/* main's exit status from cmocka's count of failed cases: 1 on a failure, else 77 when a
 * case had no context (ctest: Skipped), else 0. */
static inline int gl_exit(int failed)
{
	if (failed)
		return 1;
	if (gl_no_context) {
		printf("no GL context here: exit 77 (skipped), not passed\n");
		return 77;
	}
	return 0;
}

/* A GL renderer, or NULL when this build or machine cannot make the context (then
 * gl_skip()). Every NULL also marks the run as skipped, so a case cannot forget to. */
static inline struct rs_renderer *gl_open(const char *backend, const struct rs_render_desc *desc)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	if (!rs_renderer_has_backend(backend)) {
		print_message("%s: not in this build: skipped\n", backend);
		gl_no_context = true;
		return NULL;
	}
	enum rs_status st = rs_renderer_open(backend, desc, &r, &err);
	if (st != RS_OK) {
		print_message("%s: no context here (%s): skipped\n", backend, err.message);
		gl_no_context = true;
		return NULL;
	}
	return r;
}

static inline struct rs_scene *gl_scene(const char *name)
{
	struct rs_error err;
	struct rs_scene *scene = NULL;
	/* The shipped cow found as every program finds it (rs_scenegen_data_path). */
	if (rs_scenegen_load(name, &scene, &err) != RS_OK)
		fail_msg("scenegen %s: %s", name, err.message);
	return scene;
}

/* Render `scene` with renderer `r` into rgb (and depth) of desc's size. */
static inline void gl_render(struct rs_renderer *r, const struct rs_scene *scene, float *rgb,
                             float *depth)
{
	struct rs_error err;
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("set_scene: %s", err.message);
	struct rs_frame frame = {.rgb = rgb, .depth = depth};
	if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("render: %s", err.message);
}

/* A frame's timing of the kernel named `name`, or NULL when the frame ran none. */
static inline const struct rs_render_kernel_time *gl_kernel(const struct rs_render_stats *s,
                                                            const char *name)
{
	for (uint32_t k = 0; k < s->kernel_count; ++k)
		if (strcmp(s->kernels[k].name, name) == 0)
			return &s->kernels[k];
	return NULL;
}

/* How many times a frame ran the kernel named `name` (0: none). */
static inline uint32_t gl_calls(const struct rs_render_stats *s, const char *name)
{
	const struct rs_render_kernel_time *t = gl_kernel(s, name);
	return t ? t->calls : 0;
}

/* Render frame `f` with the renderer's scene and camera; the frame's stats into *out. */
static inline void gl_render_frame(struct rs_renderer *r, const struct rs_frame *f,
                                   struct rs_render_stats *out)
{
	struct rs_error err = {0};
	if (rs_renderer_render(r, NULL, f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
	*out = *rs_renderer_stats(r);
}

/* Every method the fused chain's passes can be (docs/gles.md "Chains"), as frames of at
 * most w x h with 2 lights: traced primaries at 1, 2 and 5 passes, shadow maps and none,
 * classic environment maps (2 passes: one trace pass reading the maps at its end; 1 pass:
 * none read; without shadows), inter-reflection (capture plans each frame), rasterized
 * primaries at 1 and 3 passes, an odd frame size, and cube faces larger than the frame (the
 * targets then larger than the frame). The tests of the fused chain's ways (the display
 * pass fused, compute kernels) each run them all. */
struct gl_fused_case {
	const char *what, *scene;
	struct rs_render_desc desc;
};
#define GL_FUSED_CASES 13

/* The fused-chain tests' descriptor: a w x h frame of `passes` passes with 2 lights. */
static inline struct rs_render_desc gl_fused_desc(uint32_t w, uint32_t h, uint32_t passes)
{
	return (struct rs_render_desc){.width = w, .height = h, .passes = passes, .lights = 2};
}

static inline void gl_fused_cases(uint32_t w, uint32_t h, struct gl_fused_case out[GL_FUSED_CASES])
{
	for (int i = 0; i < GL_FUSED_CASES; ++i)
		out[i].desc = gl_fused_desc(w, h, 2);
	struct rs_render_desc *d;
	out[0].what = "box, 2 passes", out[0].scene = "box";
	out[1].what = "cow1, 1 pass", out[1].scene = "cow1";
	out[1].desc.passes = 1;
	out[2].what = "mirrors, 5 passes", out[2].scene = "mirrors";
	out[2].desc.passes = 5;
	out[3].what = "cow1, shadow maps", out[3].scene = "cow1";
	d = &out[3].desc;
	d->shadows = RS_SHADOW_MAP;
	d->shadow_map_size = 128;
	d->shadow_filter = 3;
	out[4].what = "cow1, no shadows", out[4].scene = "cow1";
	out[4].desc.shadows = RS_SHADOW_NONE;
	for (int i = 5; i < 8; ++i) {
		out[i].scene = "mirrors";
		out[i].desc.reflections = RS_REFLECT_ENVMAP;
		out[i].desc.envmap_size = 32;
	}
	out[5].what = "mirrors, classic map, 2 passes";
	out[6].what = "mirrors, classic map, 1 pass";
	out[6].desc.passes = 1;
	out[7].what = "mirrors, classic map, no shadows";
	out[7].desc.shadows = RS_SHADOW_NONE;
	out[8].what = "mirrors, inter-reflection", out[8].scene = "mirrors";
	d = &out[8].desc;
	d->passes = 3;
	d->reflections = RS_REFLECT_INTERREFLECT;
	d->reflection_bounces = 2;
	d->envmap_size = 24;
	out[9].what = "cow1, raster, 1 pass", out[9].scene = "cow1";
	out[9].desc.passes = 1;
	out[9].desc.primary = RS_PRIMARY_RASTER;
	out[10].what = "cow1, raster, 3 passes", out[10].scene = "cow1";
	out[10].desc.passes = 3;
	out[10].desc.primary = RS_PRIMARY_RASTER;
	for (int i = 11; i < 13; ++i) {
		out[i].desc.width = w < 37 ? w : 37;
		out[i].desc.height = h < 23 ? h : 23;
	}
	out[11].what = "box, 37x23", out[11].scene = "box";
	out[12].what = "mirrors, 37x23, classic map", out[12].scene = "mirrors";
	out[12].desc.reflections = RS_REFLECT_ENVMAP;
	out[12].desc.envmap_size = 40; /* the targets larger than the frame */
}

/* A frame of `scene` on `backend` opened with `desc`: colour and depth (either may be NULL)
 * and, when `stats` is given, the stats copied out (zeroed when there is no frame). False
 * when this machine cannot make the context (the caller gl_skip()s). */
static inline bool gl_frame(const char *backend, const struct rs_render_desc *desc,
                            const struct rs_scene *scene, float *rgb, float *depth,
                            struct rs_render_stats *stats)
{
	if (stats)
		*stats = (struct rs_render_stats){0};
	struct rs_renderer *r = gl_open(backend, desc);
	if (!r)
		return false;
	gl_render(r, scene, rgb, depth);
	if (stats)
		*stats = *rs_renderer_stats(r);
	rs_renderer_destroy(&r);
	return true;
}

/* The CPU reference for the same descriptor. */
static inline void gl_reference(const struct rs_render_desc *desc, const struct rs_scene *scene,
                                float *rgb, float *depth)
{
	struct rs_renderer *cpu = NULL;
	struct rs_error err;
	if (rs_renderer_create_cpu(desc, &cpu, &err) != RS_OK)
		fail_msg("cpu: %s", err.message);
	gl_render(cpu, scene, rgb, depth);
	rs_renderer_destroy(&cpu);
}

/* Six strongly different environment faces with two broad dark bands each, centred at
 * `center` (off the capture points, so a face turned or mirrored in place shows). */
static inline void gl_coloured_environment(struct rs_scene *s, const double center[3],
                                           double half_size)
{
	struct rs_environment env = {.center = {center[0], center[1], center[2]},
	                             .half_size = half_size,
	                             .grid = 2,
	                             .line_width = 0.3f,
	                             .face_color = {{0.9f, 0.1f, 0.1f},
	                                            {0.1f, 0.9f, 0.1f},
	                                            {0.1f, 0.1f, 0.9f},
	                                            {0.9f, 0.9f, 0.1f},
	                                            {0.1f, 0.9f, 0.9f},
	                                            {0.9f, 0.1f, 0.9f}}};
	if (rs_scene_set_environment(s, &env, NULL) != RS_OK)
		fail_msg("environment refused");
}

/* A UV sphere (48 slices, 24 rings, seam vertices repeated) of `material` added to `s`. */
static inline void gl_add_sphere(struct rs_scene *s, const double centre[3], double radius,
                                 uint32_t material)
{
	enum { SL = 48, RI = 24 };
	double *pos = malloc(sizeof(double) * (SL + 1) * (RI + 1) * 3);
	float *nrm = malloc(sizeof(float) * (SL + 1) * (RI + 1) * 3);
	uint32_t *idx = malloc(sizeof(uint32_t) * SL * RI * 6);
	if (!pos || !nrm || !idx)
		fail_msg("out of memory for a sphere");
	size_t v = 0, t = 0;
	for (uint32_t i = 0; i <= RI; ++i)
		for (uint32_t j = 0; j <= SL; ++j, ++v) {
			double th = RS_PI * i / RI, ph = 2.0 * RS_PI * j / SL;
			double n[3] = {sin(th) * cos(ph), cos(th), -sin(th) * sin(ph)};
			for (int k = 0; k < 3; ++k) {
				pos[3 * v + k] = centre[k] + radius * n[k];
				nrm[3 * v + k] = (float)n[k];
			}
		}
	for (uint32_t i = 0; i < RI; ++i)
		for (uint32_t j = 0; j < SL; ++j, t += 2) {
			uint32_t a = i * (SL + 1) + j, b = a + SL + 1;
			uint32_t tri[6] = {a, b, a + 1, a + 1, b, b + 1};
			memcpy(&idx[t * 3], tri, sizeof tri);
		}
	struct rs_mesh_desc m = {.positions_f64 = pos,
	                         .vertex_count = v,
	                         .normals = nrm,
	                         .indices = idx,
	                         .triangle_count = t,
	                         .material = material};
	if (rs_scene_add_mesh(s, &m, NULL) != RS_OK)
		fail_msg("sphere mesh refused");
	free(pos);
	free(nrm);
	free(idx);
}

#endif
