/* The Embree 3 peer of raystream-bench --table 2 (see peer.h). Embree's geometry is made from
 * the packed triangle texture, so primitive id = packed slot and the reference's shading
 * reads the same triangle; a ray leaving a surface skips that slot through a context
 * filter, as the reference's walk does. Rays go through rtcIntersect1 / rtcOccluded1. */
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../peer.h"

/* A recorded query: the ray as Embree took it, the slot it skips, kind and answer. */
struct recorded {
	struct RTCRay ray;
	uint32_t skip;
	uint8_t occluded_query;
	uint8_t hit;
};

struct skip_context {
	struct RTCIntersectContext ctx; /* first: Embree hands this pointer to the filter */
	uint32_t skip;
};

struct bench_peer {
	RTCDevice device;
	RTCScene scene;
	struct RTCRay *stream[2]; /* recorded closest / shadow rays for rtc*1M, id = slot to skip */
	uint64_t stream_count[2];
	bool stream_ready;
	const struct rs_packed *packed;
	struct rs_trace_intersector isect;
	uint32_t threads;
	struct recorded *rec;
	uint64_t cap;
	atomic_uint_fast64_t count;
	atomic_bool recording;
};

const char *bench_peer_name(void)
{
	return "Embree " RTC_VERSION_STRING;
}

/* The triangle a ray leaves never counts (the reference's skip_slot rule). */
static void skip_filter(const struct RTCFilterFunctionNArguments *args)
{
	const struct skip_context *c = (const struct skip_context *)args->context;
	/* RTCHitN is structure-of-arrays: Ng x, y, z, u, v, primID, ... each N wide. */
	const unsigned *prim = (const unsigned *)args->hit + 5u * args->N;
	for (unsigned i = 0; i < args->N; ++i)
		if (args->valid[i] && prim[i] == c->skip)
			args->valid[i] = 0;
}

/* The same rule for rtcIntersect1M / rtcOccluded1M, whose packets mix rays: each ray's id
 * carries its slot to skip (RTCRayN is structure-of-arrays too: ..., tfar, mask, id). */
static void skip_id_filter(const struct RTCFilterFunctionNArguments *args)
{
	const unsigned *prim = (const unsigned *)args->hit + 5u * args->N;
	const unsigned *id = (const unsigned *)args->ray + 10u * args->N;
	for (unsigned i = 0; i < args->N; ++i)
		if (args->valid[i] && prim[i] == id[i])
			args->valid[i] = 0;
}

static void to_embree(const struct rs_ray *ray, struct RTCRay *out)
{
	out->org_x = (float)ray->origin[0];
	out->org_y = (float)ray->origin[1];
	out->org_z = (float)ray->origin[2];
	out->dir_x = (float)ray->dir[0];
	out->dir_y = (float)ray->dir[1];
	out->dir_z = (float)ray->dir[2];
	out->tnear = (float)ray->tmin;
	out->tfar = (float)ray->tmax; /* +INFINITY stays infinite */
	out->time = 0.0f;
	out->mask = 0xffffffffu;
	out->id = ray->skip_slot; /* RS_NO_SLOT never equals a primitive id */
	out->flags = 0;
}

static void init_context(struct skip_context *c, uint32_t skip)
{
	rtcInitIntersectContext(&c->ctx);
	c->skip = skip;
	if (skip != RS_NO_SLOT)
		c->ctx.filter = skip_filter;
}

static bool trace_closest(RTCScene scene, const struct RTCRay *ray, uint32_t skip,
                          struct RTCRayHit *rh)
{
	struct skip_context c;
	init_context(&c, skip);
	rh->ray = *ray;
	rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
	rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
	rtcIntersect1(scene, &c.ctx, rh);
	return rh->hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

static bool trace_occluded(RTCScene scene, const struct RTCRay *ray, uint32_t skip)
{
	struct skip_context c;
	init_context(&c, skip);
	struct RTCRay r = *ray;
	rtcOccluded1(scene, &c.ctx, &r);
	return r.tfar < 0.0f; /* Embree marks an occluded ray with tfar = -inf */
}

static void record(struct bench_peer *p, const struct RTCRay *ray, uint32_t skip, bool occluded,
                   bool hit)
{
	if (!atomic_load_explicit(&p->recording, memory_order_relaxed))
		return;
	uint64_t i = atomic_fetch_add(&p->count, 1);
	if (i < p->cap)
		p->rec[i] = (struct recorded){
		    .ray = *ray, .skip = skip, .occluded_query = occluded, .hit = hit};
}

static bool peer_closest(void *user, const struct rs_ray *ray, struct rs_hit *out)
{
	struct bench_peer *p = user;
	struct RTCRay r;
	to_embree(ray, &r);
	struct RTCRayHit rh;
	bool hit = trace_closest(p->scene, &r, ray->skip_slot, &rh);
	record(p, &r, ray->skip_slot, false, hit);
	if (!hit)
		return false;
	out->t = rh.ray.tfar;
	out->u = rh.hit.u;
	out->v = rh.hit.v;
	out->slot = rh.hit.primID;
	const float *t0 =
	    rs_pack_texel(&p->packed->triangles, RS_PACK_TRIANGLE_TEXELS, out->slot, 0);
	out->triangle = (uint32_t)t0[3];
	return true;
}

static bool peer_occluded(void *user, const struct rs_ray *ray)
{
	struct bench_peer *p = user;
	struct RTCRay r;
	to_embree(ray, &r);
	bool hit = trace_occluded(p->scene, &r, ray->skip_slot);
	record(p, &r, ray->skip_slot, true, hit);
	return hit;
}

static enum rs_status device_error(struct bench_peer *p, const char *what, struct rs_error *err)
{
	return rs_error_set(err, RS_ERR_DEVICE, "embree: %s failed (error %d)", what,
	                    (int)rtcGetDeviceError(p->device));
}

static enum rs_status peer_prepare(void *user, const struct rs_packed *packed, struct rs_error *err)
{
	struct bench_peer *p = user;
	if (p->scene)
		rtcReleaseScene(p->scene);
	p->scene = NULL;
	p->packed = packed;
	RTCScene scene = rtcNewScene(p->device);
	if (!scene)
		return device_error(p, "rtcNewScene", err);
	rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
	rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
	uint32_t n = packed->triangle_count;
	if (n > 0) {
		RTCGeometry geom = rtcNewGeometry(p->device, RTC_GEOMETRY_TYPE_TRIANGLE);
		float *v =
		    geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
		                                   RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3u * n)
		         : NULL;
		unsigned *idx =
		    geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
		                                   3 * sizeof(unsigned), n)
		         : NULL;
		if (!v || !idx) {
			if (geom)
				rtcReleaseGeometry(geom);
			rtcReleaseScene(scene);
			return device_error(p, "geometry buffers", err);
		}
		for (uint32_t s = 0; s < n; ++s) {
			for (uint32_t k = 0; k < 3; ++k) {
				const float *t = rs_pack_texel(&packed->triangles,
				                               RS_PACK_TRIANGLE_TEXELS, s, k);
				memcpy(v + 9u * s + 3u * k, t, 3 * sizeof(float));
				idx[3u * s + k] = 3u * s + k;
			}
		}
		rtcCommitGeometry(geom);
		rtcAttachGeometry(scene, geom);
		rtcReleaseGeometry(geom);
	}
	rtcCommitScene(scene);
	if (rtcGetDeviceError(p->device) != RTC_ERROR_NONE) {
		rtcReleaseScene(scene);
		return device_error(p, "scene build", err);
	}
	p->scene = scene;
	return RS_OK;
}

enum rs_status bench_peer_create(uint64_t max_rays, uint32_t threads, struct bench_peer **out,
                                 struct rs_error *err)
{
	*out = NULL;
	struct bench_peer *p = calloc(1, sizeof *p);
	if (!p)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "embree: out of memory");
	p->threads = threads ? threads : 1;
	p->cap = max_rays;
	if (max_rays && !(p->rec = malloc(max_rays * sizeof *p->rec))) {
		free(p);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "embree: out of memory for %llu rays",
		                    (unsigned long long)max_rays);
	}
	char config[32];
	snprintf(config, sizeof config, "threads=%u", p->threads);
	p->device = rtcNewDevice(config);
	if (!p->device) {
		free(p->rec);
		free(p);
		return rs_error_set(err, RS_ERR_DEVICE, "embree: rtcNewDevice failed (error %d)",
		                    (int)rtcGetDeviceError(NULL));
	}
	atomic_init(&p->count, 0);
	atomic_init(&p->recording, false);
	p->isect = (struct rs_trace_intersector){
	    .closest = peer_closest, .occluded = peer_occluded, .prepare = peer_prepare, .user = p};
	*out = p;
	return RS_OK;
}

void bench_peer_destroy(struct bench_peer **peer)
{
	if (!peer || !*peer)
		return;
	struct bench_peer *p = *peer;
	if (p->scene)
		rtcReleaseScene(p->scene);
	rtcReleaseDevice(p->device);
	free(p->stream[0]);
	free(p->stream[1]);
	free(p->rec);
	free(p);
	*peer = NULL;
}

const struct rs_trace_intersector *bench_peer_intersector(struct bench_peer *peer)
{
	return &peer->isect;
}

void bench_peer_record(struct bench_peer *peer, bool on)
{
	if (on) {
		atomic_store(&peer->count, 0);
		peer->stream_ready = false;
	}
	atomic_store(&peer->recording, on);
}

enum rs_status bench_peer_recorded(const struct bench_peer *peer, uint64_t *out_closest,
                                   uint64_t *out_occluded, uint64_t *out_hits, struct rs_error *err)
{
	uint64_t n = atomic_load(&peer->count);
	if (n > peer->cap)
		return rs_error_set(err, RS_ERR_LIMIT, "embree: %llu rays, room for %llu",
		                    (unsigned long long)n, (unsigned long long)peer->cap);
	*out_closest = *out_occluded = *out_hits = 0;
	for (uint64_t i = 0; i < n; ++i) {
		*(peer->rec[i].occluded_query ? out_occluded : out_closest) += 1;
		*out_hits += peer->rec[i].hit;
	}
	return RS_OK;
}

struct replay_job {
	struct bench_peer *peer;
	atomic_uint_fast64_t *next;
	uint64_t end;
	uint64_t hits;
};

/* One ray at a time, chunks from a shared counter as the CPU renderer hands out rows. */
static void *replay_single(void *arg)
{
	struct replay_job *job = arg;
	const uint64_t chunk = 1024;
	const struct recorded *rec = job->peer->rec;
	for (;;) {
		uint64_t begin = atomic_fetch_add(job->next, chunk);
		if (begin >= job->end)
			break;
		uint64_t end = begin + chunk < job->end ? begin + chunk : job->end;
		for (uint64_t i = begin; i < end; ++i) {
			struct RTCRayHit rh;
			job->hits +=
			    rec[i].occluded_query
			        ? trace_occluded(job->peer->scene, &rec[i].ray, rec[i].skip)
			        : trace_closest(job->peer->scene, &rec[i].ray, rec[i].skip, &rh);
		}
	}
	return NULL;
}

enum { STREAM_CHUNK = 256 };

/* Streams of STREAM_CHUNK rays of one kind, in recorded order, Embree packing them into
 * packets (coherent: neighbouring pixels' rays come together). Chunk c < the closest-ray
 * chunk count is a closest-hit chunk, the rest shadow chunks. */
static void *replay_stream(void *arg)
{
	struct replay_job *job = arg;
	struct bench_peer *p = job->peer;
	uint64_t closest_chunks = (p->stream_count[0] + STREAM_CHUNK - 1) / STREAM_CHUNK;
	struct RTCRayHit hits[STREAM_CHUNK];
	struct RTCRay shadow[STREAM_CHUNK];
	struct RTCIntersectContext ctx;
	rtcInitIntersectContext(&ctx);
	ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
	ctx.filter = skip_id_filter;
	for (;;) {
		uint64_t c = atomic_fetch_add(job->next, 1);
		if (c >= job->end)
			break;
		int kind = c >= closest_chunks;
		uint64_t begin = (kind ? c - closest_chunks : c) * STREAM_CHUNK;
		uint64_t left = p->stream_count[kind] - begin;
		unsigned n = left < STREAM_CHUNK ? (unsigned)left : STREAM_CHUNK;
		const struct RTCRay *src = p->stream[kind] + begin;
		if (kind) {
			memcpy(shadow, src, n * sizeof *shadow);
			rtcOccluded1M(p->scene, &ctx, shadow, n, sizeof *shadow);
			for (unsigned i = 0; i < n; ++i)
				job->hits += shadow[i].tfar < 0.0f;
		} else {
			for (unsigned i = 0; i < n; ++i) {
				hits[i].ray = src[i];
				hits[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
				hits[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
			}
			rtcIntersect1M(p->scene, &ctx, hits, n, sizeof *hits);
			for (unsigned i = 0; i < n; ++i)
				job->hits += hits[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
		}
	}
	return NULL;
}

/* The recorded rays split by kind for the stream replay (once per recording, not timed). */
static enum rs_status split_streams(struct bench_peer *p, uint64_t n, struct rs_error *err)
{
	if (p->stream_ready)
		return RS_OK;
	uint64_t count[2] = {0, 0};
	for (uint64_t i = 0; i < n; ++i)
		count[p->rec[i].occluded_query]++;
	for (int k = 0; k < 2; ++k) {
		free(p->stream[k]);
		p->stream[k] = malloc((count[k] ? count[k] : 1) * sizeof *p->stream[k]);
		if (!p->stream[k])
			return rs_error_set(err, RS_ERR_NO_MEMORY,
			                    "embree: out of memory for streams");
		p->stream_count[k] = 0;
	}
	for (uint64_t i = 0; i < n; ++i) {
		int k = p->rec[i].occluded_query;
		p->stream[k][p->stream_count[k]++] = p->rec[i].ray;
	}
	p->stream_ready = true;
	return RS_OK;
}

enum rs_status bench_peer_replay(struct bench_peer *peer, bool stream, double *out_ms,
                                 uint64_t *out_hits, struct rs_error *err)
{
	uint64_t n = atomic_load(&peer->count);
	if (!peer->scene || n > peer->cap)
		return rs_error_set(err, RS_ERR_INVALID, "embree: nothing recorded to replay");
	if (stream) {
		enum rs_status s = split_streams(peer, n, err);
		if (s != RS_OK)
			return s;
	}
	uint64_t end = stream ? (peer->stream_count[0] + STREAM_CHUNK - 1) / STREAM_CHUNK +
	                            (peer->stream_count[1] + STREAM_CHUNK - 1) / STREAM_CHUNK
	                      : n;
	void *(*run)(void *) = stream ? replay_stream : replay_single;
	enum { MAX_THREADS = 256 };
	struct replay_job jobs[MAX_THREADS];
	pthread_t ids[MAX_THREADS];
	uint32_t threads = peer->threads < MAX_THREADS ? peer->threads : MAX_THREADS;
	atomic_uint_fast64_t next;
	atomic_init(&next, 0);
	double t0 = rs_now_ms();
	uint32_t started = 1;
	for (uint32_t t = 0; t < threads; ++t) {
		jobs[t] = (struct replay_job){.peer = peer, .next = &next, .end = end};
		if (t > 0 && pthread_create(&ids[t], NULL, run, &jobs[t]) == 0)
			started = t + 1;
		else if (t > 0)
			break;
	}
	run(&jobs[0]);
	for (uint32_t t = 1; t < started; ++t)
		pthread_join(ids[t], NULL);
	*out_ms = rs_now_ms() - t0;
	*out_hits = 0;
	for (uint32_t t = 0; t < started; ++t)
		*out_hits += jobs[t].hits;
	return RS_OK;
}
