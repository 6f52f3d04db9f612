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

} // namespace rs_optical
