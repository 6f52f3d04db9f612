/* The CPU reference as a render backend: rs_trace_render() over threads that take bands of
 * rows from a shared counter, so the busy middle of the image does not land on one thread. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raystream/rs_image.h"
#include "render_internal.h"

struct cpu_renderer {
	struct rs_render_accel accel;
	const struct rs_scene *scene;
	struct rs_render_desc desc;
	float *rgb; /* scratch when the caller wants only RGBA8 */
	size_t rgb_floats;
	const struct rs_trace_intersector *intersector; /* NULL: the BVH walk */
};

struct band_job {
	const struct cpu_renderer *cpu;
	struct rs_trace_desc desc;
	atomic_uint *next_row;
	float *rgb, *depth;
	struct rs_trace_stats stats;
	struct rs_error err;
	enum rs_status status;
};

static void trace_stats_add(struct rs_trace_stats *sum, const struct rs_trace_stats *s)
{
	sum->pixels += s->pixels;
	sum->rays += s->rays;
	sum->shadow_rays += s->shadow_rays;
	sum->box_tests += s->box_tests;
	sum->triangle_tests += s->triangle_tests;
}

static void *render_bands(void *arg)
{
	struct band_job *job = arg;
	const uint32_t band = 4;
	for (;;) {
		uint32_t begin = atomic_fetch_add(job->next_row, band);
		if (begin >= job->desc.height)
			break;
		struct rs_trace_desc d = job->desc;
		d.row_begin = begin;
		d.row_end = begin + band < d.height ? begin + band : d.height;
		struct rs_trace_stats s;
		job->status = rs_trace_render(job->cpu->scene, &job->cpu->accel.packed, &d,
		                              job->rgb, job->depth, &s, &job->err);
		if (job->status != RS_OK)
			break;
		trace_stats_add(&job->stats, &s);
	}
	return NULL;
}

static uint32_t thread_count(uint32_t asked, uint32_t rows)
{
	long cores = sysconf(_SC_NPROCESSORS_ONLN);
	uint32_t n = asked ? asked : cores > 0 ? (uint32_t)cores : 1u;
	if (n > RS_RENDER_MAX_THREADS)
		n = RS_RENDER_MAX_THREADS;
	return n < rows ? n : rows ? rows : 1u;
}

/* Threads that could not be created cost time, not rows: the ones that did start (the
 * calling thread at least) take rows until none is left. */
static enum rs_status render_threads(const struct cpu_renderer *cpu,
                                     const struct rs_trace_desc *desc, float *rgb, float *depth,
                                     struct rs_trace_stats *out_stats, struct rs_error *err)
{
	struct band_job jobs[RS_RENDER_MAX_THREADS];
	pthread_t ids[RS_RENDER_MAX_THREADS];
	uint32_t threads = thread_count(cpu->desc.threads, desc->height);
	atomic_uint next_row;
	atomic_init(&next_row, 0);
	uint32_t started = 0;
	for (uint32_t t = 0; t < threads; ++t) {
		jobs[t] = (struct band_job){
		    .cpu = cpu, .desc = *desc, .next_row = &next_row, .rgb = rgb, .depth = depth};
		if (t > 0 && pthread_create(&ids[t], NULL, render_bands, &jobs[t]) != 0)
			break;
		started = t + 1;
	}
	render_bands(&jobs[0]);
	for (uint32_t t = 1; t < started; ++t)
		pthread_join(ids[t], NULL);
	struct rs_trace_stats sum = {0};
	for (uint32_t t = 0; t < started; ++t) {
		if (jobs[t].status != RS_OK) {
			if (err)
				*err = jobs[t].err;
			return jobs[t].status;
		}
		trace_stats_add(&sum, &jobs[t].stats);
	}
	*out_stats = sum;
	return RS_OK;
}

static enum rs_status cpu_set_scene(void *impl, const struct rs_scene *scene,
                                    const struct rs_render_desc *desc,
                                    struct rs_render_stats *stats, struct rs_error *err)
{
	struct cpu_renderer *cpu = impl;
	rs_render_accel_free(&cpu->accel);
	cpu->scene = NULL;
	struct rs_bvh_desc bvh = rs_render_bvh_desc(desc);
	bool two_level = false;
	enum rs_status status = rs_render_two_level(desc, scene, &two_level, err);
	if (status == RS_OK && two_level && cpu->intersector) {
		/* a peer intersector answers in the slots of one flattened tree */
		if (desc->instances == RS_INSTANCES_TWO_LEVEL)
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "render: instances two-level: an intersector walks the "
			                    "flattened scene");
		two_level = false;
	}
	if (status == RS_OK)
		status = two_level
		             ? rs_render_accel_build_two_level(scene, &bvh, &desc->pack,
		                                               &cpu->accel, err)
		             : rs_render_accel_build(scene, &bvh, &desc->pack, &cpu->accel, err);
	if (status == RS_OK && cpu->intersector && cpu->intersector->prepare)
		status = cpu->intersector->prepare(cpu->intersector->user, &cpu->accel.packed, err);
	if (status != RS_OK) {
		rs_render_accel_free(&cpu->accel);
		return status;
	}
	size_t floats = (size_t)desc->width * desc->height * 3u;
	if (floats > cpu->rgb_floats) {
		float *rgb = realloc(cpu->rgb, floats * sizeof *rgb);
		if (!rgb) {
			rs_render_accel_free(&cpu->accel);
			return rs_error_set(err, RS_ERR_NO_MEMORY,
			                    "render: out of memory for %ux%u", desc->width,
			                    desc->height);
		}
		cpu->rgb = rgb;
		cpu->rgb_floats = floats;
	}
	cpu->scene = scene;
	cpu->desc = *desc;
	stats->build_ms = cpu->accel.build_ms;
	stats->pack_ms = cpu->accel.pack_ms;
	return RS_OK;
}

/* Triangle ids of the primary hits: the camera rays traced once more (not counted). */
static void primary_ids(const struct cpu_renderer *cpu, const struct rs_camera *camera,
                        uint32_t *out)
{
	uint32_t w = cpu->desc.width, h = cpu->desc.height;
	for (uint32_t y = 0; y < h; ++y)
		for (uint32_t x = 0; x < w; ++x) {
			struct rs_ray ray;
			struct rs_hit hit;
			rs_trace_camera_ray(camera, w, h, x + 0.5, y + 0.5, &ray);
			if (cpu->accel.two_level.instance_count) {
				struct rs_instance_hit ih;
				for (int a = 0; a < 3; ++a) /* R1: the merged packing's frame */
					ray.origin[a] -= cpu->accel.packed.origin[a];
				rs_trace_two_level_closest(&cpu->accel.two_level,
				                           cpu->desc.triangle_test, &ray, &ih,
				                           NULL);
				hit = ih.hit;
			} else {
				rs_trace_closest(&cpu->accel.packed, cpu->desc.triangle_test, &ray,
				                 &hit, NULL);
			}
			out[(size_t)y * w + x] = hit.triangle;
		}
}

static enum rs_status cpu_render(void *impl, const struct rs_camera *camera,
                                 const struct rs_frame *frame, struct rs_render_stats *stats,
                                 struct rs_error *err)
{
	struct cpu_renderer *cpu = impl;
	const struct rs_render_desc *d = &cpu->desc;
	struct rs_trace_desc td = rs_render_trace_desc(d);
	td.camera = camera;
	td.intersector = cpu->intersector;
	td.two_level = cpu->accel.two_level.instance_count ? &cpu->accel.two_level : NULL;
	float *rgb = frame->rgb ? frame->rgb : frame->rgba8 ? cpu->rgb : NULL;
	struct rs_trace_stats ts;
	double t0 = rs_now_ms();
	enum rs_status status = render_threads(cpu, &td, rgb, frame->depth, &ts, err);
	if (status != RS_OK)
		return status;
	stats->render_ms = rs_now_ms() - t0;
	if (frame->triangle)
		primary_ids(cpu, camera, frame->triangle);
	if (frame->rgba8) {
		double t1 = rs_now_ms();
		size_t n = (size_t)d->width * d->height;
		for (size_t i = 0; i < n; ++i) {
			for (int c = 0; c < 3; ++c)
				frame->rgba8[4 * i + c] = rs_image_quantize_value(rgb[3 * i + c]);
			frame->rgba8[4 * i + 3] = 255;
		}
		stats->readback_ms = rs_now_ms() - t1;
	}
	stats->pixels = ts.pixels;
	stats->primary_rays = ts.pixels;
	stats->secondary_rays = ts.rays - ts.pixels;
	stats->shadow_rays = ts.shadow_rays;
	stats->box_tests = ts.box_tests;
	stats->triangle_tests = ts.triangle_tests;
	stats->counters_valid = !cpu->intersector; /* the BVH walk always counts */
	return RS_OK;
}

static enum rs_status cpu_update_vertices(void *impl, const struct rs_scene *scene,
                                          struct rs_render_stats *stats, struct rs_error *err)
{
	struct cpu_renderer *cpu = impl;
	struct rs_render_accel next;
	enum rs_status status =
	    rs_render_accel_update(&cpu->accel, scene, &cpu->desc.bvh, &cpu->desc.pack,
	                           cpu->desc.rebuild_ratio, &next, err);
	if (status == RS_OK && cpu->intersector && cpu->intersector->prepare)
		status = cpu->intersector->prepare(cpu->intersector->user, &next.packed, err);
	if (status != RS_OK) {
		rs_render_accel_free(&next);
		rs_render_accel_free(&cpu->accel);
		cpu->scene = NULL;
		return status;
	}
	rs_render_accel_free(&cpu->accel);
	cpu->accel = next;
	cpu->scene = scene;
	stats->update_rebuilt = next.rebuilt;
	stats->update_sah_ratio = next.sah_ratio;
	stats->refit_ms = next.refit_ms;
	stats->build_ms = next.rebuilt ? next.build_ms : 0.0;
	stats->pack_ms = next.pack_ms;
	return RS_OK;
}

/* Two levels: the TLAS rebuilt and merged in place; flattened: the baked triangles moved. */
static enum rs_status cpu_update_instances(void *impl, const struct rs_scene *scene,
                                           struct rs_render_stats *stats, struct rs_error *err)
{
	struct cpu_renderer *cpu = impl;
	if (!cpu->accel.two_level.instance_count) {
		enum rs_status st = cpu_update_vertices(impl, scene, stats, err);
		stats->instance_update_baked = true;
		return st;
	}
	struct rs_bvh_desc bvh = rs_render_bvh_desc(&cpu->desc);
	enum rs_status st = rs_render_accel_update_instances(&cpu->accel, scene, &bvh, err);
	if (st != RS_OK) {
		rs_render_accel_free(&cpu->accel);
		cpu->scene = NULL;
		return st;
	}
	cpu->scene = scene;
	stats->tlas_build_ms = cpu->accel.tlas_build_ms;
	stats->pack_ms = cpu->accel.pack_ms;
	return RS_OK;
}

static void cpu_destroy(void *impl)
{
	struct cpu_renderer *cpu = impl;
	if (!cpu)
		return;
	rs_render_accel_free(&cpu->accel);
	free(cpu->rgb);
	free(cpu);
}

static void cpu_describe(const void *impl, char *out, size_t cap)
{
	(void)impl;
	snprintf(out, cap, "CPU double-precision reference, %ld cores",
	         sysconf(_SC_NPROCESSORS_ONLN));
}

static const struct rs_renderer_ops cpu_ops = {.name = "cpu",
                                               .set_scene = cpu_set_scene,
                                               .render = cpu_render,
                                               .destroy = cpu_destroy,
                                               .describe = cpu_describe,
                                               .update_vertices = cpu_update_vertices,
                                               .update_instances = cpu_update_instances};

enum rs_status rs_renderer_create_cpu(const struct rs_render_desc *desc, struct rs_renderer **out,
                                      struct rs_error *err)
{
	return rs_renderer_create_cpu_with(desc, NULL, out, err);
}

enum rs_status rs_renderer_create_cpu_with(const struct rs_render_desc *desc,
                                           const struct rs_trace_intersector *intersector,
                                           struct rs_renderer **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	if (desc && desc->primary == RS_PRIMARY_RASTER)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "render: the cpu backend traces primary rays only (no raster)");
	if (desc && desc->shadows == RS_SHADOW_MAP)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "render: the cpu backend has exact shadow rays only (no maps)");
	if (desc && (desc->reflections == RS_REFLECT_ENVMAP ||
	             desc->reflections == RS_REFLECT_INTERREFLECT))
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "render: the cpu backend traces reflections only (no env map)");
	if (intersector && (!intersector->closest || !intersector->occluded))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: the intersector lacks a closest or occluded query");
	struct cpu_renderer *cpu = calloc(1, sizeof *cpu);
	if (!cpu)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "render: out of memory");
	cpu->intersector = intersector;
	return rs_renderer_create(&cpu_ops, cpu, desc, out, err);
}
