// The pose error law for triangulated markers: anisotropic per-marker covariances carried
// through the linearised rigid fit (docs/optical.md, "Error law").
#include "optical_internal.hpp"

#include <cmath>

namespace rs_optical
{

static cv::Matx33d skew(const cv::Vec3d &v)
{
	return cv::Matx33d(0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0);
}

bool fit_layout(const rs_pose_layout &layout, const cv::Vec3d *P, int n, rs_pose *T)
{
	RS_ASSERT(n == 3 || (n == 4 && layout.has_verifier));
	double model[4][3], measured[4][3];
	for (int i = 0; i < n; ++i)
		for (int k = 0; k < 3; ++k) {
			model[i][k] = i < 3 ? layout.markers[i][k] : layout.verifier[k];
			measured[i][k] = P[i][k];
		}
	return rs_pose_fit((const double(*)[3])model, (const double(*)[3])measured, (size_t)n, T,
	                   nullptr, nullptr) == RS_OK;
}

void pose_error_law(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S, int n,
                    double *out_rot_rms, double *out_pos_rms)
{
	*out_rot_rms = *out_pos_rms = INFINITY;
	// Where the display origin is: the layout fitted to the points, then its offset.
	rs_pose T;
	if (!fit_layout(layout, P, n, &T))
		return;
	double o[3];
	rs_pose_transform_point(&T, layout.T_markers_display.position, o);
	cv::Vec3d cen(0, 0, 0), c[4];
	for (int i = 0; i < n; ++i)
		cen += P[i] * (1.0 / n);
	cv::Matx33d J = cv::Matx33d::zeros();
	for (int i = 0; i < n; ++i) {
		c[i] = P[i] - cen;
		J += cv::Matx33d::eye() * c[i].dot(c[i]) - c[i] * c[i].t();
	}
	cv::Matx33d Ji;
	if (!cv::invert(J, Ji, cv::DECOMP_CHOLESKY))
		return;
	// w = sum N_i n_i and e = sum M_i n_i to first order, N_i = J^-1 [c_i]x,
	// M_i = I/n - [r]x N_i: the covariances add as sum N S N^T, sum M S M^T.
	cv::Matx33d rx = skew(cv::Vec3d(o[0], o[1], o[2]) - cen);
	double tw = 0, tp = 0;
	for (int i = 0; i < n; ++i) {
		cv::Matx33d N = Ji * skew(c[i]);
		cv::Matx33d M = cv::Matx33d::eye() * (1.0 / n) - rx * N;
		tw += cv::trace(N * S[i] * N.t());
		tp += cv::trace(M * S[i] * M.t());
	}
	*out_rot_rms = std::sqrt(tw);
	*out_pos_rms = std::sqrt(tp);
}

// How a point at `arm` from the translation moves under the left perturbation
// R <- exp([w]x) R, t <- t + dt: by -[arm]x w + dt, the 3x6 matrix [-[arm]x | I].
static cv::Matx<double, 3, 6> rigid_jacobian(const cv::Vec3d &arm)
{
	cv::Matx<double, 3, 6> A;
	const cv::Matx33d K = -skew(arm);
	for (int a = 0; a < 3; ++a)
		for (int b = 0; b < 3; ++b) {
			A(a, b) = K(a, b);
			A(a, b + 3) = a == b ? 1.0 : 0.0;
		}
	return A;
}

// Gauss-Newton from the closed-form fit to the generalised least-squares rigid fit: each
// point weighted by its inverse covariance, so a triangulated point's long axis (its depth
// along the baseline's bisector, where a centroid error along the epipolar line moves it)
// counts for what it is worth (rigid_jacobian's perturbation, the step taken by
// rs_pose_extrapolate over unit time).
bool fit_layout_weighted(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S,
                         int n, WeightedFit *fit)
{
	rs_pose &T = fit->T;
	if (!fit_layout(layout, P, n, &T))
		return false;
	for (int i = 0; i < n; ++i) {
		fit->S[i] = S[i];
		if (!cv::invert(S[i], fit->W[i], cv::DECOMP_CHOLESKY))
			return false;
	}
	cv::Matx66d H;
	for (int it = 0; it <= 8; ++it) {
		// the residuals and Jacobians at T: the last pass's are the fit's
		cv::Matx33d R = quat_to_R(T.orientation);
		H = cv::Matx66d::zeros();
		cv::Vec6d g = cv::Vec6d::all(0);
		for (int i = 0; i < n; ++i) {
			const double *m = i < 3 ? layout.markers[i] : layout.verifier;
			cv::Vec3d Rm = R * cv::Vec3d(m[0], m[1], m[2]);
			fit->r[i] = P[i] - (Rm + cv::Vec3d(T.position));
			fit->A[i] = rigid_jacobian(Rm);
			H += fit->A[i].t() * fit->W[i] * fit->A[i];
			g += fit->A[i].t() * fit->W[i] * fit->r[i];
		}
		cv::Vec6d d;
		if (!cv::solve(H, g, d, cv::DECOMP_CHOLESKY))
			return false;
		if (cv::norm(d) < 1e-12 || it == 8)
			break;
		rs_pose_extrapolate(&T, &d.val[3], &d.val[0], 1.0, &T);
	}
	return cv::invert(H, fit->C, cv::DECOMP_CHOLESKY) != 0;
}

double fault_w(const WeightedFit &fit, int i, const cv::Vec3d &u, double *out_per_m)
{
	// the residual's covariance at point i, S_i - A_i C A_i^T; the fault's signature W_i u
	cv::Matx33d Q = fit.S[i] - fit.A[i] * fit.C * fit.A[i].t();
	cv::Vec3d f = fit.W[i] * u;
	double den = f.dot(Q * f);
	*out_per_m = den > 0 ? std::sqrt(den) : 0;
	return den > 0 ? f.dot(fit.r[i]) / *out_per_m : 0; // den 0: a fault the fit cannot see
}

} // namespace rs_optical
