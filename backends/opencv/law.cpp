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
// counts for what it is worth (rigid_jacobian's perturbation).
bool fit_layout_weighted(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S,
                         int n, rs_pose *T, cv::Matx66d *out_C)
{
	if (!fit_layout(layout, P, n, T))
		return false;
	cv::Matx33d Wt[4];
	for (int i = 0; i < n; ++i)
		if (!cv::invert(S[i], Wt[i], cv::DECOMP_CHOLESKY))
			return false;
	cv::Matx66d H;
	for (int it = 0; it < 8; ++it) {
		cv::Matx33d R = quat_to_R(T->orientation);
		cv::Vec3d t(T->position);
		H = cv::Matx66d::zeros();
		cv::Vec6d g = cv::Vec6d::all(0);
		for (int i = 0; i < n; ++i) {
			const double *m = i < 3 ? layout.markers[i] : layout.verifier;
			cv::Vec3d Rm = R * cv::Vec3d(m[0], m[1], m[2]);
			cv::Vec3d r = P[i] - (Rm + t);
			const cv::Matx<double, 3, 6> A = rigid_jacobian(Rm);
			H += A.t() * Wt[i] * A;
			g += A.t() * Wt[i] * r;
		}
		cv::Vec6d d;
		if (!cv::solve(H, g, d, cv::DECOMP_CHOLESKY))
			return false;
		double ang = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		rs_pose D = {};
		D.orientation[3] = std::cos(ang / 2);
		double s = ang > 0 ? std::sin(ang / 2) / ang : 0.5;
		for (int k = 0; k < 3; ++k)
			D.orientation[k] = d[k] * s;
		double pos[3] = {t[0] + d[3], t[1] + d[4], t[2] + d[5]};
		rs_pose_compose(&D, T, T);
		for (int k = 0; k < 3; ++k)
			T->position[k] = pos[k];
		if (ang < 1e-12 && std::sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]) < 1e-12)
			break;
	}
	return cv::invert(H, *out_C, cv::DECOMP_CHOLESKY) != 0;
}

double fault_w(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S,
               const rs_pose &T, const cv::Matx66d &C, int i, const cv::Vec3d &u, double *out_per_m)
{
	*out_per_m = 0;
	const double *m = i < 3 ? layout.markers[i] : layout.verifier;
	cv::Matx33d R = quat_to_R(T.orientation), Wi;
	cv::Vec3d Rm = R * cv::Vec3d(m[0], m[1], m[2]);
	cv::Vec3d r = P[i] - (Rm + cv::Vec3d(T.position));
	if (!cv::invert(S[i], Wi, cv::DECOMP_CHOLESKY))
		return INFINITY; // fit_layout_weighted refused it already
	const cv::Matx<double, 3, 6> A = rigid_jacobian(Rm);
	// the residual's covariance at point i, S_i - A_i C A_i^T; the fault's signature W_i u
	cv::Matx33d Q = S[i] - A * C * A.t();
	cv::Vec3d f = Wi * u;
	double den = f.dot(Q * f);
	if (!(den > 0))
		return 0; // a fault the fit cannot see: no test
	*out_per_m = std::sqrt(den);
	return f.dot(r) / *out_per_m;
}

} // namespace rs_optical
