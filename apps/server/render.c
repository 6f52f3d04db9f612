/* Render threads: each owns a renderer and a JPEG encoder, takes the newest pose of the
 * next viewer that needs a frame (round robin), renders, encodes and leaves the FRAME
 * message in that viewer's pending slot for the poll loop. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app_refine.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"
#include "server.h"

struct worker {
	struct server *s;
	struct rs_renderer *renderer;
	/* --target-fps: renderers of the smaller scales (ladder[0] is renderer), opened when a
	 * viewer first needs one */
	struct rs_renderer *ladder[APP_PACE_LEVELS];
	struct rs_render_desc desc;
	struct rs_jpeg *jpeg;
	uint8_t *rgba, *jpg, *msg;
	size_t jpg_cap;
	uint32_t cursor;
	struct rs_scene *scene; /* --animate: this renderer's frame, once it left s->scene */
	uint32_t frame;
};

/* --animate: move this thread's renderer to the frame the clock has reached (a frame is a
 * pure function of its number: raystream-render --frame N renders the same one). */
static enum rs_status follow_clock(struct worker *w, struct rs_error *err)
{
	struct server *s = w->s;
	double elapsed = server_now_s() - s->started_s;
	uint32_t f = s->o.frame + (uint32_t)(elapsed > 0 ? elapsed * s->o.animate : 0);
	if (f == w->frame)
		return RS_OK;
	struct rs_scene *next = NULL;
	enum rs_status st = rs_scenegen_load_frame(s->o.scene, f, s->o.animate, &next, err);
	/* an instanced herd (cowNi) moves by its instance transforms */
	if (st == RS_OK)
		st = rs_scene_instance_count(next)
		         ? rs_renderer_update_instances(w->renderer, next, err)
		         : rs_renderer_update_vertices(w->renderer, next, err);
	if (st != RS_OK) {
		rs_scene_destroy(&next);
		return st;
	}
	rs_scene_destroy(&w->scene); /* the renderer holds `next` now */
	w->scene = next;
	w->frame = f;
	pthread_mutex_lock(&s->lock);
	s->scene_frame = f > s->scene_frame ? f : s->scene_frame;
	pthread_mutex_unlock(&s->lock);
	return RS_OK;
}

static struct worker workers[SERVER_MAX_THREADS];

/* The next viewer with a new pose and room for a frame; drops a pending frame that has
 * waited longer than stale_s when a newer pose is there (a slow reader gets fresh frames,
 * not a backlog). Called with the lock held. */
static struct viewer *pick(struct server *s, struct worker *w)
{
	double now = server_now_s();
	for (uint32_t k = 0; k < SERVER_SLOTS; ++k) {
		uint32_t i = (w->cursor + k) % SERVER_SLOTS;
		struct viewer *v = &s->viewers[i];
		if (!v->active || !v->hello_done || v->closing || !v->pose_new || v->busy)
			continue;
		if (v->pending.full) {
			if (now - v->pending.queued_s <= s->o.stale_s)
				continue;
			v->pending.full = 0;
			++v->frames_dropped;
			++v->next_frame_id; /* the viewer sees the gap */
		}
		w->cursor = i + 1;
		return v;
	}
	return NULL;
}

/* Whether two cameras are the same, field by field (the viewer sends its resting pose's
 * camera unchanged while still). */
static int same_camera(const struct rs_camera *a, const struct rs_camera *b)
{
	for (int i = 0; i < 3; ++i)
		if (a->eye[i] != b->eye[i] || a->target[i] != b->target[i] || a->up[i] != b->up[i])
			return 0;
	return a->fov_y_deg == b->fov_y_deg && a->shift[0] == b->shift[0] &&
	       a->shift[1] == b->shift[1];
}

/* The refinement sample of `pose` for viewer v at render scale `level` (lock held): the next
 * one when its camera and scale are the last one's, else 0 (a restart). */
static uint32_t refine_sample(struct server *s, struct viewer *v, const struct rs_stream_pose *pose,
                              int level)
{
	struct rs_camera cam;
	server_pose_camera(s, pose, &cam);
	/* --animate: the scene moves under a still camera, so every frame restarts. */
	if (v->refine && !s->o.animate && v->refine_have && level == v->refine_level &&
	    same_camera(&cam, &v->refine_cam)) {
		if (v->refine_sample + 1 < APP_REFINE_MAX_SAMPLES)
			++v->refine_sample;
	} else {
		v->refine_cam = cam;
		v->refine_level = level;
		v->refine_have = 1;
		v->refine_sample = 0;
	}
	return v->refine_sample;
}

/* The renderer of render scale `level` (opened now if needed) and its size; level 0 when a
 * smaller one cannot be opened (said once in the log). */
static struct rs_renderer *at_level(struct worker *w, int *level, uint32_t *width, uint32_t *height)
{
	struct server *s = w->s;
	w->ladder[0] = w->renderer;
	if (*level > 0 && !w->ladder[*level]) {
		struct rs_render_desc d = w->desc;
		app_pace_size(*level, s->o.width, s->o.height, &d.width, &d.height);
		struct rs_error err = {0}, note = {0};
		if (rs_renderer_open_noted(s->o.backend, &d, &w->ladder[*level], &note, &err) !=
		        RS_OK ||
		    rs_renderer_set_scene(w->ladder[*level], s->scene, &err) != RS_OK) {
			server_log(s, "render scale %.2f: %s; full size instead",
			           app_pace_scales[*level], err.message);
			rs_renderer_destroy(&w->ladder[*level]);
			*level = 0;
		}
	}
	app_pace_size(*level, s->o.width, s->o.height, width, height);
	return w->ladder[*level];
}

/* Render and encode `pose` at render scale *level and refinement sample `sample` into
 * w->msg, adding it to the mean in *acc; returns the message length, 0 on failure. */
static size_t produce(struct worker *w, const struct rs_stream_pose *pose, int quality, int *level,
                      uint32_t sample, float **acc, uint32_t us[2], struct rs_error *err)
{
	struct server *s = w->s;
	struct rs_camera cam;
	server_pose_camera(s, pose, &cam);
	cam.sample = sample;
	uint32_t fw, fh;
	struct rs_renderer *r = at_level(w, level, &fw, &fh);
	struct rs_frame frame = {.rgba8 = w->rgba};
	if (s->o.animate && follow_clock(w, err) != RS_OK)
		return 0;
	double t0 = server_now_s();
	if (rs_renderer_render(r, &cam, &frame, err) != RS_OK)
		return 0;
	if (!*acc) { /* full size, so every scale fits; a new buffer starts the mean */
		*acc = malloc((size_t)s->o.width * s->o.height * 3u * sizeof **acc);
		sample = 0;
	}
	if (!*acc || app_refine_mean(acc, sample, w->rgba, fw, fh) != 0)
		sample = 0; /* out of memory: the frame as rendered, one sample */
	double t1 = server_now_s();
	struct rs_stream_msg m = {.type = RS_STREAM_FRAME};
	m.u.frame =
	    (struct rs_stream_frame){.pose_id = pose->pose_id,
	                             .pose_time_us = pose->time_us,
	                             .width = (uint16_t)fw,
	                             .height = (uint16_t)fh,
	                             .samples = (uint16_t)(sample < 65534u ? sample + 1 : 65535u)};
	size_t n = (size_t)fw * fh * 4u;
	if (s->o.raw) {
		m.u.frame.encoding = RS_STREAM_ENC_RGBA8;
		m.u.frame.data = w->rgba;
	} else {
		if (rs_jpeg_encode(w->jpeg, w->rgba, fw, fh, quality, s->o.sub, w->jpg, w->jpg_cap,
		                   &n, err) != RS_OK)
			return 0;
		m.u.frame.encoding = RS_STREAM_ENC_JPEG;
		m.u.frame.data = w->jpg;
	}
	double t2 = server_now_s();
	m.u.frame.size = (uint32_t)n;
	m.u.frame.render_us = (uint32_t)((t1 - t0) * 1e6);
	m.u.frame.encode_us = (uint32_t)((t2 - t1) * 1e6);
	us[0] = m.u.frame.render_us;
	us[1] = m.u.frame.encode_us;
	size_t len = 0;
	if (rs_stream_encode(&m, w->msg, s->frame_cap, &len, err) != RS_OK)
		return 0;
	return len;
}

static void *render_main(void *arg)
{
	struct worker *w = arg;
	struct server *s = w->s;
	pthread_mutex_lock(&s->lock);
	while (!s->stop) {
		struct viewer *v = pick(s, w);
		if (!v) {
			pthread_cond_wait(&s->work, &s->lock);
			continue;
		}
		struct rs_stream_pose pose = v->pose;
		uint32_t id = v->id;
		int quality = v->quality;
		int level = v->pace.level;
		uint32_t sample = refine_sample(s, v, &pose, level);
		float *acc = v->refine_acc; /* ours while busy */
		v->refine_acc = NULL;
		v->pose_new = 0;
		v->busy = 1;
		pthread_mutex_unlock(&s->lock);

		struct rs_error err = {0};
		uint32_t us[2] = {0, 0}; /* render, encode */
		size_t len = produce(w, &pose, quality, &level, sample, &acc, us, &err);
		uint32_t render_us = us[0];

		pthread_mutex_lock(&s->lock);
		if (v->id != id) { /* it left while we rendered: the slot may be a new viewer's */
			free(acc);
		} else {
			v->busy = 0;
			v->refine_acc = acc;
			if (len == 0)
				v->refine_have = 0; /* the mean may be partial */
			v->pace.level = level;      /* level 0 when the smaller renderer failed */
			if (len) /* what this viewer's frame cost the server decides its next scale
			          */
				app_pace_update(&v->pace, ((double)us[0] + us[1]) * 1e-3);
		}
		if (len == 0) {
			server_log(s, "viewer %u: pose %u not rendered: %s", id, pose.pose_id,
			           err.message);
			continue;
		}
		if (!v->active || v->id != id)
			continue;      /* it left while we rendered */
		if (v->pending.full) { /* cannot happen while busy guards it; never overwrite */
			++v->frames_dropped;
			++v->next_frame_id;
		}
		uint32_t fid = v->next_frame_id++;
		for (int b = 0; b < 4;
		     ++b) /* the frame id is given at hand-over: ids stay in order */
			w->msg[RS_STREAM_HEADER_SIZE + b] = (uint8_t)(fid >> (8 * b));
		memcpy(v->pending.data, w->msg, len);
		double now = server_now_s();
		v->pending.len = len;
		v->pending.off = 0;
		v->pending.full = 1;
		v->pending.queued_s = now;
		v->pending.ready_s = now + s->o.link_latency_ms * 1e-3;
		++v->frames_rendered;
		++s->frames_rendered;
		s->render_ms_sum += render_us * 1e-3;
		ssize_t wr = write(s->wake[1], "w", 1);
		(void)wr; /* a full pipe already means "wake up" */
	}
	pthread_mutex_unlock(&s->lock);
	return NULL;
}

int server_render_start(struct server *s, pthread_t *threads, uint32_t n)
{
	struct rs_render_desc desc = {.width = s->o.width,
	                              .height = s->o.height,
	                              .passes = s->o.passes,
	                              .lights = s->o.lights,
	                              .shadows = s->o.shadows,
	                              .shadow_map_size = s->o.shadow_map_size,
	                              .shadow_filter = s->o.shadow_filter,
	                              .kernels = s->o.kernels,
	                              .threads = s->o.threads};
	for (uint32_t i = 0; i < n; ++i) {
		struct worker *w = &workers[i];
		struct rs_error err = {0};
		*w = (struct worker){.s = s, .cursor = i, .frame = s->o.frame, .desc = desc};
		w->jpg_cap = rs_jpeg_bound(s->o.width, s->o.height);
		w->rgba = malloc((size_t)s->o.width * s->o.height * 4u);
		w->jpg = malloc(w->jpg_cap);
		w->msg = malloc(s->frame_cap);
		if (!w->rgba || !w->jpg || !w->msg) {
			fprintf(stderr, "raystream-server: out of memory for render buffers\n");
			return -1;
		}
		struct rs_error note = {0};
		if (rs_renderer_open_noted(s->o.backend, &desc, &w->renderer, &note, &err) !=
		        RS_OK ||
		    rs_renderer_set_scene(w->renderer, s->scene, &err) != RS_OK ||
		    rs_jpeg_create(&w->jpeg, &err) != RS_OK) {
			fprintf(stderr, "raystream-server: %s\n", err.message);
			return -1;
		}
		if (note.message[0] && i == 0) /* auto fell back to cpu: say so once */
			fprintf(stderr, "raystream-server: %s\n", note.message);
		s->backend = rs_renderer_backend(w->renderer);
	}
	for (uint32_t i = 0; i < n; ++i)
		if (pthread_create(&threads[i], NULL, render_main, &workers[i]) != 0) {
			fprintf(stderr, "raystream-server: cannot start render thread %u\n", i);
			server_render_stop(s, threads, i);
			return -1;
		}
	return 0;
}

void server_render_stop(struct server *s, pthread_t *threads, uint32_t n)
{
	pthread_mutex_lock(&s->lock);
	s->stop = 1;
	pthread_cond_broadcast(&s->work);
	pthread_mutex_unlock(&s->lock);
	for (uint32_t i = 0; i < n; ++i)
		pthread_join(threads[i], NULL);
	for (uint32_t i = 0; i < SERVER_MAX_THREADS; ++i) {
		struct worker *w = &workers[i];
		for (int l = 1; l < APP_PACE_LEVELS; ++l)
			rs_renderer_destroy(&w->ladder[l]);
		rs_renderer_destroy(&w->renderer);
		rs_scene_destroy(&w->scene); /* after the renderer that held it */
		rs_jpeg_destroy(&w->jpeg);
		free(w->rgba);
		free(w->jpg);
		free(w->msg);
		*w = (struct worker){0};
	}
}
