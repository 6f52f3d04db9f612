/* Synthetic marker samples for the rs_pose tests: a seeded splitmix64 generator,
 * Box-Muller Gaussian noise, random poses and noisy samples of a marker layout. */
#ifndef RS_TEST_POSE_FIXTURE_H
#define RS_TEST_POSE_FIXTURE_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "raystream/rs_pose.h"

/* ---- synthetic samples: seeded splitmix64 + Box-Muller ---- */
struct rng {
	uint64_t s;
};

static inline double uniform01(struct rng *r)
{
	uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	z ^= z >> 31;
	return ((double)(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

static inline double gauss(struct rng *r)
{
	double u = uniform01(r), v = uniform01(r);
	return sqrt(-2.0 * log(u)) * cos(2.0 * RS_PI * v);
}

static inline void random_pose(struct rng *r, double extent, struct rs_pose *T)
{
	double q[4], n = 0.0;
	for (int k = 0; k < 4; ++k) {
		q[k] = gauss(r);
		n += q[k] * q[k];
	}
	n = sqrt(n);
	int flip = q[3] < 0.0;
	for (int k = 0; k < 4; ++k)
		T->orientation[k] = (flip ? -q[k] : q[k]) / n;
	for (int k = 0; k < 3; ++k)
		T->position[k] = extent * (2.0 * uniform01(r) - 1.0);
	T->time_s = 0.0;
}

static inline void make_sample(const struct rs_pose_layout *layout, const struct rs_pose *T,
                               double sigma, struct rng *r, double t, struct rs_marker_sample *out)
{
	memset(out, 0, sizeof *out);
	out->host_time_s = t;
	out->marker_count = 3;
	for (uint32_t i = 0; i < 3; ++i) {
		out->markers[i].id = i;
		out->markers[i].flags = RS_MARKER_VALID;
		rs_pose_transform_point(T, layout->markers[i], out->markers[i].position);
		for (int k = 0; k < 3; ++k)
			out->markers[i].position[k] += sigma * gauss(r);
	}
}

static inline double pos_error(const struct rs_pose *a, const struct rs_pose *b)
{
	double d[3] = {a->position[0] - b->position[0], a->position[1] - b->position[1],
	               a->position[2] - b->position[2]};
	return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

#endif
