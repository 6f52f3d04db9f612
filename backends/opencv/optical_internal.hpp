// Private helpers shared by the OpenCV backend's C++ files (not installed).
#ifndef RS_OPTICAL_INTERNAL_HPP
#define RS_OPTICAL_INTERNAL_HPP

#include <opencv2/core.hpp>

#include "raystream/rs_optical.h"

namespace rs_optical
{

inline cv::Matx33d K_of(const rs_optical_camera &c)
{
	return cv::Matx33d(c.K);
}

inline cv::Mat dist_of(const rs_optical_camera &c)
{
	return cv::Mat(1, 5, CV_64F, const_cast<double *>(c.dist)).clone();
}

inline cv::Matx33d R_of(const rs_optical_rig &r)
{
	return cv::Matx33d(r.R_cam1_cam0);
}

inline cv::Vec3d t_of(const rs_optical_rig &r)
{
	return cv::Vec3d(r.t_cam1_cam0[0], r.t_cam1_cam0[1], r.t_cam1_cam0[2]);
}

// 3x3 rotation of a unit quaternion x, y, z, w.
cv::Matx33d quat_to_R(const double q[4]);

// A header over caller-owned grey pixels (no copy); the caller checked the image.
inline cv::Mat wrap(const rs_optical_image &img)
{
	return cv::Mat(img.height, img.width, CV_8UC1, const_cast<uint8_t *>(img.pixels),
	               img.stride);
}

// RS_ERR_INVALID unless pixels, sizes (1..16384) and stride are sane.
rs_status check_image(const rs_optical_image *img, rs_error *err);

// The pose (marker frame to camera 0) of points P in layout id order: the three markers,
// and with n = 4 the layout's verifier (rs_pose_fit). False when degenerate.
bool fit_layout(const rs_pose_layout &layout, const cv::Vec3d *P, int n, rs_pose *T);

// The generalised least-squares fit of the layout to points (Gauss-Newton from
// fit_layout's closed form, each point weighted by its inverse covariance): its pose, the
// covariance of its parameters (rotation vector, translation: R <- exp([w]x) R, t <- t +
// dt), and at that pose each point's covariance S, weight W = S^-1, residual r and
// Jacobian A (the point's move per parameter).
struct WeightedFit {
	rs_pose T;
	cv::Matx66d C;
	cv::Matx33d S[4], W[4];
	cv::Vec3d r[4];
	cv::Matx<double, 3, 6> A[4];
};

// The weighted fit of points P (layout id order, n = 3 or 4) with covariances S. False
// when degenerate or a covariance is singular.
bool fit_layout_weighted(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S,
                         int n, WeightedFit *fit);

// Baarda's w-test (standard normal on clean data) of one fault in the weighted fit: point
// i moved along unit u. *out_per_m: how much w grows per metre the point moves along u
// (the square root of its information; 0: the fit cannot see such a fault, and w is 0).
double fault_w(const WeightedFit &fit, int i, const cv::Vec3d &u, double *out_per_m);

// Linearised RMS rotation error (rad) and 3-D RMS error of the display origin of the pose
// fitted to points P[i] (camera frame, layout id order: the three markers, and with n = 4
// the layout's verifier) with covariances S[i] (docs/optical.md, "Error law"). Infinite
// when the points are degenerate.
void pose_error_law(const rs_pose_layout &layout, const cv::Vec3d *P, const cv::Matx33d *S, int n,
                    double *out_rot_rms, double *out_pos_rms);

// Inverse covariance, per unit centroid variance, of a centroid in undistorted pixels at
// `undistorted` (the lens's distortion Jacobian; the identity without distortion).
cv::Matx22d centroid_weight(const rs_optical_camera &c, cv::Point2d undistorted);

// Chi-square of the side lengths of P (layout_sides[k] opposite P[k]) for marker
// covariances S: in total (3 degrees of freedom) and per marker (the two sides meeting at
// it, 2 degrees). Infinite when the points coincide.
void side_chi2(const double layout_sides[3], const cv::Vec3d P[3], const cv::Matx33d S[3],
               double *out_total, double out_marker[3]);

// The temporal prior of the step gate: the last reported pose moved on to this frame, and
// the stated errors rs_pose_step_score() weighs a step with.
struct StepPrior {
	rs_pose predicted;
	double rot_rms, pos_rms, dt;
};

// The largest pose error (rotation rad, position m) one gross centroid fault could cause
// and still pass the side tests (and, with a prior, the step gate): a centroid moved along
// its epipolar line moves marker i along the other camera's ray, rays[i][v] (unit, v the
// camera whose ray it is).
void fault_bound(const rs_pose_layout &layout, const double layout_sides[3], const cv::Vec3d P[3],
                 const cv::Matx33d S[3], const cv::Vec3d rays[3][2], const StepPrior *prior,
                 double *out_rot, double *out_pos);

} // namespace rs_optical

#endif
