/* The CPU reference render split across threads: threads take bands of rows from a shared
 * counter, so the busy middle of the image does not land on one thread. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "tool_common.h"

struct render_job {
	const struct rs_scene *scene;
	const struct rs_packed *packed;
	struct rs_trace_desc desc;
	atomic_uint *next_row;
	float *rgb, *depth;
	struct rs_trace_stats stats;
	struct rs_error err;
	enum rs_status status;
};

/* Add the counts of `s` to `sum`; the per-pixel means are derived once at the end. */
static void stats_add(struct rs_trace_stats *sum, const struct rs_trace_stats *s)
{
	sum->pixels += s->pixels;
	sum->rays += s->rays;
	sum->shadow_rays += s->shadow_rays;
	sum->box_tests += s->box_tests;
	sum->triangle_tests += s->triangle_tests;
}

static void *render_rows(void *arg)
{
	struct render_job *job = arg;
	const uint32_t band = 4;
	for (;;) {
		uint32_t begin = atomic_fetch_add(job->next_row, band);
		if (begin >= job->desc.height)
			break;
		struct rs_trace_desc d = job->desc;
		d.row_begin = begin;
		d.row_end = begin + band < d.height ? begin + band : d.height;
		struct rs_trace_stats s;
		job->status = rs_trace_render(job->scene, job->packed, &d, job->rgb, job->depth, &s,
		                              &job->err);
		if (job->status != RS_OK)
			break;
		stats_add(&job->stats, &s);
	}
	return NULL;
}

enum rs_status rs_tool_render_cpu(const struct rs_scene *scene, const struct rs_packed *packed,
                                  const struct rs_trace_desc *desc, uint32_t threads,
                                  float *out_rgb, float *out_depth,
                                  struct rs_trace_stats *out_stats, struct rs_error *err)
{
	/* The size rs_trace_render() will use: the camera's unless both sides are given. */
	uint32_t width = desc->width, height = desc->height;
	if (width == 0 || height == 0) {
		struct rs_camera cam;
		rs_camera_resolve(rs_scene_camera(scene), &cam);
		width = cam.width;
		height = cam.height;
	}
	if (threads == 0)
		threads = 1;
	if (threads > height)
		threads = height;
	struct render_job *jobs = calloc(threads, sizeof *jobs);
	pthread_t *ids = calloc(threads, sizeof *ids);
	if (!jobs || !ids) {
		free(jobs);
		free(ids);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory starting render threads");
	}
	atomic_uint next_row;
	atomic_init(&next_row, 0);
	uint32_t started = 0;
	for (uint32_t t = 0; t < threads; ++t) {
		jobs[t] = (struct render_job){.scene = scene,
		                              .packed = packed,
		                              .desc = *desc,
		                              .next_row = &next_row,
		                              .rgb = out_rgb,
		                              .depth = out_depth};
		jobs[t].desc.width = width;
		jobs[t].desc.height = height;
		if (t > 0 && pthread_create(&ids[t], NULL, render_rows, &jobs[t]) != 0)
			break;
		started = t + 1;
	}
	if (started > 0)
		render_rows(&jobs[0]);
	for (uint32_t t = 1; t < started; ++t)
		pthread_join(ids[t], NULL);
	/* Threads take rows from the shared counter until none is left, so the ones that did
	 * start (the calling thread at least) have rendered every row: a thread that could not
	 * be created costs time, not rows. */
	enum rs_status status = RS_OK;
	struct rs_trace_stats sum = {0};
	for (uint32_t t = 0; t < started && status == RS_OK; ++t) {
		if (jobs[t].status != RS_OK) {
			status = jobs[t].status;
			if (err)
				*err = jobs[t].err;
			break;
		}
		stats_add(&sum, &jobs[t].stats);
	}
	if (sum.pixels) {
		sum.box_per_pixel = (double)sum.box_tests / (double)sum.pixels;
		sum.triangle_per_pixel = (double)sum.triangle_tests / (double)sum.pixels;
		sum.total_per_pixel = sum.box_per_pixel + sum.triangle_per_pixel;
	}
	if (out_stats)
		*out_stats = sum;
	free(jobs);
	free(ids);
	return status;
}
