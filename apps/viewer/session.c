/* The viewer's loop: tracker samples -> pose -> camera -> (server | local renderer) ->
 * frame shown; keys; status line; clean shutdown with a stats file. */
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_scenegen.h"

#include "app_net.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_tracker.h"
#include "viewer.h"

static volatile sig_atomic_t stop_signal;

static void on_signal(int sig)
{
	stop_signal = sig;
}

double viewer_now_s(void)
{
	return rs_now_ms() * 1e-3;
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
	v->scene_frame = o->frame;
	if (rs_scenegen_load_frame(o->scene, o->frame, o->animate, &v->scene, &err) != RS_OK)
		return fail("", &err);
	struct rs_pose_layout layout;
	rs_pose_layout_default(&layout);
	if (o->layout && rs_pose_layout_load(o->layout, &layout, &err) != RS_OK)
		return fail("", &err);
	if (rs_pose_solver_create(NULL, &layout, &v->solver, &err) != RS_OK)
		return fail("", &err);
	struct rs_pose_filter_desc fd = {.disable_filter = 1};
	if (!o->no_predict && rs_pose_filter_create(&fd, &v->filter, &err) != RS_OK)
		return fail("", &err);
	/* camera view without --fov: the scene camera's own, so the first frame is exactly
	 * the scene's view */
	struct rs_view_calibration cal = o->cal;
	if (cal.mode == RS_VIEW_CAMERA && cal.fov_y_deg == 0.0)
		cal.fov_y_deg = rs_scene_camera(v->scene)->fov_y_deg;
	if (rs_view_create(&cal, rs_scene_camera(v->scene), o->width, o->height, &v->view, &err) !=
	    RS_OK)
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
	if (!o->headless && viewer_window_open(v) != 0)
		return -1;
	if (viewer_local_open(v) != 0)
		return -1;
	if (rs_tracker_open(o->tracker, &v->tracker, &err) != RS_OK)
		return fail("", &err);
	v->link.fd = -1;
	if (o->server && viewer_connect(v) != 0)
		return -1;
	v->remote = o->start_remote;
	return 0;
}

static void teardown(struct viewer *v)
{
	if (v->link.fd >= 0 || v->link.inbuf)
		viewer_disconnect(v, "viewer closing");
	viewer_local_close(v); /* before the window: it may draw on its context */
	viewer_window_close(v);
	rs_track_source_destroy(&v->tracker);
	rs_jpeg_destroy(&v->jpeg);
	rs_view_destroy(&v->view);
	rs_pose_solver_destroy(&v->solver);
	rs_pose_filter_destroy(&v->filter);
	rs_scene_destroy(&v->scene);
	free(v->rgba);
	free(v->check);
	free(v->latency_ms);
}

/* Move a fresh pose to the time its frame will be shown: the measured motion-to-photon
 * latency ahead, within the filter's 30 ms cap (held or lost poses are left alone). */
static void predict(struct viewer *v, struct rs_pose *pose, enum rs_pose_status status)
{
	if (!v->filter || (status != RS_POSE_OK && status != RS_POSE_RELABELED))
		return;
	struct rs_pose now;
	if (rs_pose_filter_update(v->filter, pose, &now, NULL) != RS_OK)
		return;
	struct rs_pose ahead;
	double horizon_s = v->latency_avg_ms * 1e-3;
	if (horizon_s > 0 &&
	    rs_pose_filter_predict(v->filter, now.time_s + horizon_s, &ahead, NULL) == RS_OK) {
		v->predicted_ms_sum += (ahead.time_s - now.time_s) * 1e3;
		++v->predicted_n;
		*pose = ahead;
	}
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
	predict(v, &pose, q.status);
	v->pose_now = pose;
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
	/* still: the resting pose's camera, unchanged, so the server refines it (the server
	 * counts the samples itself; the wire has no sample number) */
	struct rs_camera cam = v->camera;
	if (v->link.fd >= 0)
		app_refine_camera(&v->refine_remote, &v->pose_now, 0, &cam);
	cam.sample = 0;
	uint32_t slot = v->pose_id % VIEWER_POSE_RING;
	v->ring[slot] = cam; /* what the server renders, for --verify-local */
	v->ring_id[slot] = v->pose_id;
	if (v->link.fd >= 0)
		viewer_send_pose(v, &cam,
		                 v->view_state == RS_VIEW_FRESH ? 0u : RS_STREAM_POSE_STALE);
	if (!v->remote && v->local)
		viewer_local_frame(v);
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
			app_refine_restart(&v->refine);
			app_refine_restart(&v->refine_remote);
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
	/* --verify-local compares each remote frame with one local sample of its camera */
	v.refine_remote.enabled = !o->no_refine && !o->verify_local;
	v.remote_samples = 1;
	v.remote_scale = v.remote_scale_min = 1.0;
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
