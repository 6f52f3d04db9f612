// The consistency gate of a labelled marker triple (issue 19): chi-square tests of the
// triangle's side lengths, per marker and in total, against the covariances the
// triangulation states, and the lens-distortion weight of a centroid. With three markers
// the rigid fit's residual lives wholly in the three side lengths (nine coordinates less
// six pose parameters), so the sides are the exact test. A triple that
// fails is not reported: a wrong pose must never come back good.
#include "optical_internal.hpp"

#include <algorithm>
#include <cmath>

namespace rs_optical
{

// Pixel (undistorted, camera matrix K) -> pixel with the lens's distortion applied.
static cv::Point2d distort_px(const rs_optical_camera &c, cv::Point2d p)
{
	const double *K = c.K, *d = c.dist;
	double x = (p.x - K[2]) / K[0], y = (p.y - K[5]) / K[4];
	double r2 = x * x + y * y, radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
	double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
	double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
	return cv::Point2d(xd * K[0] + K[2], yd * K[4] + K[5]);
}

cv::Matx22d centroid_weight(const rs_optical_camera &c, cv::Point2d undistorted)
{
	if (!c.dist[0] && !c.dist[1] && !c.dist[2] && !c.dist[3] && !c.dist[4])
		return cv::Matx22d::eye();
	// D = d(distorted)/d(undistorted): centroid noise s^2 I in the image is s^2 D^-1 D^-T
	// in undistorted pixels, whose inverse is D^T D / s^2.
	const double h = 1e-3;
	cv::Point2d px = distort_px(c, undistorted + cv::Point2d(h, 0));
	cv::Point2d mx = distort_px(c, undistorted - cv::Point2d(h, 0));
	cv::Point2d py = distort_px(c, undistorted + cv::Point2d(0, h));
	cv::Point2d my = distort_px(c, undistorted - cv::Point2d(0, h));
	cv::Matx22d D((px.x - mx.x) / (2 * h), (py.x - my.x) / (2 * h), (px.y - mx.y) / (2 * h),
	              (py.y - my.y) / (2 * h));
	return D.t() * D;
}

// Side k (opposite point k) joins points a and b and moves by u . (n_b - n_a), u the unit
// vector a -> b, to first order: its deviations from the layout and their covariance
// C = G blockdiag(S) G^T (G the 3x9 Jacobian). False for coincident points.
static bool side_deviation(const double layout_sides[3], const cv::Vec3d P[3],
                           const cv::Matx33d S[3], cv::Vec3d *ds, cv::Matx33d *C)
{
	cv::Vec3d G[3][3];
	for (int k = 0; k < 3; ++k) {
		int a = (k + 1) % 3, b = (k + 2) % 3;
		cv::Vec3d d = P[b] - P[a];
		double n = cv::norm(d);
		if (!(n > 0))
			return false;
		(*ds)[k] = n - layout_sides[k];
		for (int i = 0; i < 3; ++i)
			G[k][i] = cv::Vec3d(0, 0, 0);
		G[k][b] = d / n;
		G[k][a] = -d / n;
	}
	*C = cv::Matx33d::zeros();
	for (int k = 0; k < 3; ++k)
		for (int l = 0; l < 3; ++l)
			for (int i = 0; i < 3; ++i)
				(*C)(k, l) += G[k][i].dot(S[i] * G[l][i]);
	return true;
}

void side_chi2(const double layout_sides[3], const cv::Vec3d P[3], const cv::Matx33d S[3],
               double *out_total, double out_marker[3])
{
	*out_total = out_marker[0] = out_marker[1] = out_marker[2] = INFINITY;
	cv::Vec3d ds;
	cv::Matx33d C, Ci;
	if (!side_deviation(layout_sides, P, S, &ds, &C) || !cv::invert(C, Ci, cv::DECOMP_CHOLESKY))
		return;
	*out_total = ds.dot(Ci * ds);
	// Marker i: the two sides that meet at it (the sides k != i). Its rigid-fit residual
	// is no test here: the isotropic fit spreads one marker's depth error over the others'
	// precise lateral directions, so r_i's covariance is not S_i.
	for (int i = 0; i < 3; ++i) {
		int a = (i + 1) % 3, b = (i + 2) % 3;
		cv::Matx22d c(C(a, a), C(a, b), C(b, a), C(b, b)), ci;
		if (!cv::invert(c, ci, cv::DECOMP_CHOLESKY))
			continue;
		cv::Vec2d d(ds[a], ds[b]);
		out_marker[i] = d.dot(ci * d);
	}
}

// The pose of markers P (layout id order): false when degenerate.
static bool fit_pose(const rs_pose_layout &layout, const cv::Vec3d P[3], rs_pose *T)
{
	rs_pose M;
	if (!fit_layout(layout, P, 3, &M))
		return false;
	rs_pose_compose(&M, &layout.T_markers_display, T);
	return true;
}

// Whether the gate's side tests (and the step gate, with a prior) pass with marker i moved
// by d along u.
static bool passes_moved(const rs_pose_layout &layout, const double layout_sides[3],
                         const cv::Vec3d P[3], const cv::Matx33d S[3], const StepPrior *prior,
                         int i, const cv::Vec3d &u, double d)
{
	cv::Vec3d Q[3] = {P[0], P[1], P[2]};
	Q[i] += d * u;
	double total, mc[3];
	side_chi2(layout_sides, Q, S, &total, mc);
	if (!(total <= RS_OPTICAL_CHI2_3DOF && mc[0] <= RS_OPTICAL_CHI2_2DOF &&
	      mc[1] <= RS_OPTICAL_CHI2_2DOF && mc[2] <= RS_OPTICAL_CHI2_2DOF))
		return false;
	if (!prior)
		return true;
	rs_pose T;
	return fit_pose(layout, Q, &T) &&
	       rs_pose_step_score(&prior->predicted, &T, prior->rot_rms, prior->pos_rms, prior->dt,
	                          0.0) <= RS_POSE_STEP_CHI2;
}

// Total side chi-square with marker i moved by d along u.
static double moved_chi2(const double layout_sides[3], const cv::Vec3d P[3], const cv::Matx33d S[3],
                         int i, const cv::Vec3d &u, double d)
{
	cv::Vec3d Q[3] = {P[0], P[1], P[2]};
	Q[i] += d * u;
	double total, mc[3];
	side_chi2(layout_sides, Q, S, &total, mc);
	return total;
}

// The far passing region along u beyond `from`, if any: each side meeting at marker i
// returns to its layout length at a second distance along the ray (the triangle tilted the
// other way, a mirror image in depth), and where both do, the moved triple passes again.
// Returns the farthest passing distance found (0: none).
static double far_region(const rs_pose_layout &layout, const double layout_sides[3],
                         const cv::Vec3d P[3], const cv::Matx33d S[3], const StepPrior *prior,
                         int i, const cv::Vec3d &u, double from, double max_d)
{
	double root[2];
	int n = 0;
	for (int j = 0; j < 3; ++j) {
		if (j == i)
			continue;
		// |P_i - P_j + d u| = L: d^2 + 2 b d + c = 0 (the side opposite the third marker)
		cv::Vec3d w = P[i] - P[j];
		double L = layout_sides[3 - i - j], b = u.dot(w), c = w.dot(w) - L * L;
		double disc = b * b - c;
		// no root: the side comes closest at -b
		root[n++] = disc < 0 ? -b : std::max(-b - std::sqrt(disc), -b + std::sqrt(disc));
	}
	double a = std::max(from, std::min(root[0], root[1]) - 0.002);
	double e = std::min(max_d, std::max(root[0], root[1]) + 0.002);
	if (!(e > a))
		return 0;
	// The chi-square's least value in [a, e]: a 5-point scan, then golden-section steps
	// to 0.05 mm (one new value per step).
	double best = a, best_c = INFINITY, step = (e - a) / 4;
	for (int k = 0; k <= 4; ++k) {
		double c = moved_chi2(layout_sides, P, S, i, u, a + k * step);
		if (c < best_c) {
			best_c = c;
			best = a + k * step;
		}
	}
	const double g = 0.5 * (std::sqrt(5.0) - 1.0);
	double lo = std::max(a, best - step), hi = std::min(e, best + step);
	double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
	double c1 = moved_chi2(layout_sides, P, S, i, u, m1);
	double c2 = moved_chi2(layout_sides, P, S, i, u, m2);
	for (int it = 0; it < 24 && hi - lo > 5e-5; ++it) {
		if (c1 < c2) {
			hi = m2;
			m2 = m1;
			c2 = c1;
			m1 = hi - g * (hi - lo);
			c1 = moved_chi2(layout_sides, P, S, i, u, m1);
		} else {
			lo = m1;
			m1 = m2;
			c1 = c2;
			m2 = lo + g * (hi - lo);
			c2 = moved_chi2(layout_sides, P, S, i, u, m2);
		}
	}
	double d = 0.5 * (lo + hi);
	if (!passes_moved(layout, layout_sides, P, S, prior, i, u, d))
		return 0;
	// Outwards to where it is refused (0.25 mm steps: the region is millimetres wide).
	for (int k = 0; k < 400 && d < max_d; ++k) {
		if (!passes_moved(layout, layout_sides, P, S, prior, i, u, d + 0.00025))
			return d + 0.00025; // the refused edge: a bound errs outwards
		d += 0.00025;
	}
	return std::min(d, max_d);
}

void fault_bound(const rs_pose_layout &layout, const double layout_sides[3], const cv::Vec3d P[3],
                 const cv::Matx33d S[3], const cv::Vec3d rays[3][2], const StepPrior *prior,
                 double *out_rot, double *out_pos)
{
	*out_rot = *out_pos = INFINITY;
	rs_pose T0;
	if (!fit_pose(layout, P, &T0))
		return;
	double rot = 0, pos = 0;
	const double max_d = 0.1; // beyond 10 cm the labelling refuses the triple anyway
	for (int i = 0; i < 3; ++i)
		for (int v = 0; v < 2; ++v)
			for (int sign = -1; sign <= 1; sign += 2) {
				const cv::Vec3d u = rays[i][v] * (double)sign;
				// Grow d geometrically until the gate refuses, then bisect the
				// edge to 1 % of d (a bound, not a measurement).
				double lo = 0, hi = 1e-4;
				while (hi < max_d &&
				       passes_moved(layout, layout_sides, P, S, prior, i, u, hi)) {
					lo = hi;
					hi *= 1.5;
				}
				for (int it = 0; hi < max_d && it < 6; ++it) {
					double mid = 0.5 * (lo + hi);
					(passes_moved(layout, layout_sides, P, S, prior, i, u, mid)
					     ? lo
					     : hi) = mid;
				}
				// The refused edge: a bound errs outwards. Beyond it the triple may
				// pass again (the far region); the farther of the two counts.
				double d = std::min(hi, max_d);
				if (hi < max_d)
					d = std::max(d, far_region(layout, layout_sides, P, S,
					                           prior, i, u, hi, max_d));
				cv::Vec3d Q[3] = {P[0], P[1], P[2]};
				Q[i] += d * u;
				rs_pose T;
				if (!fit_pose(layout, Q, &T))
					return;
				double dp[3];
				for (int k = 0; k < 3; ++k)
					dp[k] = T.position[k] - T0.position[k];
				rot = std::max(rot, rs_pose_angle_between(&T, &T0));
				pos = std::max(
				    pos, std::sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]));
			}
	*out_rot = rot;
	*out_pos = pos;
}

} // namespace rs_optical

extern "C" const char *rs_optical_verdict_name(enum rs_optical_verdict v)
{
	switch (v) {
	case RS_OPTICAL_SOLVED:
		return "RS_OPTICAL_SOLVED";
	case RS_OPTICAL_ONE_VIEW:
		return "RS_OPTICAL_ONE_VIEW";
	case RS_OPTICAL_TOO_FEW_MATCHES:
		return "RS_OPTICAL_TOO_FEW_MATCHES";
	case RS_OPTICAL_NO_LAYOUT:
		return "RS_OPTICAL_NO_LAYOUT";
	case RS_OPTICAL_REPROJECTION:
		return "RS_OPTICAL_REPROJECTION";
	case RS_OPTICAL_MARKER_RESIDUAL:
		return "RS_OPTICAL_MARKER_RESIDUAL";
	case RS_OPTICAL_SIDE_RESIDUAL:
		return "RS_OPTICAL_SIDE_RESIDUAL";
	case RS_OPTICAL_AMBIGUOUS:
		return "RS_OPTICAL_AMBIGUOUS";
	case RS_OPTICAL_STEP:
		return "RS_OPTICAL_STEP";
	case RS_OPTICAL_SPOT_SIZE:
		return "RS_OPTICAL_SPOT_SIZE";
	case RS_OPTICAL_VERIFIER:
		return "RS_OPTICAL_VERIFIER";
	}
	return "RS_OPTICAL_UNKNOWN";
}
