/* Synthetic stereo rigs and marker poses for the optical tests: two 640 x 480 cameras,
 * f = 800 px, camera 1 at x = baseline, toed in so both axes meet 1 m in front of
 * camera 0; the display about 1 m away, facing the cameras. Also the linearised pose
 * error law for triangulated markers (docs/optical.md). */
#ifndef RS_TEST_OPTICAL_FIXTURE_H
#define RS_TEST_OPTICAL_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "raystream/rs_optical.h"
#include "test_pose_fixture.h"

static inline void make_rig(double baseline, struct rs_optical_rig *rig)
{
	rs_optical_rig_example(baseline, 640, 480, rig);
}

/* The display 1 m (+-5 cm) in front of camera 0, its marker plane turned at most ~35
 * degrees away from facing the rig. */
static inline void facing_pose(struct rng *r, struct rs_pose *T)
{
	double axis[3] = {gauss(r), gauss(r), gauss(r)};
	double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
	double ang = 0.6 * (uniform01(r) - 0.5) * 2.0;
	/* about z any angle, about the in-plane axes up to ~35 degrees */
	double qz[4] = {0, 0, sin(RS_PI * uniform01(r)), 0};
	qz[3] = sqrt(1 - qz[2] * qz[2]);
	double qa[4] = {sin(ang / 2) * axis[0] / n, sin(ang / 2) * axis[1] / n, 0, cos(ang / 2)};
	double na = sqrt(qa[0] * qa[0] + qa[1] * qa[1] + qa[3] * qa[3]);
	for (int k = 0; k < 4; ++k)
		qa[k] /= na;
	/* q = qa * qz; then flip to face the cameras (markers' +z towards -z of the camera) */
	double q[4] = {qa[3] * qz[0] + qa[0] * qz[3] + qa[1] * qz[2] - qa[2] * qz[1],
	               qa[3] * qz[1] - qa[0] * qz[2] + qa[1] * qz[3] + qa[2] * qz[0],
	               qa[3] * qz[2] + qa[0] * qz[1] - qa[1] * qz[0] + qa[2] * qz[3],
	               qa[3] * qz[3] - qa[0] * qz[0] - qa[1] * qz[1] - qa[2] * qz[2]};
	if (q[3] < 0)
		for (int k = 0; k < 4; ++k)
			q[k] = -q[k];
	memcpy(T->orientation, q, sizeof q);
	T->position[0] = -0.04 + 0.05 * (2 * uniform01(r) - 1);
	T->position[1] = -0.03 + 0.05 * (2 * uniform01(r) - 1);
	T->position[2] = 1.0 + 0.05 * (2 * uniform01(r) - 1);
	T->time_s = 0;
}

/* A small text file for the file-loading tests (cmocka's assert: include it first). */
static inline void write_text(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
}

/* Pinhole projection (the fixture rigs have no distortion) into camera v. */
static inline void project_point(const struct rs_optical_rig *rig, int v, const double X0[3],
                                 double *u, double *w)
{
	double X[3];
	memcpy(X, X0, sizeof X);
	if (v) {
		const double *R = rig->R_cam1_cam0, *t = rig->t_cam1_cam0;
		for (int i = 0; i < 3; ++i)
			X[i] =
			    R[3 * i] * X0[0] + R[3 * i + 1] * X0[1] + R[3 * i + 2] * X0[2] + t[i];
	}
	const double *K = rig->cam[v].K;
	*u = K[0] * X[0] / X[2] + K[2];
	*w = K[4] * X[1] / X[2] + K[5];
}

static inline void inv3(const double m[3][3], double o[3][3])
{
	double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
	             m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
	             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j) {
			int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
			o[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / det;
		}
}

/* Covariance of a maximum-likelihood triangulated point for isotropic centroid noise
 * sigma_px: sigma^2 (A^T A)^-1, A the 4x3 Jacobian of both projections (numerical). */
static inline void point_cov(const struct rs_optical_rig *rig, const double X[3], double sigma_px,
                             double cov[3][3])
{
	double A[4][3], h = 1e-6;
	for (int k = 0; k < 3; ++k) {
		double Xp[3] = {X[0], X[1], X[2]}, Xm[3] = {X[0], X[1], X[2]};
		Xp[k] += h;
		Xm[k] -= h;
		for (int v = 0; v < 2; ++v) {
			double up, vp, um, vm;
			project_point(rig, v, Xp, &up, &vp);
			project_point(rig, v, Xm, &um, &vm);
			A[2 * v][k] = (up - um) / (2 * h);
			A[2 * v + 1][k] = (vp - vm) / (2 * h);
		}
	}
	double AtA[3][3] = {{0}};
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			for (int r = 0; r < 4; ++r)
				AtA[i][j] += A[r][i] * A[r][j];
	inv3(AtA, cov);
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			cov[i][j] *= sigma_px * sigma_px;
}

/* Linearised RMS rotation error (rad) and RMS 3-D error of the marker-frame origin for
 * the three markers P[i] (camera frame) with covariances cov[i]: the Horn fit's estimator
 * is linear in the noise, w = J^-1 sum [c_i]x n_i and e = mean(n) - [r]x w. */
static inline void pose_error_law(const double P[3][3], double cov[3][3][3], const double origin[3],
                                  double *rot_rms, double *pos_rms)
{
	double cen[3] = {0}, c[3][3], J[3][3] = {{0}}, Ji[3][3];
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			cen[k] += P[i][k] / 3;
	for (int i = 0; i < 3; ++i) {
		double n2 = 0;
		for (int k = 0; k < 3; ++k) {
			c[i][k] = P[i][k] - cen[k];
			n2 += c[i][k] * c[i][k];
		}
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				J[a][b] += (a == b ? n2 : 0) - c[i][a] * c[i][b];
	}
	inv3(J, Ji);
	double r[3] = {origin[0] - cen[0], origin[1] - cen[1], origin[2] - cen[2]};
	double rx[3][3] = {{0, -r[2], r[1]}, {r[2], 0, -r[0]}, {-r[1], r[0], 0}};
	double tw = 0, tp = 0;
	for (int i = 0; i < 3; ++i) {
		double cx[3][3] = {
		    {0, -c[i][2], c[i][1]}, {c[i][2], 0, -c[i][0]}, {-c[i][1], c[i][0], 0}};
		double N[3][3] = {{0}}, M[3][3];
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				for (int k = 0; k < 3; ++k)
					N[a][b] += Ji[a][k] * cx[k][b];
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b) {
				M[a][b] = (a == b ? 1.0 / 3 : 0);
				for (int k = 0; k < 3; ++k)
					M[a][b] -= rx[a][k] * N[k][b];
			}
		/* trace(N cov N^T), trace(M cov M^T) */
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				for (int k = 0; k < 3; ++k) {
					tw += N[a][b] * cov[i][b][k] * N[a][k];
					tp += M[a][b] * cov[i][b][k] * M[a][k];
				}
	}
	*rot_rms = sqrt(tw);
	*pos_rms = sqrt(tp);
}

#endif
