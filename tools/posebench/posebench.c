/* raystream-posebench: poses per second of the rs_pose solver and 1-euro filter (median of
 * several runs), and a Monte Carlo table of pose error versus marker noise, printed as
 * markdown. A benchmark, not a test: nothing here is asserted. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_pose.h"

#define POOL 1024

struct rng {
	uint64_t s;
};

static double uniform01(struct rng *r)
{
	uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	z ^= z >> 31;
	return ((double)(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

static double gauss(struct rng *r)
{
	double u = uniform01(r), v = uniform01(r);
	return sqrt(-2.0 * log(u)) * cos(2.0 * RS_PI * v);
}

static void random_pose(struct rng *r, struct rs_pose *T)
{
	double q[4], n = 0.0;
	for (int k = 0; k < 4; ++k) {
		q[k] = gauss(r);
		n += q[k] * q[k];
	}
	n = sqrt(n) * (q[3] < 0 ? -1.0 : 1.0);
	for (int k = 0; k < 4; ++k)
		T->orientation[k] = q[k] / n;
	for (int k = 0; k < 3; ++k)
		T->position[k] = 4.0 * uniform01(r) - 2.0;
	T->time_s = 0.0;
}

static void make_sample(const struct rs_pose_layout *L, const struct rs_pose *T, double sigma,
                        struct rng *r, double t, struct rs_marker_sample *out)
{
	memset(out, 0, sizeof *out);
	out->host_time_s = t;
	out->marker_count = 3;
	for (uint32_t i = 0; i < 3; ++i) {
		out->markers[i].id = i;
		out->markers[i].flags = RS_MARKER_VALID;
		rs_pose_transform_point(T, L->markers[i], out->markers[i].position);
		for (int k = 0; k < 3; ++k)
			out->markers[i].position[k] += sigma * gauss(r);
	}
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static double median(double *v, int n)
{
	qsort(v, (size_t)n, sizeof *v, cmp_double);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The layout with its origin at the markers' centroid: the solved position is then the
 * centroid, whose error is sigma / sqrt(3) per axis (docs/pose.md). */
static void centred_layout(struct rs_pose_layout *L)
{
	rs_pose_layout_default(L);
	double c[3] = {0};
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			c[k] += L->markers[i][k] / 3.0;
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			L->markers[i][k] -= c[k];
}

/* sqrt(trace(J^-1)), J = sum(|c|^2 I - c c^T): linearised RMS rotation error per sigma. */
static double rotation_error_constant(const struct rs_pose_layout *L)
{
	double J[3][3] = {{0}};
	for (int i = 0; i < 3; ++i) {
		const double *p = L->markers[i];
		double n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				J[a][b] += (a == b ? n2 : 0.0) - p[a] * p[b];
	}
	double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
	             J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
	             J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
	double tr = J[1][1] * J[2][2] - J[1][2] * J[2][1] + J[0][0] * J[2][2] - J[0][2] * J[2][0] +
	            J[0][0] * J[1][1] - J[0][1] * J[1][0];
	return sqrt(tr / det);
}

static int bench_solver(long iters, int runs, double *out_median)
{
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver *s = NULL;
	struct rs_error err;
	/* A pool of unrelated poses 1 ms apart: no step gate (it would hold them). */
	struct rs_pose_solver_desc d = {.independent_samples = 1};
	if (rs_pose_solver_create(&d, &L, &s, &err) != RS_OK) {
		fprintf(stderr, "posebench: %s\n", err.message);
		return 1;
	}
	static struct rs_marker_sample pool[POOL];
	struct rng r = {99};
	for (int i = 0; i < POOL; ++i) {
		struct rs_pose T;
		random_pose(&r, &T);
		make_sample(&L, &T, 0.0005, &r, 0.001 * i, &pool[i]);
	}
	double rates[64], sink = 0.0;
	for (int run = 0; run < runs; ++run) {
		double t0 = 1e-3 * rs_now_ms();
		for (long i = 0; i < iters; ++i) {
			struct rs_pose out;
			struct rs_pose_quality q;
			struct rs_marker_sample *smp = &pool[i % POOL];
			smp->host_time_s = 0.001 * (double)i;
			rs_pose_solver_update(s, smp, &out, &q);
			sink += out.position[0];
		}
		rates[run] = (double)iters / (1e-3 * rs_now_ms() - t0);
	}
	rs_pose_solver_destroy(&s);
	*out_median = median(rates, runs);
	return sink == 12345.678; /* keeps the loop from being optimised away */
}

static int bench_filter(long iters, int runs, double *out_median)
{
	struct rs_pose_filter *f = NULL;
	struct rs_error err;
	if (rs_pose_filter_create(NULL, &f, &err) != RS_OK) {
		fprintf(stderr, "posebench: %s\n", err.message);
		return 1;
	}
	static struct rs_pose pool[POOL];
	struct rng r = {7};
	for (int i = 0; i < POOL; ++i) {
		pool[i].orientation[2] = sin(0.001 * i);
		pool[i].orientation[3] = cos(0.001 * i);
		for (int k = 0; k < 3; ++k)
			pool[i].position[k] = 0.0005 * gauss(&r);
	}
	double rates[64], sink = 0.0;
	for (int run = 0; run < runs; ++run) {
		rs_pose_filter_reset(f);
		double t0 = 1e-3 * rs_now_ms();
		for (long i = 0; i < iters; ++i) {
			struct rs_pose in = pool[i % POOL], out;
			in.time_s = 0.001 * (double)i;
			rs_pose_filter_update(f, &in, &out, NULL);
			sink += out.position[0];
		}
		rates[run] = (double)iters / (1e-3 * rs_now_ms() - t0);
	}
	rs_pose_filter_destroy(&f);
	*out_median = median(rates, runs);
	return sink == 12345.678;
}

static void error_table(long trials)
{
	static const double sigmas_mm[] = {0.0, 0.1, 0.5, 1.0, 2.0};
	struct rs_pose_layout L;
	centred_layout(&L);
	double k = rotation_error_constant(&L);
	const double h_min = 0.008 / sqrt(2.0 * 0.08 * 0.08);
	printf("\n### Pose error vs marker noise (%ld Monte Carlo trials per row)\n\n", trials);
	printf("Layout: default 10 cm x 8 cm triangle, smallest height %.1f mm; rotation "
	       "constant sqrt(trace(J^-1)) = %.2f / m = %.3f / h_min; position at the marker "
	       "centroid.\n\n",
	       h_min * 1e3, k, k * h_min);
	printf("| sigma (mm/axis) | rot RMS (deg) | predicted %.2f sigma/h (deg) | "
	       "pos RMS/axis (mm) | predicted sigma/sqrt(3) (mm) | not OK |\n",
	       k * h_min);
	printf("|---:|---:|---:|---:|---:|---:|\n");
	for (size_t j = 0; j < sizeof sigmas_mm / sizeof sigmas_mm[0]; ++j) {
		double sigma = sigmas_mm[j] * 1e-3;
		struct rs_pose_solver_desc d = {.noise_sigma_m = sigma > 0 ? sigma : 0.0005};
		struct rs_pose_solver *s = NULL;
		if (rs_pose_solver_create(&d, &L, &s, NULL) != RS_OK)
			return;
		struct rng r = {1000 + j};
		double sr = 0.0, sp = 0.0;
		long bad = 0;
		for (long i = 0; i < trials; ++i) {
			struct rs_pose T, out;
			struct rs_marker_sample smp;
			struct rs_pose_quality q;
			random_pose(&r, &T);
			make_sample(&L, &T, sigma, &r, 0.001 * (double)i, &smp);
			rs_pose_solver_reset(s);
			rs_pose_solver_update(s, &smp, &out, &q);
			/* Ambiguous labellings are not solved (NONE); the error is over solved
			 * samples, which is unbiased (docs/pose.md, "Ids by side lengths"). */
			if (q.status != RS_POSE_OK) {
				++bad;
				continue;
			}
			double a = rs_pose_angle_between(&out, &T);
			sr += a * a;
			for (int c = 0; c < 3; ++c) {
				double e = out.position[c] - T.position[c];
				sp += e * e;
			}
		}
		rs_pose_solver_destroy(&s);
		double n = (double)(trials - bad > 0 ? trials - bad : 1);
		printf("| %.1f | %.4g | %.4g | %.4g | %.4g | %ld |\n", sigmas_mm[j],
		       sqrt(sr / n) * 180.0 / RS_PI, k * sigma * 180.0 / RS_PI,
		       sqrt(sp / (3.0 * n)) * 1e3, sigma / sqrt(3.0) * 1e3, bad);
	}
}

int main(int argc, char **argv)
{
	uint32_t iters = 1000000, trials = 20000, runs = 7;
	const struct rs_cli_option opts[] = {
	    RS_CLI_U32_OPT("--iters", &iters, 1, 1000000000, "updates per timed run"),
	    RS_CLI_U32_OPT("--runs", &runs, 1, 64, "timed runs, the median is reported"),
	    RS_CLI_U32_OPT("--trials", &trials, 1, 1000000000,
	                   "Monte Carlo trials per noise level"),
	};
	struct rs_cli cli = {.prog = "raystream-posebench",
	                     .usage = "[options]",
	                     .about = "Pose solver and filter throughput, then pose error versus "
	                              "marker noise, as markdown on stdout.\n",
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0]};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code;
	double solver_rate, filter_rate;
	if (bench_solver(iters, (int)runs, &solver_rate) ||
	    bench_filter(iters, (int)runs, &filter_rate))
		return 1;
	printf("### rs_pose throughput (median of %u runs x %u updates, one thread)\n\n", runs,
	       iters);
	printf("| stage | poses/s | ns/pose |\n|---|---:|---:|\n");
	printf("| solver (validate, gate, relabel check, Horn fit, calibration) | %.3g | %.0f |\n",
	       solver_rate, 1e9 / solver_rate);
	printf("| 1-euro filter (position + orientation) | %.3g | %.0f |\n", filter_rate,
	       1e9 / filter_rate);
	error_table(trials);
	return 0;
}
