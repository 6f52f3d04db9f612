/* What the viewer does with a frame: measure (motion-to-photon latency on its own clock,
 * frame id order, pose ids), optionally check it against a local render, write it
 * (headless) or draw it (window), and report a status line and a stats file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_net.h"
#include "raystream/rs_image.h"
#include "viewer.h"

static void rgba_to_float(const uint8_t *rgba, uint32_t n, float *out)
{
	for (uint32_t i = 0; i < n; ++i)
		for (int c = 0; c < 3; ++c)
			out[3 * i + c] = rgba[4 * i + c] / 255.0f;
}

/* PSNR of the shown frame against a local render of the same camera. */
static void verify(struct viewer *v, uint32_t pose_id)
{
	uint32_t slot = pose_id % VIEWER_POSE_RING;
	if (v->ring_id[slot] != pose_id || !v->local)
		return;
	struct rs_frame f = {.rgba8 = v->check};
	struct rs_error err = {0};
	if (rs_renderer_render(v->local, &v->ring[slot], &f, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: local check render failed: %s\n", err.message);
		return;
	}
	uint32_t n = v->o.width * v->o.height;
	float *a = malloc((size_t)n * 3 * sizeof *a), *b = malloc((size_t)n * 3 * sizeof *b);
	if (a && b) {
		rgba_to_float(v->rgba, n, a);
		rgba_to_float(v->check, n, b);
		struct rs_image_diff d;
		rs_image_compare(a, b, v->o.width, v->o.height, 3, 1.0, 0.1, &d);
		double p = isfinite(d.psnr_db) ? d.psnr_db : 99.0;
		if (v->psnr_n == 0 || p < v->psnr_min)
			v->psnr_min = p;
		v->psnr_sum += p;
		++v->psnr_n;
	}
	free(a);
	free(b);
}

int viewer_write_last(struct viewer *v, const char *path)
{
	uint32_t n = v->o.width * v->o.height;
	float *rgb = malloc((size_t)n * 3 * sizeof *rgb);
	struct rs_error err = {0};
	if (!rgb)
		return -1;
	rgba_to_float(v->rgba, n, rgb);
	/* rs_image_write_png goes through a temporary file and a rename */
	enum rs_status st = rs_image_write_png(path, rgb, v->o.width, v->o.height, &err);
	free(rgb);
	if (st != RS_OK) {
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		return -1;
	}
	return 0;
}

static void write_frame(struct viewer *v)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/frame_%06llu.png", v->o.out_dir,
	         (unsigned long long)v->frames_written);
	if (viewer_write_last(v, path) == 0)
		++v->frames_written;
}

void viewer_show(struct viewer *v, uint32_t frame_id, uint32_t pose_id, uint64_t pose_time_us)
{
	double now = viewer_now_s();
	if (v->latency_n < VIEWER_MAX_SAMPLES)
		v->latency_ms[v->latency_n++] = (now - (double)pose_time_us * 1e-6) * 1e3;
	double lat_ms = (now - (double)pose_time_us * 1e-6) * 1e3; /* what prediction covers */
	v->latency_avg_ms = v->latency_avg_ms > 0 ? 0.9 * v->latency_avg_ms + 0.1 * lat_ms : lat_ms;
	if (v->have_frame) {
		if (frame_id <= v->last_frame_id)
			++v->order_errors;
		else
			v->gaps += frame_id - v->last_frame_id - 1u;
	}
	if (pose_id > v->pose_id || pose_id <= v->o.pose_id_base || pose_id < v->last_pose_id_shown)
		++v->unknown_poses; /* never sent, or older than one already shown */
	v->last_frame_id = frame_id;
	v->last_pose_id_shown = pose_id;
	v->have_frame = 1;
	++v->frames;
	if (v->o.verify_local && v->remote)
		verify(v, pose_id);
	if (v->o.out_dir && (v->frames - 1) % v->o.every == 0)
		write_frame(v);
	if (v->window && !(v->shown && !v->remote)) /* a direct or scaled frame is shown */
		viewer_window_present(v);
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static double percentile(struct viewer *v, double q)
{
	if (v->latency_n == 0)
		return 0.0;
	qsort(v->latency_ms, v->latency_n, sizeof *v->latency_ms, cmp_double);
	size_t i = (size_t)ceil(q * (double)v->latency_n) - 1u;
	return v->latency_ms[i < v->latency_n ? i : v->latency_n - 1];
}

void viewer_status_line(struct viewer *v, double now, int force)
{
	if (!force && now - v->last_line_s < 1.0)
		return;
	double dt = now - v->last_line_s;
	double fps = dt > 0 ? (double)(v->frames - v->frames_at_line) / dt : 0;
	double mbps = dt > 0 ? (double)(v->link.bytes_in - v->bytes_at_line) * 8.0 / dt / 1e6 : 0;
	/* the median of the last second's latencies (the array is sorted only at the end) */
	double lat = 0.0, recent[256];
	uint64_t k = 0;
	for (uint64_t i = v->latency_at_line; i < v->latency_n && k < 256; ++i)
		recent[k++] = v->latency_ms[i];
	if (k) {
		qsort(recent, k, sizeof *recent, cmp_double);
		lat = recent[k / 2];
	}
	v->latency_at_line = v->latency_n;
	char line[256];
	snprintf(
	    line, sizeof line,
	    "%s | %.1f fps | latency %.1f ms median | link %.2f Mbit/s | frame %u pose %u | %s | "
	    "scale %.2f | %u sample(s)",
	    v->remote ? "remote" : "local", fps, lat, mbps, v->last_frame_id, v->last_pose_id_shown,
	    rs_view_state_name(v->view_state),
	    v->remote ? v->remote_scale : app_pace_scales[v->pace.level],
	    v->remote ? v->remote_samples : app_refine_samples(&v->refine));
	printf("raystream-viewer: %s\n", line);
	fflush(stdout);
	if (v->window)
		viewer_window_caption(v, line);
	v->last_line_s = now;
	v->frames_at_line = v->frames;
	v->bytes_at_line = v->link.bytes_in;
}

/* What renders the local frames (and --verify-local's checks): the full-size renderer and
 * its last frame's kernels, so a run can tell which stage ran (compute names "trace
 * compute"). */
static void add_local_renderer(cJSON *doc, const struct viewer *v)
{
	if (!v->local)
		return;
	const struct rs_render_stats *st = rs_renderer_stats(v->local);
	const char *backend = rs_renderer_backend(v->local);
	cJSON *o = cJSON_AddObjectToObject(doc, "local_renderer");
	cJSON_AddStringToObject(o, "backend", backend);
	cJSON_AddStringToObject(o, "renderer", st->renderer);
	if (!strcmp(backend, "cpu")) /* no kernels: --kernels means nothing there */
		return;
	char stage[16];
	rs_render_desc_get(rs_renderer_desc(v->local), "kernels", stage, sizeof stage, NULL);
	cJSON_AddStringToObject(o, "kernel_stage", stage);
	cJSON *list = cJSON_AddArrayToObject(o, "kernels");
	for (uint32_t i = 0; i < st->kernel_count; ++i) {
		cJSON *k = cJSON_CreateObject();
		cJSON_AddStringToObject(k, "name", st->kernels[i].name);
		cJSON_AddNumberToObject(k, "calls", st->kernels[i].calls);
		cJSON_AddNumberToObject(k, "ms", st->kernels[i].ms);
		cJSON_AddItemToArray(list, k);
	}
}

int viewer_write_stats(struct viewer *v)
{
	double secs = viewer_now_s() - v->started_s;
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "mode", v->remote ? "remote" : "local");
	cJSON_AddNumberToObject(doc, "seconds", secs);
	cJSON_AddNumberToObject(doc, "frames", (double)v->frames);
	cJSON_AddNumberToObject(doc, "fps", secs > 0 ? (double)v->frames / secs : 0);
	cJSON_AddNumberToObject(doc, "poses_sent", v->pose_id - v->o.pose_id_base);
	cJSON_AddNumberToObject(doc, "frame_id_gaps", (double)v->gaps);
	cJSON_AddNumberToObject(doc, "frame_order_errors", (double)v->order_errors);
	cJSON_AddNumberToObject(doc, "unknown_pose_ids", (double)v->unknown_poses);
	cJSON_AddNumberToObject(doc, "last_pose_id", v->last_pose_id_shown);
	cJSON_AddNumberToObject(doc, "bytes_received", (double)v->link.bytes_in);
	cJSON_AddNumberToObject(doc, "link_mbps",
	                        secs > 0 ? (double)v->link.bytes_in * 8.0 / secs / 1e6 : 0);
	cJSON_AddNumberToObject(doc, "latency_samples", (double)v->latency_n);
	cJSON_AddNumberToObject(doc, "latency_median_ms", percentile(v, 0.5));
	cJSON_AddNumberToObject(doc, "latency_p99_ms", percentile(v, 0.99));
	cJSON_AddNumberToObject(doc, "frames_written", (double)v->frames_written);
	cJSON_AddNumberToObject(doc, "server_frames_dropped", v->link.server_stats.dropped);
	cJSON_AddNumberToObject(doc, "predicted_ms_mean",
	                        v->predicted_n ? v->predicted_ms_sum / (double)v->predicted_n : 0);
	cJSON_AddNumberToObject(doc, "scale_final",
	                        v->remote ? v->remote_scale : app_pace_scales[v->pace.level]);
	cJSON_AddNumberToObject(doc, "remote_scale_min", v->remote_scale_min);
	cJSON_AddNumberToObject(doc, "scale_steps_down", v->pace.steps_down);
	cJSON_AddNumberToObject(doc, "scale_steps_up", v->pace.steps_up);
	cJSON_AddNumberToObject(doc, "refine_samples",
	                        v->remote ? v->remote_samples : app_refine_samples(&v->refine));
	cJSON_AddNumberToObject(doc, "refine_restarts", v->refine.restarts);
	if (v->psnr_n) {
		cJSON_AddNumberToObject(doc, "psnr_checked", (double)v->psnr_n);
		cJSON_AddNumberToObject(doc, "psnr_min_db", v->psnr_min);
		cJSON_AddNumberToObject(doc, "psnr_mean_db", v->psnr_sum / (double)v->psnr_n);
	}
	add_local_renderer(doc, v);
	struct rs_error err = {0};
	enum rs_status st = app_write_json(v->o.stats, doc, &err);
	cJSON_Delete(doc);
	if (st != RS_OK) {
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		return -1;
	}
	return 0;
}
