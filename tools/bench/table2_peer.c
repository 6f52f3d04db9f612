/* raystream-bench --table 2, the peer: Intel Embree 3 traces the same scene, camera and rays
 * on the same CPU threads. The CPU reference's path logic runs with Embree as its
 * intersector (same primary rays, shadow feelers and reflected/refracted rays, same shading),
 * its image is checked against the reference, and every ray of one frame is recorded and
 * traced again by Embree alone: rays per second of the peer, against which the backend's
 * rays per second (whole frames) are given as a ratio measured in the same run. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "table2.h"
#include "tool_common.h"
#ifdef RS_BENCH_HAVE_EMBREE
#include "peer.h"
#endif

#ifdef RS_BENCH_HAVE_EMBREE
static void summary(double *v, uint32_t n, double *med, double *lo, double *hi)
{
	struct bench_summary s = bench_summarize(v, n);
	*med = s.median;
	*lo = s.min;
	*hi = s.max;
}

/* The peer's replays, each round after one backend frame of the traced setting of `passes`
 * (the timed frames' RGBA8 output), so that a change of the machine's speed falls on both
 * alike: the ratio is taken per round. Without that setting (refused) the replays alone.
 * trace[m][i]: replay m (0 one ray at a time, 1 streams) of round i, ms. */
static enum rs_status alternate(const struct bench_options *o, struct t2_scene *sc, uint32_t passes,
                                struct bench_peer *peer, double trace[2][T2_MAX_REPEATS],
                                struct rs_error *err)
{
	struct t2_peer *p = &sc->peer[passes];
	const struct t2_result *b = t2_traced(sc, passes);
	struct rs_renderer *r = NULL;
	enum rs_status s = RS_OK;
	uint8_t *rgba8 = NULL;
	if (!b->refused) {
		struct rs_render_desc d = t2_desc(o, RS_PRIMARY_TRACE, passes);
		rgba8 = malloc((size_t)o->size * o->size * 4);
		s = rgba8 ? t2_open(o->backend, &d, sc->scene, &r, err)
		          : rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory for the frame");
	}
	struct rs_frame fr = {.rgba8 = rgba8};
	if (r && s == RS_OK)
		s = rs_renderer_render(r, NULL, &fr, err); /* warm-up */
	double back[T2_MAX_REPEATS], ratio[T2_MAX_REPEATS];
	for (uint32_t i = 0; i < o->repeats && s == RS_OK; ++i) {
		if (r) {
			double t0 = rs_now_ms();
			s = rs_renderer_render(r, NULL, &fr, err);
			back[i] = rs_now_ms() - t0;
		}
		for (int m = 0; m < 2 && s == RS_OK; ++m)
			s = bench_peer_replay(peer, m == 1, &trace[m][i], &p->replay_hits[m], err);
		if (r && s == RS_OK) {
			double best = trace[0][i] < trace[1][i] ? trace[0][i] : trace[1][i];
			ratio[i] = ((double)b->rays / back[i]) /
			           ((double)(p->closest + p->occluded) / best);
		}
	}
	rs_renderer_destroy(&r);
	free(rgba8);
	if (s == RS_OK && !b->refused) {
		double lo, hi;
		summary(back, o->repeats, &p->backend_median, &lo, &hi);
		summary(ratio, o->repeats, &p->ratio_median, &p->ratio_min, &p->ratio_max);
		p->alternated = true;
	}
	return s;
}

static int peer_passes(const struct bench_options *o, struct t2_scene *sc, uint32_t passes,
                       const float *ref, float *rgb)
{
	struct t2_peer *p = &sc->peer[passes];
	struct rs_render_desc d = t2_desc(o, RS_PRIMARY_TRACE, passes);
	uint64_t max_rays = (uint64_t)o->size * o->size * passes * (1u + o->lights);
	struct bench_peer *peer = NULL;
	struct rs_renderer *r = NULL;
	struct rs_error err = {0};
	double frame[T2_MAX_REPEATS], trace[2][T2_MAX_REPEATS];
	struct rs_frame fr = {.rgb = rgb};
	enum rs_status s = bench_peer_create(max_rays, o->threads, &peer, &err);
	if (s == RS_OK)
		s = rs_renderer_create_cpu_with(&d, bench_peer_intersector(peer), &r, &err);
	if (s == RS_OK)
		s = rs_renderer_set_scene(r, sc->scene, &err);
	if (s == RS_OK)
		s = rs_renderer_render(r, NULL, &fr, &err); /* warm-up, and the image check */
	if (s == RS_OK)
		rs_image_compare(rgb, ref, o->size, o->size, 3, 1.0, 8.0 / 255.0, &p->diff);
	for (uint32_t i = 0; i < o->repeats && s == RS_OK; ++i) {
		double t0 = rs_now_ms();
		s = rs_renderer_render(r, NULL, &fr, &err);
		frame[i] = rs_now_ms() - t0;
	}
	if (s == RS_OK) {
		bench_peer_record(peer, true);
		s = rs_renderer_render(r, NULL, &fr, &err);
		bench_peer_record(peer, false);
	}
	if (s == RS_OK)
		s = bench_peer_recorded(peer, &p->closest, &p->occluded, &p->hits, &err);
	/* the replays trace Embree's scene over this renderer's packed triangles: kept alive */
	if (s == RS_OK)
		s = alternate(o, sc, passes, peer, trace, &err);
	rs_renderer_destroy(&r);
	bench_peer_destroy(&peer);
	if (s != RS_OK) {
		fprintf(stderr, "raystream-bench: %s peer, %s: %s\n", bench_peer_name(), sc->name,
		        err.message);
		return 1;
	}
	summary(frame, o->repeats, &p->frame_median, &p->frame_min, &p->frame_max);
	for (int m = 0; m < 2; ++m)
		summary(trace[m], o->repeats, &p->trace_median[m], &p->trace_min[m],
		        &p->trace_max[m]);
	p->done = true;
	return 0;
}

int t2_peer_scene(const struct bench_options *o, struct t2_scene *sc, float *const ref[3])
{
	float *rgb = malloc((size_t)o->size * o->size * 3 * sizeof(float));
	if (!rgb) {
		fprintf(stderr, "raystream-bench: out of memory\n");
		return 1;
	}
	int code = peer_passes(o, sc, 1, ref[1], rgb) || peer_passes(o, sc, 2, ref[2], rgb);
	free(rgb);
	return code;
}

void t2_peer_print(const struct bench_options *o, const struct t2_scene *scenes, uint32_t count)
{
	printf(
	    "\nPeer: %s on the same rays and %u thread(s), median (min–max) of %u: one ray at a "
	    "time (rtcIntersect1 / rtcOccluded1) and streams of 256 (rtcIntersect1M / "
	    "rtcOccluded1M, coherent); backend / Embree = the backend's rays per second over "
	    "whole frames against Embree's best of the two over the same rays, measured "
	    "alternately: each of %u round(s) one backend frame (the traced setting, RGBA8) then "
	    "Embree's two replays, the ratio taken per round, median (min–max) of the rounds\n\n",
	    bench_peer_name(), o->threads, o->repeats, o->repeats);
	printf("| scene | passes | Embree rays: closest + shadow (hits; replay hits 1, 1M) | "
	       "Embree ms, 1 ray | Embree ms, streams | Embree Mrays/s, best | Embree + "
	       "reference shading: frame ms | Embree image vs reference | backend rays | backend "
	       "Mrays/s | backend / Embree |\n"
	       "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	for (uint32_t i = 0; i < count; ++i) {
		for (uint32_t passes = 1; passes <= 2; ++passes) {
			const struct t2_peer *p = &scenes[i].peer[passes];
			if (!p->done)
				continue;
			uint64_t rays = p->closest + p->occluded;
			double best = p->trace_median[0] < p->trace_median[1] ? p->trace_median[0]
			                                                      : p->trace_median[1];
			double embree = (double)rays / (best * 1e3);
			const struct t2_result *b = t2_traced(&scenes[i], passes);
			char back[64] = "refused", ratio[64] = "n/a", brays[32] = "-";
			if (p->alternated) { /* the backend's setting ran (not refused) */
				double mr = (double)b->rays / (p->backend_median * 1e3);
				snprintf(brays, sizeof brays, "%llu", (unsigned long long)b->rays);
				snprintf(back, sizeof back, "%.2f", mr);
				snprintf(ratio, sizeof ratio, "%.3f (%.3f–%.3f)", p->ratio_median,
				         p->ratio_min, p->ratio_max);
			}
			printf("| %-5s | %u | %llu + %llu (%llu; %llu, %llu) | %.1f (%.1f–%.1f) | "
			       "%.1f "
			       "(%.1f–%.1f) | %.2f | %.1f (%.1f–%.1f) | %.1f dB, %.3f%%, %s | %s | "
			       "%s | "
			       "%s |\n",
			       scenes[i].name, passes, (unsigned long long)p->closest,
			       (unsigned long long)p->occluded, (unsigned long long)p->hits,
			       (unsigned long long)p->replay_hits[0],
			       (unsigned long long)p->replay_hits[1], p->trace_median[0],
			       p->trace_min[0], p->trace_max[0], p->trace_median[1],
			       p->trace_min[1], p->trace_max[1], embree, p->frame_median,
			       p->frame_min, p->frame_max, p->diff.psnr_db,
			       100.0 * p->diff.bad_share, t2_verdict(&p->diff), brays, back, ratio);
		}
	}
}
#else
int t2_peer_scene(const struct bench_options *o, struct t2_scene *sc, float *const ref[3])
{
	(void)o, (void)sc, (void)ref;
	return 0;
}

void t2_peer_print(const struct bench_options *o, const struct t2_scene *scenes, uint32_t count)
{
	(void)o, (void)scenes, (void)count;
	printf("\nPeer: not built (Intel Embree 3 was not found when this build was configured; "
	       "install libembree-dev, tools/deps.sh does)\n");
}
#endif
