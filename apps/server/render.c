/* Render threads: each owns a renderer and a JPEG encoder, takes the newest pose of the
 * next viewer that needs a frame (round robin), renders, encodes and leaves the FRAME
 * message in that viewer's pending slot for the poll loop. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"
#include "server.h"

struct worker {
	struct server *s;
	struct rs_renderer *renderer;
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
	if (st == RS_OK)
		st = rs_renderer_update_vertices(w->renderer, next, err);
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

/* Render and encode `pose` into w->msg; returns the message length, 0 on failure. */
static size_t produce(struct worker *w, const struct rs_stream_pose *pose, int quality,
                      uint32_t *render_us, struct rs_error *err)
{
	struct server *s = w->s;
	struct rs_camera cam;
	server_pose_camera(s, pose, &cam);
	struct rs_frame frame = {.rgba8 = w->rgba};
	if (s->o.animate && follow_clock(w, err) != RS_OK)
		return 0;
	double t0 = server_now_s();
	if (rs_renderer_render(w->renderer, &cam, &frame, err) != RS_OK)
		return 0;
	double t1 = server_now_s();
	struct rs_stream_msg m = {.type = RS_STREAM_FRAME};
	m.u.frame = (struct rs_stream_frame){.pose_id = pose->pose_id,
	                                     .pose_time_us = pose->time_us,
	                                     .width = (uint16_t)s->o.width,
	                                     .height = (uint16_t)s->o.height};
	size_t n = (size_t)s->o.width * s->o.height * 4u;
	if (s->o.raw) {
		m.u.frame.encoding = RS_STREAM_ENC_RGBA8;
		m.u.frame.data = w->rgba;
	} else {
		if (rs_jpeg_encode(w->jpeg, w->rgba, s->o.width, s->o.height, quality, s->o.sub,
		                   w->jpg, w->jpg_cap, &n, err) != RS_OK)
			return 0;
		m.u.frame.encoding = RS_STREAM_ENC_JPEG;
		m.u.frame.data = w->jpg;
	}
	double t2 = server_now_s();
	m.u.frame.size = (uint32_t)n;
	m.u.frame.render_us = (uint32_t)((t1 - t0) * 1e6);
	m.u.frame.encode_us = (uint32_t)((t2 - t1) * 1e6);
	*render_us = m.u.frame.render_us;
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
		v->pose_new = 0;
		v->busy = 1;
		pthread_mutex_unlock(&s->lock);

		struct rs_error err = {0};
		uint32_t render_us = 0;
		size_t len = produce(w, &pose, quality, &render_us, &err);

		pthread_mutex_lock(&s->lock);
		v->busy = 0;
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
	                              .threads = s->o.threads};
	for (uint32_t i = 0; i < n; ++i) {
		struct worker *w = &workers[i];
		struct rs_error err = {0};
		*w = (struct worker){.s = s, .cursor = i, .frame = s->o.frame};
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
		rs_renderer_destroy(&w->renderer);
		rs_scene_destroy(&w->scene); /* after the renderer that held it */
		rs_jpeg_destroy(&w->jpeg);
		free(w->rgba);
		free(w->jpg);
		free(w->msg);
		*w = (struct worker){0};
	}
}
