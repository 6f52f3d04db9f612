/*
 * Tracker simulator: scripted handheld motion integrated from smooth velocity profiles,
 * three markers on a rigid layout, and the faults a real optical tracker shows (noise,
 * dropouts, occlusion, swapped ids, clock jitter). Deterministic for a given seed.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_sim.h"
#include "private/rs_vec.h"
#include "sim_internal.h"

#define SUBSTEPS 4

struct rs_sim {
	struct rs_sim_desc desc;
	struct sim_segment seg[RS_SIM_MAX_SEGMENTS];
	size_t nseg;
	double script_s;
	double layout[RS_TRACK_MARKERS][3];
	uint64_t rng;
	uint64_t k;        /* index of the next sample */
	double p[3], q[4]; /* current truth: position, quaternion x y z w */
	uint64_t last_device_us;
	int occluded; /* marker index, or -1 */
	double occluded_until;
	double last_seen[RS_TRACK_MARKERS][3];
};

static const double default_layout[RS_TRACK_MARKERS][3] = {
    {0.0, 0.0, 0.0}, {0.10, 0.0, 0.0}, {0.02, 0.08, 0.0}};

void rs_sim_default_layout(double out_layout[RS_TRACK_MARKERS][3])
{
	memcpy(out_layout, default_layout, sizeof default_layout);
}

void rs_sim_desc_resolve(const struct rs_sim_desc *desc, struct rs_sim_desc *out)
{
	static const struct rs_sim_desc zero;
	*out = desc ? *desc : zero;
	if (out->seed == 0)
		out->seed = 1;
	if (out->rate_hz == 0)
		out->rate_hz = 120.0;
	if (out->occlusion_s == 0)
		out->occlusion_s = 0.3;
}

/* splitmix64: tiny, fast and well mixed; ours so runs match across C libraries. */
static uint64_t rng_u64(uint64_t *s)
{
	uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}

static double rng_uniform(uint64_t *s) /* (0, 1] */
{
	return ((double)(rng_u64(s) >> 11) + 1.0) * (1.0 / 9007199254740992.0);
}

static double rng_gauss(uint64_t *s)
{
	double u1 = rng_uniform(s), u2 = rng_uniform(s);
	return sqrt(-2.0 * log(u1)) * cos(2.0 * RS_PI * u2);
}

static int bad_prob(double p)
{
	return !(p >= 0.0 && p <= 1.0);
}

static int bad_nonneg(double v)
{
	return !(v >= 0.0 && isfinite(v));
}

enum rs_status rs_sim_create(const struct rs_sim_desc *desc, struct rs_sim **out_sim,
                             struct rs_error *err)
{
	RS_ASSERT(out_sim);
	*out_sim = NULL;
	struct rs_sim_desc d;
	rs_sim_desc_resolve(desc, &d);
	/* Below 0.01 Hz a single step would carry the motion (and the device clock) out of
	 * the wire format's range; nothing real samples that slowly anyway. */
	if (bad_nonneg(d.rate_hz) || d.rate_hz < 0.01 || d.rate_hz > 1e6)
		return rs_error_set(err, RS_ERR_INVALID, "sim: rate %g Hz out of range [0.01, 1e6]",
		                    d.rate_hz);
	if (bad_nonneg(d.noise_sigma_m) || d.noise_sigma_m > 1.0)
		return rs_error_set(err, RS_ERR_INVALID, "sim: noise %g m out of range",
		                    d.noise_sigma_m);
	if (bad_prob(d.dropout_prob) || bad_prob(d.occlusion_prob) || bad_prob(d.swap_prob))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "sim: dropout/occlusion/swap probabilities must lie in [0, 1]");
	if (bad_nonneg(d.occlusion_s) || bad_nonneg(d.clock_jitter_s) || bad_nonneg(d.duration_s))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "sim: occlusion_time, jitter and duration must be >= 0");
	if (d.clock_jitter_s > 1.0)
		return rs_error_set(err, RS_ERR_INVALID, "sim: jitter %g s out of range [0, 1]",
		                    d.clock_jitter_s);
	for (int a = 0; a < 3; a++)
		if (!isfinite(d.start_position[a]))
			return rs_error_set(err, RS_ERR_INVALID, "sim: start position not finite");
	struct rs_sim *s = calloc(1, sizeof *s);
	if (!s)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "sim: out of memory");
	enum rs_status st = sim_parse_script(
	    d.script && d.script[0] ? d.script : RS_SIM_DEFAULT_SCRIPT, s->seg, &s->nseg, err);
	if (st != RS_OK) {
		free(s);
		return st;
	}
	const double(*lay)[3] = d.layout ? d.layout : default_layout;
	for (int m = 0; m < RS_TRACK_MARKERS; m++)
		for (int a = 0; a < 3; a++) {
			if (!isfinite(lay[m][a])) {
				free(s);
				return rs_error_set(err, RS_ERR_INVALID, "sim: layout not finite");
			}
			s->layout[m][a] = lay[m][a];
		}
	d.script = NULL; /* copied into seg[] */
	d.layout = NULL;
	s->desc = d;
	for (size_t i = 0; i < s->nseg; i++)
		s->script_s += s->seg[i].duration_s;
	s->rng = d.seed;
	memcpy(s->p, d.start_position, sizeof s->p);
	s->q[3] = 1.0;
	s->occluded = -1;
	*out_sim = s;
	return RS_OK;
}

void rs_sim_destroy(struct rs_sim **sim)
{
	if (!sim)
		return;
	free(*sim);
	*sim = NULL;
}

/* Advance the truth from t0 by dt with midpoint velocities. */
static void integrate(struct rs_sim *s, double t0, double dt)
{
	double h = dt / SUBSTEPS;
	for (int i = 0; i < SUBSTEPS; i++) {
		double t = t0 + (i + 0.5) * h;
		double local = fmod(t, s->script_s);
		size_t k = 0;
		double start = 0;
		while (k + 1 < s->nseg && local >= start + s->seg[k].duration_s)
			start += s->seg[k++].duration_s;
		struct sim_motion mo;
		sim_segment_motion(&s->seg[k], local - start, s->q, &mo);
		for (int a = 0; a < 3; a++)
			s->p[a] += mo.v_world[a] * h;
		sim_quat_integrate(s->q, mo.w_world, mo.w_body, h);
	}
}

enum rs_status rs_sim_next(struct rs_sim *s, struct rs_marker_sample *out, struct rs_pose *truth,
                           struct rs_error *err)
{
	RS_ASSERT(s && out);
	double dt = 1.0 / s->desc.rate_hz;
	double t = (double)s->k * dt;
	if (s->desc.duration_s > 0 && t >= s->desc.duration_s)
		return rs_error_set(err, RS_END, "simulation ended after %g s", s->desc.duration_s);
	if (s->k > 0)
		integrate(s, t - dt, dt);

	memset(out, 0, sizeof *out);
	out->sequence = s->desc.first_sequence + (uint32_t)s->k;
	double jitter =
	    s->desc.clock_jitter_s > 0 ? rng_gauss(&s->rng) * s->desc.clock_jitter_s : 0;
	double dev_t = t + jitter;
	/* Clamped (at ~31700 years) so the conversion stays defined however long the run. */
	uint64_t dev_us = dev_t <= 0     ? 0
	                  : dev_t < 1e12 ? (uint64_t)llround(dev_t * 1e6)
	                                 : (uint64_t)1e18;
	if (s->k > 0 && dev_us <= s->last_device_us)
		dev_us = s->last_device_us + 1;
	s->last_device_us = dev_us;
	out->device_time_us = dev_us;
	out->host_time_s = t;
	out->marker_count = RS_TRACK_MARKERS;

	if (s->occluded >= 0 && t >= s->occluded_until)
		s->occluded = -1;
	if (s->desc.occlusion_prob > 0 && rng_uniform(&s->rng) <= s->desc.occlusion_prob &&
	    s->occluded < 0) {
		s->occluded = (int)(rng_u64(&s->rng) % RS_TRACK_MARKERS);
		s->occluded_until = t + s->desc.occlusion_s;
	}
	for (int m = 0; m < RS_TRACK_MARKERS; m++) {
		struct rs_marker *mk = &out->markers[m];
		mk->id = (uint32_t)m;
		double w[3];
		rs_q_rotate(s->q, s->layout[m], w);
		for (int a = 0; a < 3; a++) {
			double n = s->desc.noise_sigma_m > 0
			               ? rng_gauss(&s->rng) * s->desc.noise_sigma_m
			               : 0;
			mk->position[a] = w[a] + s->p[a] + n;
		}
		int dropped =
		    s->desc.dropout_prob > 0 && rng_uniform(&s->rng) <= s->desc.dropout_prob;
		if (m == s->occluded) {
			mk->flags = RS_MARKER_OCCLUDED; /* a tracker repeats the stale position */
			memcpy(mk->position, s->last_seen[m], sizeof mk->position);
		} else if (dropped) {
			mk->flags = 0;
			memset(mk->position, 0, sizeof mk->position);
		} else {
			mk->flags = RS_MARKER_VALID;
			memcpy(s->last_seen[m], mk->position, sizeof mk->position);
		}
	}
	if (s->desc.swap_prob > 0 && rng_uniform(&s->rng) <= s->desc.swap_prob) {
		/* The tracker mislabels two markers: their ids travel with swapped positions. */
		int a = (int)(rng_u64(&s->rng) % RS_TRACK_MARKERS);
		int b = (a + 1 + (int)(rng_u64(&s->rng) % 2)) % RS_TRACK_MARKERS;
		out->markers[a].id = (uint32_t)b;
		out->markers[b].id = (uint32_t)a;
	}
	if (truth) {
		truth->time_s = t;
		memcpy(truth->position, s->p, sizeof s->p);
		memcpy(truth->orientation, s->q, sizeof s->q);
		if (truth->orientation[3] < 0)
			for (int i = 0; i < 4; i++)
				truth->orientation[i] = -truth->orientation[i];
	}
	s->k++;
	return RS_OK;
}
