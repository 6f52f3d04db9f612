/* raystream-optsynth --bench: frame pairs per second of the whole optical path (detect,
 * match, triangulate, solve, filter) at 640x480 and 1280x720, and pose error against
 * centroid and image noise. A benchmark, not a test: nothing is asserted. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "optsynth.h"

#define PAIRS 32
#define REPS 8

/* CPU seconds of the process (all threads): on a shared machine the wall clock also counts the time
 * other processes held the core. */
static double cpu_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t g_state = 12345;

static double uniform01(void)
{
	g_state = g_state * 6364136223846793005ull + 1442695040888963407ull;
	return ((double)(g_state >> 11) + 0.5) / 9007199254740992.0;
}

static double gauss(void)
{
	double u = uniform01(), v = uniform01();
	return sqrt(-2.0 * log(u)) * cos(2.0 * RS_PI * v);
}

/* The display about 1 m in front of camera 0, turned up to ~35 degrees from facing it. */
static void facing_pose(struct rs_pose *T)
{
	double tilt = 0.6 * uniform01(), dir = 2.0 * RS_PI * uniform01();
	double spin = 2.0 * RS_PI * uniform01();
	double qa[4] = {sin(tilt / 2) * cos(dir), sin(tilt / 2) * sin(dir), 0, cos(tilt / 2)};
	double qz[4] = {0, 0, sin(spin / 2), cos(spin / 2)};
	struct rs_pose A = {.orientation = {qa[0], qa[1], qa[2], qa[3]}};
	struct rs_pose Z = {.orientation = {qz[0], qz[1], qz[2], qz[3]}};
	rs_pose_compose(&A, &Z, T);
	T->position[0] = -0.04 + 0.05 * (2 * uniform01() - 1);
	T->position[1] = -0.03 + 0.05 * (2 * uniform01() - 1);
	T->position[2] = 1.0 + 0.05 * (2 * uniform01() - 1);
}

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

static int throughput(int w, int h, int runs)
{
	struct rs_optical_tracker_desc td = {0};
	rs_optical_rig_example(0.4, w, h, &td.rig);
	struct rs_optical_tracker *t = NULL;
	struct rs_pose_solver *solver = NULL;
	struct rs_pose_filter *filter = NULL;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver_desc sd = {.noise_sigma_m = 0.001};
	size_t bytes = (size_t)w * (size_t)h;
	uint8_t *img = malloc(2 * PAIRS * bytes);
	struct rs_error err;
	if (!img || rs_optical_tracker_create(&td, &t, &err) != RS_OK ||
	    rs_pose_solver_create(&sd, &L, &solver, &err) != RS_OK ||
	    rs_pose_filter_create(NULL, &filter, &err) != RS_OK) {
		fprintf(stderr, "raystream-optsynth: bench setup failed\n");
		free(img);
		return 1;
	}
	for (int i = 0; i < PAIRS; ++i) {
		struct rs_pose T;
		facing_pose(&T);
		struct rs_optical_synth_desc d = {.noise_grey = 2, .seed = (uint64_t)i + 1};
		rs_optical_synth_render(&td.rig, &L, &T, &d, img + 2 * i * bytes,
		                        img + (2 * i + 1) * bytes, NULL);
	}
	double rates[64], cpu_rates[64];
	long solved = 0, total = 0;
	for (int r = 0; r < runs; ++r) {
		double t0 = 1e-3 * rs_now_ms(), c0 = cpu_s(), time_s = r * 10.0;
		for (int k = 0; k < REPS * PAIRS; ++k) {
			int i = k % PAIRS;
			struct rs_optical_image a = {img + 2 * i * bytes, w, h, (size_t)w};
			struct rs_optical_image b = {img + (2 * i + 1) * bytes, w, h, (size_t)w};
			struct rs_marker_sample s;
			struct rs_pose p;
			struct rs_pose_quality q;
			time_s += 1.0 / 120;
			rs_optical_tracker_process(t, &a, &b, time_s, &s, NULL, NULL);
			rs_pose_solver_update(solver, &s, &p, &q);
			if (q.status <= RS_POSE_RELABELED)
				rs_pose_filter_update(filter, &p, &p, NULL);
			solved += q.status <= RS_POSE_RELABELED;
			total++;
		}
		rates[r] = REPS * PAIRS / (1e-3 * rs_now_ms() - t0);
		cpu_rates[r] = REPS * PAIRS / (cpu_s() - c0);
	}
	qsort(rates, (size_t)runs, sizeof rates[0], cmp);
	qsort(cpu_rates, (size_t)runs, sizeof cpu_rates[0], cmp);
	printf("| %dx%d | %.0f | %.0f-%.0f | %.2f | %.0f | %.0f-%.0f | %ld/%ld |\n", w, h,
	       cpu_rates[runs / 2], cpu_rates[0], cpu_rates[runs - 1], 1e3 / cpu_rates[runs / 2],
	       rates[runs / 2], rates[0], rates[runs - 1], solved, total);
	free(img);
	rs_optical_tracker_destroy(&t);
	rs_pose_solver_destroy(&solver);
	rs_pose_filter_destroy(&filter);
	return 0;
}

static void project(const struct rs_optical_rig *rig, int v, const double X0[3], double *u,
                    double *w)
{
	double X[3] = {X0[0], X0[1], X0[2]};
	if (v)
		for (int i = 0; i < 3; ++i)
			X[i] = rig->R_cam1_cam0[3 * i] * X0[0] +
			       rig->R_cam1_cam0[3 * i + 1] * X0[1] +
			       rig->R_cam1_cam0[3 * i + 2] * X0[2] + rig->t_cam1_cam0[i];
	const double *K = rig->cam[v].K;
	*u = K[0] * X[0] / X[2] + K[2];
	*w = K[4] * X[1] / X[2] + K[5];
}

/* Solve one sample with the optical path's stated noise and compare with the true pose:
 * false when the solver does not report it good; else the rotation error (rad) and the
 * squared position error (m^2). */
static bool solve_against(const struct rs_marker_sample *s, double sigma_m,
                          const struct rs_pose_layout *L, const struct rs_pose *T,
                          struct rs_pose_quality *q, double *out_rot, double *out_pos2)
{
	struct rs_pose_solver_desc sd = {.noise_sigma_m = sigma_m > 0 ? sigma_m : 1e-3};
	struct rs_pose_solver *solver = NULL;
	if (rs_pose_solver_create(&sd, L, &solver, NULL) != RS_OK)
		return false;
	struct rs_pose p;
	rs_pose_solver_update(solver, s, &p, q);
	rs_pose_solver_destroy(&solver);
	if (q->status > RS_POSE_RELABELED)
		return false;
	*out_rot = rs_pose_angle_between(&p, T);
	*out_pos2 = 0.0;
	for (int a = 0; a < 3; ++a)
		*out_pos2 += (p.position[a] - T->position[a]) * (p.position[a] - T->position[a]);
	return true;
}

/* Centroids = true projections + Gaussian noise: solved fraction and pose errors against
 * what the tracker and solver state (marker sigma from the triangulation, the solver's
 * rotation_rms_rad for it). */
static void error_row(double baseline, double sigma_px, int trials)
{
	struct rs_optical_tracker_desc td = {.centroid_sigma_px = sigma_px};
	rs_optical_rig_example(baseline, 640, 480, &td.rig);
	struct rs_optical_tracker *t = NULL;
	if (rs_optical_tracker_create(&td, &t, NULL) != RS_OK)
		return;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	double se_r = 0, se_p = 0, st_r = 0, sig = 0, law_r = 0, law_p = 0;
	int good = 0;
	for (int k = 0; k < trials; ++k) {
		struct rs_pose T;
		facing_pose(&T);
		struct rs_optical_blob b[2][3];
		for (int i = 0; i < 3; ++i) {
			double P[3];
			rs_pose_transform_point(&T, L.markers[i], P);
			for (int v = 0; v < 2; ++v) {
				project(&td.rig, v, P, &b[v][i].x, &b[v][i].y);
				b[v][i].x += sigma_px * gauss();
				b[v][i].y += sigma_px * gauss();
			}
		}
		struct rs_marker_sample s;
		struct rs_optical_quality oq;
		rs_optical_tracker_process_blobs(t, b[0], 3, b[1], 3, 0.0, &s, &oq, NULL);
		sig += oq.sigma_m * oq.sigma_m;
		struct rs_pose_quality q;
		double a, d2;
		if (!solve_against(&s, oq.sigma_m, &L, &T, &q, &a, &d2))
			continue;
		++good;
		se_r += a * a;
		se_p += d2;
		st_r += q.rotation_rms_rad * q.rotation_rms_rad;
		law_r += oq.rotation_rms_rad * oq.rotation_rms_rad;
		law_p += oq.position_rms_m * oq.position_rms_m;
	}
	int n = good ? good : 1;
	printf("| %.1f | %.1f | %.3f | %.1f %% | %.3f | %.3f | %.3f | %.3f | %.3f |\n", baseline,
	       sigma_px, sqrt(sig / trials) * 1e3, 100.0 * good / trials, sqrt(se_r / n) * 57.29578,
	       sqrt(law_r / n) * 57.29578, sqrt(st_r / n) * 57.29578, sqrt(se_p / n) * 1e3,
	       sqrt(law_p / n) * 1e3);
	rs_optical_tracker_destroy(&t);
}

/* Rendered frames with pixel noise: the whole path's pose error. */
static void image_row(double grey, int trials)
{
	struct rs_optical_tracker_desc td = {0};
	rs_optical_rig_example(0.4, 640, 480, &td.rig);
	struct rs_optical_tracker *t = NULL;
	static uint8_t img[2][640 * 480];
	if (rs_optical_tracker_create(&td, &t, NULL) != RS_OK)
		return;
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	double se_r = 0, se_p = 0;
	int good = 0;
	for (int k = 0; k < trials; ++k) {
		struct rs_pose T;
		facing_pose(&T);
		struct rs_optical_synth_desc d = {.noise_grey = grey, .seed = (uint64_t)k + 7};
		rs_optical_synth_render(&td.rig, &L, &T, &d, img[0], img[1], NULL);
		struct rs_optical_image a = {img[0], 640, 480, 640}, b = {img[1], 640, 480, 640};
		struct rs_marker_sample s;
		struct rs_optical_quality oq;
		rs_optical_tracker_process(t, &a, &b, 0.0, &s, &oq, NULL);
		struct rs_pose_quality q;
		double e, d2;
		if (!solve_against(&s, oq.sigma_m, &L, &T, &q, &e, &d2))
			continue;
		++good;
		se_r += e * e;
		se_p += d2;
	}
	int n = good ? good : 1;
	printf("| %.0f | %.1f %% | %.3f | %.3f |\n", grey, 100.0 * good / trials,
	       sqrt(se_r / n) * 57.29578, sqrt(se_p / n) * 1e3);
	rs_optical_tracker_destroy(&t);
}

int optsynth_bench(const struct optsynth_options *o)
{
	printf("### Optical path throughput (detect, match, triangulate, solve, filter)\n\n"
	       "%d pre-rendered frame pairs (3 markers, 2 grey levels of noise) processed %d "
	       "times per run; median of %d runs.\n\n",
	       PAIRS, REPS, o->runs);
	printf("| frame size | pairs per CPU-second (median) | min-max | CPU ms/pair | pairs per "
	       "wall-second | min-max | solved |\n");
	printf("|---|---:|---:|---:|---:|---:|---:|\n");
	if (throughput(640, 480, o->runs) || throughput(1280, 720, o->runs))
		return 1;
	printf("\n### Pose error against centroid noise (2000 random poses per row, 640x480, "
	       "display 1 m away)\n\n");
	printf("| baseline (m) | centroid sigma (px) | stated marker sigma (mm/axis) | solved | "
	       "rot RMS (deg) | optical law (deg) | solver's isotropic law (deg) | pos RMS 3-D "
	       "(mm) | optical law (mm) |\n");
	printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	static const double base[] = {0.4, 0.8}, sig[] = {0.1, 0.2, 0.3, 0.5, 1.0};
	for (int b = 0; b < 2; ++b)
		for (int s = 0; s < 5; ++s)
			error_row(base[b], sig[s], 2000);
	printf("\n### Pose error against image noise (rendered frames, 200 poses per row, "
	       "0.4 m baseline)\n\n");
	printf("| pixel noise (grey RMS) | solved | rot RMS (deg) | pos RMS 3-D (mm) |\n");
	printf("|---:|---:|---:|---:|\n");
	static const double grey[] = {0, 2, 5, 10};
	for (int g = 0; g < 4; ++g)
		image_row(grey[g], 200);
	return 0;
}
