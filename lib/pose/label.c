/* Which layout marker each measured point is, judged by the triangle's side lengths, and the
 * pose error the solver states for a solved sample (the sigma / h law of docs/pose.md). */
#include "raystream/rs_pose.h"

#include "pose_internal.h"
#include "private/rs_vec.h"

/* perm[j] = layout id of measured point j. */
const int rs_pose_perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

/* Standard deviation of u . (measured sides - true sides) for unit u, to first order: side k
 * (opposite vertex k) moves by a_k . (noise of its far end - noise of its near end). */
static double side_projection_sigma(const double p[3][3], const double u[3], double sigma)
{
	double a[3][3];
	rs_v3_sub(p[2], p[1], a[0]);
	rs_v3_sub(p[0], p[2], a[1]);
	rs_v3_sub(p[1], p[0], a[2]);
	for (int k = 0; k < 3; ++k) {
		double n = rs_v3_norm(a[k]);
		for (int c = 0; c < 3; ++c)
			a[k][c] = n > 0.0 ? a[k][c] / n : 0.0;
	}
	double var = 0.0;
	for (int c = 0; c < 3; ++c) {
		double g0 = u[1] * a[1][c] - u[2] * a[2][c];
		double g1 = u[2] * a[2][c] - u[0] * a[0][c];
		double g2 = u[0] * a[0][c] - u[1] * a[1][c];
		var += g0 * g0 + g1 * g1 + g2 * g2;
	}
	return sigma * sqrt(var);
}

int rs_pose_label(const double layout_sides[3], const double pts[3][3], const double sides[3],
                  double sigma, double *out_worst, double *out_separation)
{
	double cost[6], L[6][3];
	int best = 0;
	for (int p = 0; p < 6; ++p) {
		cost[p] = 0.0;
		for (int k = 0; k < 3; ++k) {
			L[p][k] = layout_sides[rs_pose_perms[p][k]];
			double d = sides[k] - L[p][k];
			cost[p] += d * d;
		}
		if (cost[p] < cost[best])
			best = p;
	}
	/* The measured side vector s is nearer L_best than L_p by (cost_p - cost_best) /
	 * (2 |L_best - L_p|) along their difference: its distance from the decision boundary.
	 * Divided by the noise of s in that direction it says how many standard deviations
	 * the noise would need to have pushed the true ordering across the boundary. */
	double separation = INFINITY, worst = 0.0;
	for (int p = 0; p < 6; ++p) {
		if (p == best)
			continue;
		double u[3];
		rs_v3_sub(L[best], L[p], u);
		double n = rs_v3_norm(u);
		if (!(n > 0.0)) {
			separation = 0.0;
			continue;
		}
		for (int k = 0; k < 3; ++k)
			u[k] /= n;
		double sd = side_projection_sigma(pts, u, sigma);
		double z = (cost[p] - cost[best]) / (2.0 * n * sd);
		if (!(z >= separation))
			separation = z;
	}
	for (int k = 0; k < 3; ++k) {
		double d = fabs(sides[k] - L[best][k]);
		worst = d > worst ? d : worst;
	}
	*out_worst = worst;
	*out_separation = separation;
	return best;
}

/* 3x3 symmetric inverse by the adjugate; the inertia tensor of three non-collinear unit
 * masses is positive definite (its planar eigenvalues l1, l2 and l1 + l2). */
static int inverse3(const double m[3][3], double out[3][3])
{
	double c[3][3];
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j) {
			int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
			c[j][i] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
		}
	double det = m[0][0] * c[0][0] + m[0][1] * c[1][0] + m[0][2] * c[2][0];
	if (!(fabs(det) > 0.0))
		return 0;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			out[i][j] = c[i][j] / det;
	return 1;
}

void rs_pose_error_law(const struct rs_pose_layout *layout, double sigma, double *out_rot_rms,
                       double *out_pos_rms)
{
	double centroid[3] = {0}, J[3][3] = {{0}}, Ji[3][3];
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
			centroid[k] += layout->markers[i][k] / 3.0;
	for (int i = 0; i < 3; ++i) {
		double c[3];
		rs_v3_sub(layout->markers[i], centroid, c);
		double n2 = rs_v3_dot(c, c);
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				J[a][b] += (a == b ? n2 : 0.0) - c[a] * c[b];
	}
	if (!inverse3((const double(*)[3])J, Ji)) {
		*out_rot_rms = *out_pos_rms = INFINITY;
		return;
	}
	/* Position of the display origin r (from the centroid): sigma^2 / 3 I from the
	 * centroid plus the lever arm [r]x Cov(w) [r]x^T, Cov(w) = sigma^2 J^-1. */
	double r[3];
	rs_v3_sub(layout->T_markers_display.position, centroid, r);
	const double X[3][3] = {{0, -r[2], r[1]}, {r[2], 0, -r[0]}, {-r[1], r[0], 0}};
	double lever = 0.0;
	for (int i = 0; i < 3; ++i)
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				lever += X[i][a] * Ji[a][b] * X[i][b];
	*out_rot_rms = sigma * sqrt(Ji[0][0] + Ji[1][1] + Ji[2][2]);
	*out_pos_rms = sigma * sqrt(1.0 + lever);
}
