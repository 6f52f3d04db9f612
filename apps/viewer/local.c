/* Local rendering: the renderer (in a window, a GPU backend draws on the window's own
 * context and shows each frame with no readback; --present readback keeps the old path)
 * and the frame-rate target (--target-fps): when frames miss the budget the camera is
 * rendered by a renderer of a smaller size (app_pace_scales; opened when first needed)
 * and the display step scales it up to the window. Files (--out, --last) and --headless
 * always get full-size frames: the target is for the window. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"
#include "viewer.h"

/* A renderer of w x h; *direct set when it draws into the window itself. */
static int open_renderer(struct viewer *v, uint32_t w, uint32_t h, struct rs_renderer **out,
                         int *direct)
{
	const struct viewer_options *o = &v->o;
	struct rs_error err = {0};
	struct rs_render_desc d = {.width = w,
	                           .height = h,
	                           .passes = o->passes,
	                           .threads = o->threads,
	                           .kernels = o->kernels};
	int gpu = !strcmp(o->backend, "egl") || !strcmp(o->backend, "auto");
	*direct = 0;
	if (v->window && gpu && !o->readback) {
		if (viewer_window_renderer(v, &d, out, &err) == 0 &&
		    rs_renderer_set_scene(*out, v->scene, &err) == RS_OK) {
			*direct = 1;
			return 0;
		}
		rs_renderer_destroy(out);
		if (strcmp(o->backend, "auto") != 0) {
			fprintf(stderr, "raystream-viewer: --backend egl in the window: %s\n",
			        err.message);
			return -1;
		}
		fprintf(stderr,
		        "raystream-viewer: no GLES context on the window (%s); trying the other "
		        "backends\n",
		        err.message);
	}
	struct rs_error note = {0};
	if (rs_renderer_open_noted(o->backend, &d, out, &note, &err) != RS_OK ||
	    rs_renderer_set_scene(*out, v->scene, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		rs_renderer_destroy(out);
		return -1;
	}
	if (note.message[0]) /* auto fell back to cpu: one line, so slow frames are explained */
		fprintf(stderr, "raystream-viewer: %s\n", note.message);
	return 0;
}

/* Whether this run scales: a window, no files that want full frames. */
static int scaling(const struct viewer *v)
{
	return v->window && !v->o.out_dir && !v->o.last;
}

int viewer_local_open(struct viewer *v)
{
	if (open_renderer(v, v->o.width, v->o.height, &v->local, &v->direct) != 0)
		return -1;
	v->ladder[0] = v->local;
	v->ladder_direct[0] = v->direct;
	app_pace_init(&v->pace, scaling(v) && v->o.fixed_level < 0 ? v->o.target_fps : 0.0);
	/* A scene that moves is never still: averaging its frames would blur the motion. */
	v->refine.enabled = !v->o.no_refine && !v->o.animate;
	if (scaling(v) && v->o.fixed_level > 0)
		v->pace.level = v->o.fixed_level;
	return 0;
}

void viewer_local_close(struct viewer *v)
{
	for (int i = 1; i < APP_PACE_LEVELS; ++i)
		rs_renderer_destroy(&v->ladder[i]);
	rs_renderer_destroy(&v->local);
	v->ladder[0] = NULL;
	free(v->small);
	v->small = NULL;
	app_refine_free(&v->refine);
}

/* The renderer of `level`, opened now if needed; NULL when it cannot be (then the level
 * above is used, and the controller is held there). */
static struct rs_renderer *at_level(struct viewer *v, int level)
{
	if (!v->ladder[level]) {
		uint32_t w, h;
		app_pace_size(level, v->o.width, v->o.height, &w, &h);
		if (open_renderer(v, w, h, &v->ladder[level], &v->ladder_direct[level]) != 0)
			return NULL;
	}
	return v->ladder[level];
}

/* --animate: every open renderer moved to scene frame --frame + k for local frame k (a pure
 * function of the number: raystream-render --frame renders the same); 0 on success. A
 * smaller renderer that cannot follow is closed and reopened on the new scene when needed. */
static enum rs_status move_to(struct rs_renderer *r, const struct rs_scene *next,
                              struct rs_error *err)
{
	/* an instanced herd (cowNi) moves by its instance transforms */
	return rs_scene_instance_count(next) ? rs_renderer_update_instances(r, next, err)
	                                     : rs_renderer_update_vertices(r, next, err);
}

static int animate(struct viewer *v)
{
	uint32_t f = v->o.frame + (uint32_t)v->frames;
	if (f == v->scene_frame)
		return 0;
	struct rs_scene *next = NULL;
	struct rs_error err = {0};
	if (rs_scenegen_load_frame(v->o.scene, f, v->o.animate, &next, &err) != RS_OK ||
	    move_to(v->local, next, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: frame %u: %s\n", f, err.message);
		rs_scene_destroy(&next);
		return -1;
	}
	for (int i = 1; i < APP_PACE_LEVELS; ++i)
		if (v->ladder[i] && move_to(v->ladder[i], next, &err) != RS_OK)
			rs_renderer_destroy(&v->ladder[i]);
	rs_scene_destroy(&v->scene); /* every renderer holds `next` now */
	v->scene = next;
	v->scene_frame = f;
	return 0;
}

void viewer_local_frame(struct viewer *v)
{
	if (v->o.animate && animate(v) != 0)
		return;
	int level = v->pace.level;
	struct rs_renderer *r = level > 0 ? at_level(v, level) : v->local;
	if (!r) {
		v->pace.level = level = level - 1;
		r = v->ladder[level];
	}
	uint32_t w = v->o.width, h = v->o.height;
	app_pace_size(level, v->o.width, v->o.height, &w, &h);
	int direct = v->ladder_direct[level];
	uint8_t *bytes = v->rgba; /* level 0: the frame's bytes where something needs them */
	if (level == 0 && direct && !v->o.out_dir && !v->o.last)
		bytes = NULL;
	if (level > 0 && !direct) {
		uint8_t *b = realloc(v->small, (size_t)w * h * 4u);
		if (!b) {
			fprintf(stderr, "raystream-viewer: out of memory\n");
			return;
		}
		bytes = v->small = b;
	} else if (level > 0) {
		bytes = NULL;
	}
	uint64_t t = (uint64_t)(viewer_now_s() * 1e6);
	struct rs_frame f = {.rgba8 = bytes};
	struct rs_error err = {0};
	/* still: the resting pose's camera at the next sub-pixel sample (a direct renderer
	 * averages on the GPU as it presents; bytes are averaged here) */
	struct rs_camera cam = v->camera;
	app_refine_camera(&v->refine, &v->pose_now, level, &cam);
	if (rs_renderer_render(r, &cam, &f, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: local render failed: %s\n", err.message);
		return;
	}
	if (bytes && v->refine.enabled && app_refine_add(&v->refine, bytes, w, h) != 0)
		fprintf(stderr, "raystream-viewer: out of memory for refinement\n");
	if (level > 0 && !direct)
		viewer_window_present_image(v, v->small, w, h); /* scaled up to the window */
	v->shown = direct || level > 0;
	viewer_show(v, (uint32_t)v->frames + 1u, v->pose_id, t);
	v->shown = 0;
	/* the frame's time from camera to screen decides the next frame's scale */
	double ms = viewer_now_s() * 1e3 - (double)t * 1e-3;
	if (v->o.fixed_level < 0)
		app_pace_update(&v->pace, ms);
}
