// The optical tracker's state and what its two files share (not installed): tracker.cpp
// matches, labels, gates and reports; verifier.cpp checks the layout's verifier light.
#ifndef RS_OPTICAL_TRACKER_INTERNAL_HPP
#define RS_OPTICAL_TRACKER_INTERNAL_HPP

#include "optical_detect.hpp"
#include "optical_internal.hpp"

#include <vector>

namespace rs_optical
{

// The six orders of a triple: k_perms[order][k] is the layout id of the triple's k-th pair.
constexpr int k_perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

struct Pair {
	int i, j;    // blob indices in view 0 and 1
	cv::Vec3d X; // triangulated, camera-0 frame
};

} // namespace rs_optical

struct rs_optical_tracker {
	rs_optical_tracker_desc d;
	cv::Matx34d P0, P1; // pixels
	cv::Matx34d N0, N1; // normalised camera coordinates
	cv::Matx33d F;      // undistorted pixel coordinates: x1^T F x0 = 0
	double layout_sides[3];
	rs_optical::DetectScratch scratch;
	rs_optical::Mask mask[2]; // the desc's rectangles and the integral of its mask image
	std::vector<rs_optical_blob> blobs[2];
	std::vector<cv::Point2d> raw[2], und[2];
	std::vector<double> area[2];   // thresholded area of each raw centroid's spot (0: unknown)
	std::vector<cv::Matx22d> W[2]; // each centroid's inverse covariance per sigma^2
	rs_optical::DetectCounts counts[2];
	std::vector<rs_optical::Pair> pairs;
	std::vector<cv::Vec3d> candidates;        // centroids of the triples that fit the layout
	std::vector<cv::Vec4i> candidate_triples; // their pairs (a, b, c) and order
	bool have_last = false;                   // the last triple reported, for settle_by_prior()
	double last_time = 0;
	cv::Vec3d last_centroid;
	// The last reported display pose, its stated errors and smoothed velocities: the
	// step gate's prediction.
	rs_pose last_pose;
	double last_rot_rms = 0, last_pos_rms = 0;
	uint32_t chain = 0; // reported poses in a row, each within the step gate of the last
	// The last reported pose's bound on what an undetected stray spot may have added to its
	// error (rotation rad, position m): the integrity bound's fault part.
	double last_bound_rot = 0, last_bound_pos = 0;
	double velocity[3] = {0, 0, 0}, angular_velocity[3] = {0, 0, 0};
	// Whether those came from two reported poses in a row (at most k_prior_max_age_s
	// apart): after a cold pose the velocity is unknown, not zero.
	bool velocity_known = false;
};

namespace rs_optical
{

// tracker.cpp
// Best labelling of three points: cost = squared side mismatch, worst = largest mismatch.
int best_order(const double ls[3], const cv::Vec3d p[3], double *cost, double *worst);
// The 2x3 projection Jacobian of view M at X and the residual of the observation; false
// behind the camera.
bool project_jacobian(const cv::Matx34d &M, const cv::Vec3d &X, cv::Point2d obs, cv::Matx23d *J,
                      cv::Vec2d *r);
// Covariance of a triangulated point for the tracker's centroid noise.
cv::Matx33d point_cov(const rs_optical_tracker &t, const cv::Vec3d &X, const cv::Matx22d W[2]);
// The maximum-likelihood point of two observations, from X.
cv::Vec3d refine(const rs_optical_tracker &t, cv::Vec3d X, const cv::Point2d obs[2],
                 const cv::Matx22d W[2]);
// The DLT point of undistorted pixels a (view 0) and b (view 1).
cv::Vec3d triangulate(const rs_optical_tracker &t, cv::Point2d a, cv::Point2d b);
// The stated errors and the integrity bound of q from the law and the fault part.
void state_errors(double rot, double pos, double fault_rot, double fault_pos,
                  rs_optical_quality &q);

// verifier.cpp (docs/optical.md, "The verifier")
rs_optical_verdict verify(const rs_optical_tracker &t, const cv::Vec3d pts[3],
                          const cv::Matx33d cov[3], const int used[2][3], rs_optical_quality &q,
                          cv::Vec3d *out_V, cv::Matx33d *out_S);
rs_optical_verdict fit_with_verifier(const rs_optical_tracker &t, const cv::Vec3d &V,
                                     const cv::Matx33d &S, double fault_rot, double fault_pos,
                                     cv::Vec3d pts[3], const cv::Matx33d cov[3],
                                     rs_optical_quality &q);
void settle_by_verifier(rs_optical_tracker &t, int best[3], int *order, double *worst);

} // namespace rs_optical

#endif
