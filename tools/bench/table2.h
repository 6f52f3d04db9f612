/* raystream-bench --table 2: results shared by the backend runs (table2.c) and the Embree
 * peer (table2_peer.c). */
#ifndef RS_BENCH_TABLE2_H
#define RS_BENCH_TABLE2_H

#include "bench.h"
#include "raystream/rs_image.h"
#include "raystream/rs_render.h"

#define T2_SETTINGS 4
#define T2_MAX_REPEATS BENCH_MAX_FRAMES

struct t2_setting {
	const char *name;
	enum rs_primary_mode primary;
	uint32_t passes;
	int paper; /* column of the paper's Table 2, -1: not in the paper */
};
extern const struct t2_setting t2_settings[T2_SETTINGS];

/* One backend setting on one scene. */
struct t2_result {
	bool refused;
	char why[RS_ERROR_MESSAGE_MAX];
	struct bench_frames frames;        /* the timed frames */
	double ms_median, ms_min, ms_max;  /* wall time per frame */
	struct rs_render_stats stats;      /* of the last timed frame */
	struct rs_render_stats rays_stats; /* where the ray counts come from (see rays_from) */
	uint64_t rays;                     /* primary + secondary + shadow */
	const char *rays_from; /* "" (the timed frames), or the source used when the backend
	                          reports no secondary or shadow rays where the reference has */
	double hits;
	bool hits_valid;
	struct rs_image_diff diff; /* against the CPU reference of the same pass count */
	float *rgb;                /* scratch, shared */
	uint8_t *rgba8;
};

/* The peer on one pass count of one scene. */
struct t2_peer {
	bool done;
	uint64_t closest, occluded, hits, replay_hits[2];
	/* Embree alone over the recorded rays: [0] one ray at a time, [1] streams */
	double trace_median[2], trace_min[2], trace_max[2];
	double frame_median, frame_min, frame_max; /* whole frames: Embree under the reference */
	struct rs_image_diff diff;                 /* frame image against the reference */
	/* Measured alternately (t2_peer_scene): each round one backend frame of the traced
	 * setting of this pass count, then Embree's two replays; `alternated` false when the
	 * backend refused that setting (the replays then ran alone). */
	bool alternated;
	double backend_median;                     /* the backend's frame ms, median of rounds */
	double ratio_median, ratio_min, ratio_max; /* backend / Embree rays per second, per round */
};

struct t2_scene {
	const char *name;
	int paper_index;
	size_t triangles;
	struct rs_scene *scene;
	struct t2_result settings[T2_SETTINGS];
	struct rs_render_stats reference[3]; /* the CPU reference's frame, by pass count */
	struct t2_peer peer[3];              /* by pass count (1, 2) */
};

/* The traced setting of `passes` (1 or 2) in t2_settings: the backend's side of the peer. */
static inline const struct t2_result *t2_traced(const struct t2_scene *sc, uint32_t passes)
{
	return &sc->settings[passes == 1 ? 0 : 3];
}

/* Whether an image agrees with the reference well enough to call it the same work: the
 * accuracy bar of the GLES backends (PSNR >= 40 dB, at most 0.1% of pixels off by > 8/255). */
static inline const char *t2_verdict(const struct rs_image_diff *d)
{
	return d->psnr_db >= 40.0 && d->bad_share <= 0.001 ? "agrees" : "DIFFERS";
}

/* The render descriptor of a setting (the peer uses the traced ones). */
struct rs_render_desc t2_desc(const struct bench_options *o, enum rs_primary_mode primary,
                              uint32_t passes);

/* Open `backend` with `d` and upload the scene; RS_ERR_UNSUPPORTED means "refused". */
enum rs_status t2_open(const char *backend, const struct rs_render_desc *d,
                       const struct rs_scene *scene, struct rs_renderer **out,
                       struct rs_error *err);

/* Run the peer on `sc` for 1 and 2 passes, alternating with the backend's traced setting of
 * the same pass count (sc->settings measured first: its rays); ref[p] is the reference image
 * of p passes. */
int t2_peer_scene(const struct bench_options *o, struct t2_scene *sc, float *const ref[3]);
/* The peer's table, with the backend / peer ratios. */
void t2_peer_print(const struct bench_options *o, const struct t2_scene *scenes, uint32_t count);

#endif
