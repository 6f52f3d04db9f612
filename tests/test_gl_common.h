/* Shared by test_gl_*.c: GL renderers opened by name (the test skips when no context can
 * be made: CI has llvmpipe, so they run there), the paper's scenes, and a frame rendered
 * by a GL backend and by the CPU double reference with the same descriptor. */
#ifndef TEST_GL_COMMON_H
#define TEST_GL_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_image.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"

/* A GL renderer, or NULL when this machine cannot make the context (then skip()). */
static inline struct rs_renderer *gl_open(const char *backend, const struct rs_render_desc *desc)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	if (!rs_renderer_has_backend(backend))
		return NULL;
	enum rs_status st = rs_renderer_open(backend, desc, &r, &err);
	if (st != RS_OK) {
		print_message("%s: no context here (%s): skipped\n", backend, err.message);
		return NULL;
	}
	return r;
}

static inline struct rs_scene *gl_scene(const char *name)
{
	struct rs_scenegen_desc d;
	struct rs_error err;
	struct rs_scene *scene = NULL;
	if (rs_scenegen_parse(name, &d, &err) != RS_OK)
		fail_msg("%s", err.message);
	d.cow_path = RS_DATA_DIR "/cow.obj";
	if (rs_scenegen_build(&d, &scene, &err) != RS_OK)
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

#endif
