// Frame pair -> three labelled marker positions: blobs in both views, pairs on each other's
// epipolar line, triangulation, the triple whose side lengths fit the layout, refinement
// (optimal correction onto the epipolar geometry, then triangulation) and quality figures.
#include "tracker_internal.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>
#include <vector>

using namespace rs_optical;

namespace
{

const size_t k_max_blobs = 24; // per view; more bright spots than this is not a marker scene
// The last triple settles an ambiguous frame only if at most this old, and only for a
// candidate within this distance of it while every other candidate is farther (and 3x
// farther): a reflection of the display lies centimetres to decimetres away.
const double k_prior_max_age_s = 0.1;
// The step gate predicts from the raw velocity of the last two poses: a smoothed one lags a
// shaking hand by its time constant times the acceleration, degrees per frame. Its noise,
// about the last pose's error, adds to the stated errors instead.
const double k_velocity_tc_s = 0.0;
const double k_prior_reach_m = 0.02;
// Spot-size agreement of a marker between the views (spot_sizes_agree()).
const double k_spot_size_ratio = 2.0;
const double k_spot_size_px = 4.0;
// The integrity bound's noise part, in stated (expected) errors: the bar for a good
// pose's error against its noise (docs/optical.md, "The stated error and the integrity bound").
const double k_bound_noise = 5.0;

} // namespace

static void sides_of(const cv::Vec3d p[3], double s[3])
{
	s[0] = cv::norm(p[2] - p[1]);
	s[1] = cv::norm(p[0] - p[2]);
	s[2] = cv::norm(p[1] - p[0]);
}

cv::Vec3d rs_optical::triangulate(const rs_optical_tracker &t, cv::Point2d a, cv::Point2d b)
{
	// Linear (DLT) triangulation, as cv::triangulatePoints, for one point without
	// allocating: the null vector of the 4x4 system by SVD. In normalised camera
	// coordinates, where the system's entries are O(1); in pixels its conditioning skews
	// the algebraic solution several times beyond the geometric error.
	cv::Point2d n[2];
	for (int v = 0; v < 2; ++v) {
		const double *K = t.d.rig.cam[v].K;
		cv::Point2d p = v ? b : a;
		n[v] = cv::Point2d((p.x - K[2]) / K[0], (p.y - K[5]) / K[4]);
	}
	cv::Matx44d A;
	for (int k = 0; k < 4; ++k) {
		A(0, k) = n[0].x * t.N0(2, k) - t.N0(0, k);
		A(1, k) = n[0].y * t.N0(2, k) - t.N0(1, k);
		A(2, k) = n[1].x * t.N1(2, k) - t.N1(0, k);
		A(3, k) = n[1].y * t.N1(2, k) - t.N1(1, k);
	}
	cv::Matx44d u, vt;
	cv::Matx41d w;
	cv::SVD::compute(A, w, u, vt, cv::SVD::FULL_UV);
	double h = vt(3, 3);
	if (!(std::fabs(h) > 1e-300))
		return cv::Vec3d(0, 0, -1);
	return cv::Vec3d(vt(3, 0) / h, vt(3, 1) / h, vt(3, 2) / h);
}

static double epipolar_distance(const cv::Matx33d &F, cv::Point2d a, cv::Point2d b)
{
	cv::Vec3d x0(a.x, a.y, 1), x1(b.x, b.y, 1);
	cv::Vec3d l1 = F * x0, l0 = F.t() * x1;
	double e = x1.dot(l1);
	double d1 = std::fabs(e) / std::hypot(l1[0], l1[1]);
	double d0 = std::fabs(e) / std::hypot(l0[0], l0[1]);
	return std::max(d0, d1);
}

extern "C" enum rs_status rs_optical_tracker_create(const struct rs_optical_tracker_desc *desc,
                                                    struct rs_optical_tracker **out,
                                                    struct rs_error *err)
{
	RS_ASSERT(desc && out);
	*out = nullptr;
	rs_optical_tracker_desc d = *desc;
	enum rs_status st = rs_optical_rig_check(&d.rig, err);
	if (st != RS_OK)
		return st;
	static const rs_pose_layout zero = {};
	if (!std::memcmp(&d.layout, &zero, sizeof zero))
		rs_pose_layout_default(&d.layout);
	if ((st = rs_pose_layout_check(&d.layout, err)) != RS_OK)
		return st;
	rs_optical_detect_desc dd;
	resolve_detect(&d.detect, &dd);
	d.detect = dd;
	if (d.centroid_sigma_px == 0.0)
		d.centroid_sigma_px = 0.3;
	// The distance from the epipolar line carries the noise of both centroids (~sqrt(2)
	// sigma): the default gate is 6 of those, and never below 2 px.
	if (d.epipolar_gate_px == 0.0 && std::isfinite(d.centroid_sigma_px))
		d.epipolar_gate_px = std::max(2.0, 6.0 * std::sqrt(2.0) * d.centroid_sigma_px);
	if (d.side_tolerance_m == 0.0)
		d.side_tolerance_m = 0.01;
	for (int v = 0; v < 2; ++v) {
		const rs_optical_mask &m = d.mask[v];
		if (m.count > RS_OPTICAL_MAX_MASK_RECTS)
			return rs_error_set(
			    err, RS_ERR_INVALID,
			    "optical tracker: camera %d mask has %u rectangles (at most %d)", v,
			    m.count, RS_OPTICAL_MAX_MASK_RECTS);
		for (uint32_t k = 0; k < m.count; ++k)
			if (!(m.rects[k].width > 0 && m.rects[k].height > 0))
				return rs_error_set(
				    err, RS_ERR_INVALID,
				    "optical tracker: camera %d mask rectangle %u is empty", v, k);
		const rs_optical_camera &c = d.rig.cam[v];
		if (m.pixels &&
		    (m.width != c.width || m.height != c.height || m.stride < (size_t)m.width))
			return rs_error_set(
			    err, RS_ERR_INVALID,
			    "optical tracker: camera %d mask image is %dx%d (stride "
			    "%zu), the camera's frames %dx%d",
			    v, m.width, m.height, m.stride, c.width, c.height);
	}
	// The verifier and two markers must never fit the layout within the triple's tolerance,
	// or it could be labelled a marker: rs_pose_layout_check() keeps those triangles at
	// least RS_POSE_LAYOUT_MIN_VERIFIER_M from the layout's sides.
	if (d.layout.has_verifier && !(d.side_tolerance_m < RS_POSE_LAYOUT_MIN_VERIFIER_M))
		return rs_error_set(
		    err, RS_ERR_DEGENERATE,
		    "optical tracker: with a verifier, side_tolerance_m (%.4f m) must "
		    "be below %.4f m, or the verifier could be taken for a marker",
		    d.side_tolerance_m, RS_POSE_LAYOUT_MIN_VERIFIER_M);
	if (!detect_desc_valid(dd) || !(d.epipolar_gate_px > 0) ||
	    !std::isfinite(d.epipolar_gate_px) || !(d.centroid_sigma_px > 0) ||
	    !std::isfinite(d.centroid_sigma_px) || !(d.side_tolerance_m > 0) ||
	    !std::isfinite(d.side_tolerance_m))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "optical tracker: gates and sigmas must be finite and > 0");
	rs_optical_tracker *t = new (std::nothrow) rs_optical_tracker();
	if (!t)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical tracker: out of memory");
	t->d = d;
	try {
		for (int v = 0; v < 2; ++v) {
			rs_optical_mask &m = t->d.mask[v];
			t->mask[v].rects = &m;
			if (m.pixels) {
				cv::Mat img(m.height, m.width, CV_8UC1,
				            const_cast<uint8_t *>(m.pixels), m.stride);
				cv::Mat ones = (img != 0) / 255; // 1 where masked
				cv::integral(ones, t->mask[v].sum, CV_32S);
			}
			m.pixels = nullptr; // the caller's; the integral is the tracker's copy
		}
	} catch (const cv::Exception &e) {
		delete t;
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical tracker: %.160s",
		                    e.msg.c_str());
	}
	cv::Matx33d K0 = K_of(d.rig.cam[0]), K1 = K_of(d.rig.cam[1]), R = R_of(d.rig);
	cv::Vec3d tv = t_of(d.rig);
	cv::Matx34d I34(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0);
	cv::Matx34d Rt(R(0, 0), R(0, 1), R(0, 2), tv[0], R(1, 0), R(1, 1), R(1, 2), tv[1], R(2, 0),
	               R(2, 1), R(2, 2), tv[2]);
	t->N0 = I34;
	t->N1 = Rt;
	t->P0 = K0 * I34;
	t->P1 = K1 * Rt;
	cv::Matx33d tx(0, -tv[2], tv[1], tv[2], 0, -tv[0], -tv[1], tv[0], 0);
	t->F = K1.inv().t() * tx * R * K0.inv();
	cv::Vec3d m[3];
	for (int i = 0; i < 3; ++i)
		m[i] = cv::Vec3d(d.layout.markers[i]);
	sides_of(m, t->layout_sides);
	*out = t;
	return RS_OK;
}

extern "C" void rs_optical_tracker_destroy(struct rs_optical_tracker **tracker)
{
	if (!tracker)
		return;
	delete *tracker;
	*tracker = nullptr;
}

// Best labelling of three points: cost = squared side mismatch, worst = largest mismatch.
int rs_optical::best_order(const double ls[3], const cv::Vec3d p[3], double *cost, double *worst)
{
	double s[3];
	sides_of(p, s);
	int best = 0;
	*cost = *worst = INFINITY;
	for (int q = 0; q < 6; ++q) {
		double c = 0, w = 0;
		for (int k = 0; k < 3; ++k) {
			double e = std::fabs(s[k] - ls[k_perms[q][k]]);
			c += e * e;
			w = std::max(w, e);
		}
		if (c < *cost) {
			*cost = c;
			*worst = w;
			best = q;
		}
	}
	return best;
}

// The 2x3 projection Jacobian of view M at X (undistorted pixels per metre) and the
// residual of the observation; false behind the camera.
bool rs_optical::project_jacobian(const cv::Matx34d &M, const cv::Vec3d &X, cv::Point2d obs,
                                  cv::Matx23d *J, cv::Vec2d *r)
{
	cv::Vec3d x = M * cv::Vec4d(X[0], X[1], X[2], 1.0);
	if (!(x[2] > 0))
		return false;
	for (int row = 0; row < 2; ++row)
		for (int k = 0; k < 3; ++k)
			(*J)(row, k) = (M(row, k) * x[2] - M(2, k) * x[row]) / (x[2] * x[2]);
	*r = cv::Vec2d(x[0] / x[2] - obs.x, x[1] / x[2] - obs.y);
	return true;
}

// Both views' J^T W J at X, W each centroid's inverse covariance in undistorted pixels
// (the lens's distortion Jacobian): the inverse is the covariance of the maximum-likelihood
// point per unit centroid variance.
static cv::Matx33d info_matrix(const rs_optical_tracker &t, const cv::Vec3d &X,
                               const cv::Matx22d W[2])
{
	const cv::Matx34d *P[2] = {&t.P0, &t.P1};
	cv::Matx33d JtJ = cv::Matx33d::zeros();
	for (int v = 0; v < 2; ++v) {
		cv::Matx23d J;
		cv::Vec2d r;
		if (project_jacobian(*P[v], X, cv::Point2d(0, 0), &J, &r))
			JtJ += J.t() * W[v] * J;
	}
	return JtJ;
}

// Covariance of a triangulated point for centroid noise sigma_px per image coordinate:
// sigma^2 (J^T W J)^-1; infinite when the views do not constrain it.
cv::Matx33d rs_optical::point_cov(const rs_optical_tracker &t, const cv::Vec3d &X,
                                  const cv::Matx22d W[2])
{
	cv::Matx33d inv;
	if (!cv::invert(info_matrix(t, X, W), inv, cv::DECOMP_CHOLESKY))
		return cv::Matx33d::eye() * INFINITY;
	return inv * (t.d.centroid_sigma_px * t.d.centroid_sigma_px);
}

// Weighted squared reprojection error of X in both views (r^T W r per view).
static void reprojection(const rs_optical_tracker &t, const cv::Vec3d &X, const cv::Point2d obs[2],
                         const cv::Matx22d W[2], double e2[2])
{
	const cv::Matx34d *P[2] = {&t.P0, &t.P1};
	for (int v = 0; v < 2; ++v) {
		cv::Matx23d J;
		cv::Vec2d r;
		e2[v] = project_jacobian(*P[v], X, obs[v], &J, &r) ? r.dot(W[v] * r) : INFINITY;
	}
}

// Gauss-Newton on the weighted reprojection error in both views (the maximum-likelihood
// point for Gaussian centroid noise), from the DLT solution; three steps converge to
// ~1e-9 px.
cv::Vec3d rs_optical::refine(const rs_optical_tracker &t, cv::Vec3d X, const cv::Point2d obs[2],
                             const cv::Matx22d W[2])
{
	const cv::Matx34d *P[2] = {&t.P0, &t.P1};
	for (int it = 0; it < 3; ++it) {
		cv::Matx33d JtJ = cv::Matx33d::zeros();
		cv::Vec3d Jtr(0, 0, 0);
		for (int v = 0; v < 2; ++v) {
			cv::Matx23d J;
			cv::Vec2d r;
			if (!project_jacobian(*P[v], X, obs[v], &J, &r))
				return X;
			JtJ += J.t() * W[v] * J;
			Jtr += J.t() * (W[v] * r);
		}
		cv::Vec3d step;
		if (!cv::solve(JtJ, -Jtr, step, cv::DECOMP_CHOLESKY))
			return X;
		X += step;
	}
	return X;
}

static void empty_sample(double time_s, rs_marker_sample *out)
{
	std::memset(out, 0, sizeof *out);
	out->host_time_s = time_s;
}

// Two or more triples fit the layout (a reflection of the whole display, a second
// display): side lengths cannot say which is the display. The last reported triple, if
// recent, settles it when one candidate is near it and every other far; otherwise the
// frame is ambiguous and gives no markers.
static bool settle_by_prior(const rs_optical_tracker &t, double time_s, const cv::Vec3d &best)
{
	if (!t.have_last || !(std::fabs(time_s - t.last_time) <= k_prior_max_age_s))
		return false;
	double d_best = cv::norm(best - t.last_centroid), d_other = INFINITY;
	for (const cv::Vec3d &c : t.candidates) {
		double d = cv::norm(c - t.last_centroid);
		if (cv::norm(c - best) > 1e-9)
			d_other = std::min(d_other, d);
	}
	return d_best <= k_prior_reach_m && d_other > std::max(3.0 * d_best, k_prior_reach_m);
}

// One LED seen by both cameras makes spots of about the same size in each (the views are
// 1 m away and 0.4 m apart: distance and emission angle differ little), and the three
// markers of one display change alike from one view to the other. A marker whose
// view-1/view-0 area ratio is off the other two's by more than 2x (and 4 px) pairs a spot
// with another light on its epipolar line: where that line runs along the display's
// normal the side lengths cannot see it (docs/optical.md). Unknown areas (0, blobs from
// elsewhere) are not tested.
static bool spot_sizes_agree(const rs_optical_tracker &t, const std::vector<Pair> &P,
                             const int best[3])
{
	double a0[3], a1[3], lr[3];
	for (int k = 0; k < 3; ++k) {
		a0[k] = t.area[0][P[best[k]].i];
		a1[k] = t.area[1][P[best[k]].j];
		if (!(a0[k] > 0) || !(a1[k] > 0))
			return true;
		lr[k] = std::log(a1[k] / a0[k]);
	}
	for (int k = 0; k < 3; ++k) {
		double ref = 0.5 * (lr[(k + 1) % 3] + lr[(k + 2) % 3]);
		if (std::fabs(lr[k] - ref) > std::log(k_spot_size_ratio) &&
		    std::fabs(a1[k] - a0[k] * std::exp(ref)) > k_spot_size_px)
			return false;
	}
	return true;
}

// The temporal prior at time_s: the last reported pose moved on at the raw velocity of the
// last two, with the errors a step from it is weighed by. False without a recent one.
static bool step_prior(const rs_optical_tracker &t, double time_s, const rs_optical_quality &q,
                       StepPrior *out)
{
	double since = time_s - t.last_time;
	// Without a velocity there is no prediction: a display moving at 0.1 m/s is 1.7 mm
	// from a constant-position one after a frame, which a step test of a pose's stated
	// error would refuse (the frames after every gap were held until a pose happened to
	// fall within it).
	if (!t.have_last || !t.velocity_known || !(since > 0) || since > k_prior_max_age_s)
		return false;
	rs_pose_extrapolate(&t.last_pose, t.velocity, t.angular_velocity, since, &out->predicted);
	// Variance of the step: this pose's, the last one's, and the velocity's (two poses'
	// differences over one interval, extrapolated over about one).
	double lr = t.last_rot_rms, lp = t.last_pos_rms;
	out->rot_rms = std::sqrt(3 * lr * lr + q.rotation_rms_rad * q.rotation_rms_rad);
	out->pos_rms = std::sqrt(3 * lp * lp + q.position_rms_m * q.position_rms_m);
	out->dt = since;
	return true;
}

// The display pose of the labelled markers, and whether it follows the prior (constant
// velocity) within both poses' stated errors and a hand's acceleration.
static rs_optical_verdict step_gate(const rs_optical_tracker &t, const cv::Vec3d pts[3],
                                    double time_s, const StepPrior *prior, rs_optical_quality &q,
                                    rs_pose *pose)
{
	rs_pose T;
	if (!fit_layout(t.d.layout, pts, 3, &T))
		return RS_OPTICAL_SIDE_RESIDUAL; // collinear: the side test cannot have passed
	rs_pose_compose(&T, &t.d.layout.T_markers_display, pose);
	pose->time_s = time_s;
	if (!prior)
		return RS_OPTICAL_SOLVED;
	q.step_score = rs_pose_step_score(&prior->predicted, pose, prior->rot_rms, prior->pos_rms,
	                                  prior->dt, 0.0);
	return q.step_score <= RS_POSE_STEP_CHI2 ? RS_OPTICAL_SOLVED : RS_OPTICAL_STEP;
}

// Blobs from elsewhere (rs_optical_tracker_process_blobs, only x and y read) carry no
// window: a centroid closer to the edge than the centroid margin plus a pixel of spot
// radius was taken over a clipped spot.
static bool near_edge(const rs_optical_camera &c, const rs_optical_blob &b)
{
	const double support = k_centroid_margin_px + 1.0;
	return b.x - support < -0.5 || b.y - support < -0.5 || b.x + support > c.width - 0.5 ||
	       b.y + support > c.height - 0.5;
}

// The consistency gate of the chosen triple (gate.cpp, docs/optical.md): each marker's
// reprojection error, each marker's rigid-fit residual and the side lengths, all against
// the covariances stated for centroid_sigma_px.
static rs_optical_verdict gate(const rs_optical_tracker &t, const cv::Vec3d pts[3],
                               const cv::Matx33d cov[3], rs_optical_quality &q)
{
	double mc[3];
	side_chi2(t.layout_sides, pts, cov, &q.side_chi2, mc);
	q.marker_chi2 = std::max(mc[0], std::max(mc[1], mc[2]));
	if (!(q.reprojection_chi2 <= RS_OPTICAL_CHI2_1DOF))
		return RS_OPTICAL_REPROJECTION;
	if (!(q.marker_chi2 <= RS_OPTICAL_CHI2_2DOF))
		return RS_OPTICAL_MARKER_RESIDUAL;
	if (!(q.side_chi2 <= RS_OPTICAL_CHI2_3DOF))
		return RS_OPTICAL_SIDE_RESIDUAL;
	return RS_OPTICAL_SOLVED;
}

// The claim is the expected error (the law); the integrity bound adds the fault part (what
// one undetected stray spot may have added) to the noise the gate's 5x bar allows
// (docs/optical.md).
void rs_optical::state_errors(double rot, double pos, double fault_rot, double fault_pos,
                              rs_optical_quality &q)
{
	q.rotation_rms_rad = q.stated_rotation_rad = rot;
	q.position_rms_m = q.stated_position_m = pos;
	q.bound_rotation_rad = fault_rot + k_bound_noise * rot;
	q.bound_position_m = fault_pos + k_bound_noise * pos;
}

// Blobs of both views (t->blobs) to the sample: undistort, match, triangulate, label, gate.
static rs_status solve_blobs(rs_optical_tracker *t, bool external, double time_s,
                             rs_marker_sample *out, rs_optical_quality &q, rs_error *err)
{
	q.has_verifier = t->d.layout.has_verifier != 0;
	try {
		for (int v = 0; v < 2; ++v) {
			const rs_optical_camera &c = t->d.rig.cam[v];
			q.blobs_at_edge[v] = t->counts[v].at_edge;
			q.blobs_crowded[v] = t->counts[v].crowded;
			q.blobs_masked[v] = t->counts[v].masked;
			t->raw[v].clear();
			t->area[v].clear();
			for (const rs_optical_blob &b : t->blobs[v]) {
				if (external && near_edge(c, b)) {
					q.blobs_at_edge[v]++;
					continue;
				}
				// No window: the spot reaches a pixel of radius and the margin.
				const int reach = k_centroid_margin_px + 1;
				if (external &&
				    window_masked(&t->mask[v], (int)std::floor(b.x + 0.5) - reach,
				                  (int)std::floor(b.y + 0.5) - reach,
				                  (int)std::floor(b.x + 0.5) + reach + 1,
				                  (int)std::floor(b.y + 0.5) + reach + 1)) {
					q.blobs_masked[v]++;
					continue;
				}
				t->raw[v].emplace_back(b.x, b.y);
				t->area[v].push_back(b.area_px);
			}
			q.blobs[v] = (uint32_t)t->raw[v].size();
			if (t->raw[v].empty())
				t->und[v].clear();
			else
				cv::undistortPoints(t->raw[v], t->und[v], K_of(c), dist_of(c),
				                    cv::noArray(), K_of(c));
			t->W[v].clear();
			for (const cv::Point2d &p : t->und[v])
				t->W[v].push_back(centroid_weight(c, p));
		}
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical tracker: %.160s",
		                    e.msg.c_str());
	}
	t->pairs.clear();
	cv::Matx33d R = R_of(t->d.rig);
	cv::Vec3d tv = t_of(t->d.rig);
	for (int i = 0; i < (int)t->und[0].size(); ++i)
		for (int j = 0; j < (int)t->und[1].size(); ++j) {
			cv::Point2d a = t->und[0][i], b = t->und[1][j];
			if (!(epipolar_distance(t->F, a, b) <= t->d.epipolar_gate_px))
				continue;
			cv::Vec3d X = triangulate(*t, a, b);
			if (!(X[2] > 0) || !((R * X + tv)[2] > 0))
				continue;
			t->pairs.push_back({i, j, X});
		}
	q.matches = (uint32_t)t->pairs.size();
	// The triple of one-to-one pairs whose side lengths fit the layout best. A stray light
	// on an epipolar line triangulates to a point, but not one at the layout's distances.
	int best[3] = {-1, -1, -1}, order = 0;
	double best_cost = INFINITY, best_worst = INFINITY;
	const std::vector<Pair> &P = t->pairs;
	t->candidates.clear();
	t->candidate_triples.clear();
	for (size_t a = 0; a < P.size(); ++a)
		for (size_t b = a + 1; b < P.size(); ++b) {
			if (P[a].i == P[b].i || P[a].j == P[b].j)
				continue;
			for (size_t c = b + 1; c < P.size(); ++c) {
				if (P[c].i == P[a].i || P[c].i == P[b].i || P[c].j == P[a].j ||
				    P[c].j == P[b].j)
					continue;
				cv::Vec3d pts[3] = {P[a].X, P[b].X, P[c].X};
				double cost, worst;
				int o = best_order(t->layout_sides, pts, &cost, &worst);
				if (worst <= t->d.side_tolerance_m) {
					t->candidates.push_back((pts[0] + pts[1] + pts[2]) / 3.0);
					t->candidate_triples.push_back(
					    cv::Vec4i((int)a, (int)b, (int)c, o));
				}
				if (cost < best_cost) {
					best_cost = cost;
					best_worst = worst;
					order = o;
					best[0] = (int)a;
					best[1] = (int)b;
					best[2] = (int)c;
				}
			}
		}
	if (best[0] < 0 || !(best_worst <= t->d.side_tolerance_m)) {
		q.side_error_m = best[0] < 0 ? 0.0 : best_worst;
		q.verdict = best[0] < 0 ? RS_OPTICAL_TOO_FEW_MATCHES : RS_OPTICAL_NO_LAYOUT;
		return RS_OK;
	}
	if (t->candidates.size() > 1 && t->d.layout.has_verifier)
		settle_by_verifier(*t, best, &order, &best_worst);
	if (t->candidates.size() > 1 &&
	    !settle_by_prior(*t, time_s, (P[best[0]].X + P[best[1]].X + P[best[2]].X) / 3.0)) {
		q.side_error_m = best_worst;
		q.verdict = RS_OPTICAL_AMBIGUOUS;
		return RS_OK;
	}
	if (!spot_sizes_agree(*t, P, best)) {
		q.side_error_m = best_worst;
		q.verdict = RS_OPTICAL_SPOT_SIZE;
		return RS_OK;
	}
	double sq = 0, sig = 0, s2 = t->d.centroid_sigma_px * t->d.centroid_sigma_px;
	cv::Vec3d pts[3];
	cv::Matx33d cov[3];
	for (int k = 0; k < 3; ++k) {
		const Pair &p = P[best[k]];
		const cv::Point2d obs[2] = {t->und[0][p.i], t->und[1][p.j]};
		const cv::Matx22d W[2] = {t->W[0][p.i], t->W[1][p.j]};
		cv::Vec3d X = refine(*t, p.X, obs, W);
		double e2[2];
		reprojection(*t, X, obs, W, e2);
		sq += (e2[0] + e2[1]) / 2.0;
		// Four image coordinates, three for the point: one degree of freedom.
		q.reprojection_chi2 = std::max(q.reprojection_chi2, (e2[0] + e2[1]) / s2);
		int id = k_perms[order][k];
		pts[id] = X;
		cov[id] = point_cov(*t, X, W);
		sig += cv::trace(cov[id]) / 3.0;
	}
	q.reprojection_px = std::sqrt(sq / 3.0);
	q.side_error_m = best_worst;
	q.sigma_m = std::sqrt(sig / 3.0);
	pose_error_law(t->d.layout, pts, cov, 3, &q.rotation_rms_rad, &q.position_rms_m);
	double bound_rot, bound_pos;
	StepPrior prior_store;
	const StepPrior *prior = step_prior(*t, time_s, q, &prior_store) ? &prior_store : nullptr;
	{
		// A stray spot on marker id's epipolar line in one view moves it along the
		// other view's ray: rays[id][v] is camera v's.
		cv::Vec3d c1 = -(R.t() * tv), rays[3][2];
		for (int id = 0; id < 3; ++id) {
			rays[id][0] = pts[id] / cv::norm(pts[id]);
			rays[id][1] = (pts[id] - c1) / cv::norm(pts[id] - c1);
		}
		// What one undetected stray spot may have added (the fault part). A cold pose
		// carries the whole fault bound F. With a prior, a stray that appeared since the
		// last pose can move this one only as far as the step gate lets it (the bound
		// with the prior, R), and the last pose's own fault part carries over (the
		// prediction inherits its fault): min(F, last fault part + R).
		double br, bp;
		fault_bound(t->d.layout, t->layout_sides, pts, cov, rays, nullptr, &br, &bp);
		if (prior) {
			double rr, rp;
			fault_bound(t->d.layout, t->layout_sides, pts, cov, rays, prior, &rr, &rp);
			br = std::min(br, t->last_bound_rot + rr);
			bp = std::min(bp, t->last_bound_pos + rp);
		}
		state_errors(q.rotation_rms_rad, q.position_rms_m, br, bp, q);
		bound_rot = br;
		bound_pos = bp;
	}
	q.verdict = gate(*t, pts, cov, q);
	if (q.verdict == RS_OPTICAL_SOLVED && t->d.layout.has_verifier) {
		const int used[2][3] = {{P[best[0]].i, P[best[1]].i, P[best[2]].i},
		                        {P[best[0]].j, P[best[1]].j, P[best[2]].j}};
		cv::Vec3d VX;
		cv::Matx33d VS;
		q.verdict = verify(*t, pts, cov, used, q, &VX, &VS);
		if (q.verdict == RS_OPTICAL_SOLVED && q.verifier_views == 2)
			q.verdict =
			    fit_with_verifier(*t, VX, VS, bound_rot, bound_pos, pts, cov, q);
	}
	rs_pose pose;
	if (q.verdict == RS_OPTICAL_SOLVED)
		q.verdict = step_gate(*t, pts, time_s, prior, q, &pose);
	if (q.verdict != RS_OPTICAL_SOLVED) {
		t->chain = 0;
		return RS_OK; // held by the solver: never a pose the gate refuses
	}
	q.prior_frames = prior ? t->chain : 0;
	// Poses in a row: this one follows the last reported within k_prior_max_age_s. The
	// second of a row has no prior (no velocity yet) but is in the row, and gives one.
	bool follows =
	    t->have_last && time_s - t->last_time > 0 && time_s - t->last_time <= k_prior_max_age_s;
	t->chain = follows ? t->chain + 1 : 1;
	t->velocity_known = follows;
	rs_pose_velocity_update(t->have_last ? &t->last_pose : nullptr, &pose, k_velocity_tc_s,
	                        k_prior_max_age_s, t->velocity, t->angular_velocity);
	t->last_pose = pose;
	t->last_rot_rms = q.rotation_rms_rad;
	t->last_pos_rms = q.position_rms_m;
	t->last_bound_rot = bound_rot;
	t->last_bound_pos = bound_pos;
	t->have_last = true;
	t->last_time = time_s;
	t->last_centroid = (pts[0] + pts[1] + pts[2]) / 3.0;
	out->marker_count = 3;
	for (int id = 0; id < 3; ++id) {
		rs_marker &m = out->markers[id];
		m.id = (uint32_t)id;
		m.flags = RS_MARKER_VALID;
		for (int c = 0; c < 3; ++c)
			m.position[c] = pts[id][c];
	}
	q.markers = 3;
	return RS_OK;
}

extern "C" enum rs_status rs_optical_tracker_process(struct rs_optical_tracker *t,
                                                     const struct rs_optical_image *img0,
                                                     const struct rs_optical_image *img1,
                                                     double time_s, struct rs_marker_sample *out,
                                                     struct rs_optical_quality *out_quality,
                                                     struct rs_error *err)
{
	rs_optical_quality qd;
	rs_optical_quality &q = out_quality ? *out_quality : qd;
	std::memset(&q, 0, sizeof q);
	RS_ASSERT(t && out);
	empty_sample(time_s, out);
	const rs_optical_image *img[2] = {img0, img1};
	for (int v = 0; v < 2; ++v) {
		if (!img[v])
			continue;
		if (check_image(img[v], err) != RS_OK)
			return RS_ERR_INVALID;
		const rs_optical_camera &c = t->d.rig.cam[v];
		if (img[v]->width != c.width || img[v]->height != c.height)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "optical tracker: camera %d frame is %dx%d, calibrated "
			                    "%dx%d",
			                    v, img[v]->width, img[v]->height, c.width, c.height);
	}
	if (!img0 || !img1) {
		q.verdict = RS_OPTICAL_ONE_VIEW; // one camera alone cannot triangulate
		return RS_OK;
	}
	try {
		for (int v = 0; v < 2; ++v) {
			detect(wrap(*img[v]), t->d.detect, t->scratch, t->blobs[v], &t->counts[v],
			       &t->mask[v]);
			if (t->blobs[v].size() > k_max_blobs)
				t->blobs[v].resize(k_max_blobs);
		}
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical tracker: %.160s",
		                    e.msg.c_str());
	}
	return solve_blobs(t, false, time_s, out, q, err);
}

extern "C" enum rs_status
rs_optical_tracker_process_blobs(struct rs_optical_tracker *t, const struct rs_optical_blob *blobs0,
                                 size_t n0, const struct rs_optical_blob *blobs1, size_t n1,
                                 double time_s, struct rs_marker_sample *out,
                                 struct rs_optical_quality *out_quality, struct rs_error *err)
{
	rs_optical_quality qd;
	rs_optical_quality &q = out_quality ? *out_quality : qd;
	std::memset(&q, 0, sizeof q);
	RS_ASSERT(t && out && (!n0 || blobs0) && (!n1 || blobs1));
	empty_sample(time_s, out);
	const rs_optical_blob *b[2] = {blobs0, blobs1};
	t->counts[0] = t->counts[1] = DetectCounts{};
	size_t n[2] = {std::min(n0, k_max_blobs), std::min(n1, k_max_blobs)};
	for (int v = 0; v < 2; ++v) {
		t->blobs[v].assign(b[v], b[v] + n[v]);
		for (const rs_optical_blob &x : t->blobs[v])
			if (!std::isfinite(x.x) || !std::isfinite(x.y))
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "optical tracker: non-finite blob centroid");
	}
	return solve_blobs(t, true, time_s, out, q, err);
}
