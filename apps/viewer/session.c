/* The viewer's loop: tracker samples -> pose -> camera -> (server | local renderer) ->
 * frame shown; keys; status line; clean shutdown with a stats file. */
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_net.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_tracker.h"
#include "tool_common.h"
#include "viewer.h"

static volatile sig_atomic_t stop_signal;

static void on_signal(int sig)
{
	stop_signal = sig;
}

double viewer_now_s(void)
{
	return (double)app_now_us() * 1e-6;
}

static int fail(const char *what, const struct rs_error *err)
{
	fprintf(stderr, "raystream-viewer: %s%s\n", what, err ? err->message : "");
	return -1;
}

static int setup(struct viewer *v)
{
	struct rs_error err = {0};
	const struct viewer_options *o = &v->o;
	if (rs_scenegen_load(o->scene, &v->scene, &err) != RS_OK)
		return fail("", &err);
	struct rs_pose_layout layout;
	rs_pose_layout_default(&layout);
	if (o->layout && rs_pose_layout_load(o->layout, &layout, &err) != RS_OK)
		return fail("", &err);
	if (rs_pose_solver_create(NULL, &layout, &v->solver, &err) != RS_OK)
		return fail("", &err);
	if (rs_view_create(&o->cal, rs_scene_camera(v->scene), o->width, o->height, &v->view,
	                   &err) != RS_OK)
		return fail("", &err);
	/* a head-coupled view with the default square screen needs a square image */
	struct rs_camera probe;
	struct rs_pose id = {.orientation = {0, 0, 0, 1}};
	if (rs_view_camera_from_pose(rs_view_calibration(v->view), &id, o->width, o->height, &probe,
	                             NULL, &err) == RS_ERR_INVALID)
		return fail("", &err);
	size_t px = (size_t)o->width * o->height;
	v->rgba = calloc(px, 4);
	v->check = calloc(px, 4);
	v->latency_ms = malloc(VIEWER_MAX_SAMPLES * sizeof *v->latency_ms);
	if (!v->rgba || !v->check || !v->latency_ms)
		return fail("out of memory", NULL);
	if (rs_jpeg_create(&v->jpeg, &err) != RS_OK)
		return fail("", &err);
	{ /* always: --local, key switching and --verify-local all render here */
		uint32_t lights = rs_scene_light_count(v->scene) ? 1u : 0u;
		struct rs_render_desc d = {.width = o->width,
		                           .height = o->height,
		                           .passes = o->passes,
		                           .lights = lights,
		                           .threads = o->threads};
		if (rs_renderer_open(o->backend, &d, &v->local, &err) != RS_OK ||
		    rs_renderer_set_scene(v->local, v->scene, &err) != RS_OK)
			return fail("", &err);
	}
	if (rs_tracker_open(o->tracker, &v->tracker, &err) != RS_OK)
		return fail("", &err);
	v->link.fd = -1;
	if (o->server && viewer_connect(v) != 0)
		return -1;
	v->remote = o->start_remote;
	if (!o->headless && viewer_window_open(v) != 0)
		return -1;
	return 0;
}

static void teardown(struct viewer *v)
{
	if (v->link.fd >= 0 || v->link.inbuf)
		viewer_disconnect(v, "viewer closing");
	viewer_window_close(v);
	rs_track_source_destroy(&v->tracker);
	rs_renderer_destroy(&v->local);
	rs_jpeg_destroy(&v->jpeg);
	rs_view_destroy(&v->view);
	rs_pose_solver_destroy(&v->solver);
	rs_scene_destroy(&v->scene);
	free(v->rgba);
	free(v->check);
	free(v->latency_ms);
}

/* Drain the tracker; 1 when a new camera was made, 0 when none, -1 on a fatal error,
 * 2 when the source ended. */
static int track(struct viewer *v, int *recentred)
{
	struct rs_marker_sample s;
	struct rs_pose pose;
	struct rs_pose_quality q = {0};
	int got = 0;
	for (int k = 0; k < 64; ++k) {
		enum rs_status st = rs_track_source_read(v->tracker, &s, 0, NULL);
		if (st == RS_TIMEOUT)
			break;
		if (st == RS_END)
			return got ? 1 : 2;
		if (st == RS_ERR_DISCONNECTED) {
			/* retried every round until the device is back; the view goes stale */
			rs_track_source_reopen(v->tracker, NULL);
			break;
		}
		if (st != RS_OK) {
			fprintf(stderr, "raystream-viewer: tracker: %s\n",
			        rs_track_source_last_error(v->tracker));
			return -1;
		}
		rs_pose_solver_update(v->solver, &s, &pose, &q);
		got = 1;
	}
	if (!got)
		return 0;
	rs_view_update(v->view, &pose, q.status, &v->camera, &v->view_state);
	if (!*recentred && v->view_state == RS_VIEW_FRESH) {
		/* start where the scene's camera is: the handheld's first pose is "home" */
		if (rs_view_recentre_last(v->view, NULL) == RS_OK)
			rs_view_update(v->view, &pose, q.status, &v->camera, &v->view_state);
		*recentred = 1;
	}
	return 1;
}

static void new_camera(struct viewer *v)
{
	++v->pose_id;
	uint32_t slot = v->pose_id % VIEWER_POSE_RING;
	v->ring[slot] = v->camera;
	v->ring_id[slot] = v->pose_id;
	if (v->link.fd >= 0)
		viewer_send_pose(v, &v->camera,
		                 v->view_state == RS_VIEW_FRESH ? 0u : RS_STREAM_POSE_STALE);
	if (!v->remote && v->local) {
		uint64_t t = (uint64_t)(viewer_now_s() * 1e6);
		struct rs_frame f = {.rgba8 = v->rgba};
		struct rs_error err = {0};
		if (rs_renderer_render(v->local, &v->camera, &f, &err) == RS_OK)
			viewer_show(v, (uint32_t)v->frames + 1u, v->pose_id, t);
		else
			fprintf(stderr, "raystream-viewer: local render failed: %s\n", err.message);
	}
}

static int loop(struct viewer *v)
{
	int recentred = 0, code = 0;
	v->started_s = v->last_line_s = viewer_now_s();
	while (!stop_signal) {
		double now = viewer_now_s();
		if (v->o.duration_s > 0 && now - v->started_s >= v->o.duration_s)
			break;
		if (v->o.frames && v->frames >= v->o.frames)
			break;
		int t = track(v, &recentred);
		if (t < 0) {
			code = 1;
			break;
		}
		if (t == 2) /* a replay or a finite simulation ended */
			break;
		if (t == 1)
			new_camera(v);
		if (v->link.fd >= 0) {
			if (viewer_pump(v, t == 1 ? 0 : 1) != 0) {
				code = 1;
				break;
			}
		} else if (t == 0) {
			poll(NULL, 0, 1);
		}
		switch (v->window ? viewer_window_poll(v) : VIEWER_KEY_NONE) {
		case VIEWER_KEY_QUIT:
			stop_signal = 1;
			break;
		case VIEWER_KEY_SWITCH:
			if (v->link.fd >= 0 && v->local)
				v->remote = !v->remote;
			break;
		case VIEWER_KEY_RECENTRE:
			rs_view_recentre_last(v->view, NULL);
			break;
		case VIEWER_KEY_NONE:
			break;
		}
		viewer_status_line(v, viewer_now_s(), 0);
	}
	viewer_status_line(v, viewer_now_s(), 1);
	if (code == 0 && v->o.last && v->have_frame && viewer_write_last(v, v->o.last) != 0)
		code = 1;
	/* keep showing the last frame (redrawn on expose) until the time is up or q */
	double until = viewer_now_s() + v->o.linger_s;
	while (code == 0 && v->window && !stop_signal && viewer_now_s() < until &&
	       viewer_window_poll(v) != VIEWER_KEY_QUIT)
		poll(NULL, 0, 10);
	return code;
}

int viewer_main(struct viewer_options *o)
{
	static struct viewer v;
	memset(&v, 0, sizeof v);
	v.o = *o;
	v.pose_id = o->pose_id_base; /* distinct bases tell viewers' frames apart in tests */
	struct sigaction sa = {.sa_handler = on_signal};
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	signal(SIGPIPE, SIG_IGN);
	int code = setup(&v) == 0 ? loop(&v) : 1;
	if (code == 0 && v.o.stats && viewer_write_stats(&v) != 0)
		code = 1;
	teardown(&v);
	return code;
}
