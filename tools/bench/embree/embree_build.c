/* Embree 3's own BVH build as the peer of raystream-bench --table 3 (see peer.h): a scene of
 * one triangle geometry over the caller's mesh, committed at RTC_BUILD_QUALITY_MEDIUM (the
 * builder Embree picks for dynamic scenes) on a device of the given thread count. Only
 * rtcCommitScene is timed (wall clock and the process's CPU time), as only rs_bvh_build is on
 * our side. */
#include <embree3/rtcore.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../peer.h"

struct bench_embree_build {
	RTCDevice device;
	float *vertices; /* padded copy: Embree reads vertex buffers 16 bytes at a time */
	const uint32_t *indices;
	size_t vertex_count, triangle_count;
};

static double clock_ms(clockid_t clock)
{
	struct timespec t;
	clock_gettime(clock, &t);
	return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

enum rs_status bench_embree_build_create(uint32_t threads, const float *positions,
                                         size_t vertex_count, const uint32_t *indices,
                                         size_t triangle_count, struct bench_embree_build **out,
                                         struct rs_error *err)
{
	*out = NULL;
	struct bench_embree_build *b = calloc(1, sizeof *b);
	float *v = malloc((3 * vertex_count + 4) * sizeof *v);
	if (!b || !v) {
		free(b);
		free(v);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "embree: out of memory");
	}
	memcpy(v, positions, 3 * vertex_count * sizeof *v);
	memset(v + 3 * vertex_count, 0, 4 * sizeof *v);
	char config[32];
	snprintf(config, sizeof config, "threads=%u", threads ? threads : 1);
	b->device = rtcNewDevice(config);
	if (!b->device) {
		free(b);
		free(v);
		return rs_error_set(err, RS_ERR_DEVICE, "embree: rtcNewDevice failed (error %d)",
		                    (int)rtcGetDeviceError(NULL));
	}
	*b = (struct bench_embree_build){b->device, v, indices, vertex_count, triangle_count};
	*out = b;
	return RS_OK;
}

enum rs_status bench_embree_build_once(struct bench_embree_build *b, double *out_ms,
                                       double *out_cpu_ms, struct rs_error *err)
{
	RTCScene scene = rtcNewScene(b->device);
	RTCGeometry geom = rtcNewGeometry(b->device, RTC_GEOMETRY_TYPE_TRIANGLE);
	if (!scene || !geom) {
		if (scene)
			rtcReleaseScene(scene);
		return rs_error_set(err, RS_ERR_DEVICE, "embree: scene setup failed (error %d)",
		                    (int)rtcGetDeviceError(b->device));
	}
	rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
	rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, b->vertices,
	                           0, 3 * sizeof(float), b->vertex_count);
	rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, b->indices, 0,
	                           3 * sizeof(uint32_t), b->triangle_count);
	rtcCommitGeometry(geom);
	rtcAttachGeometry(scene, geom);
	rtcReleaseGeometry(geom);
	double t0 = clock_ms(CLOCK_MONOTONIC), c0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
	rtcCommitScene(scene);
	*out_ms = clock_ms(CLOCK_MONOTONIC) - t0;
	*out_cpu_ms = clock_ms(CLOCK_PROCESS_CPUTIME_ID) - c0;
	enum rs_status status = RS_OK;
	if (rtcGetDeviceError(b->device) != RTC_ERROR_NONE)
		status = rs_error_set(err, RS_ERR_DEVICE, "embree: scene build failed");
	rtcReleaseScene(scene);
	return status;
}

void bench_embree_build_destroy(struct bench_embree_build **b)
{
	if (!b || !*b)
		return;
	rtcReleaseDevice((*b)->device);
	free((*b)->vertices);
	free(*b);
	*b = NULL;
}
