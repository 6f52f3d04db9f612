// The layout's verifier light (docs/optical.md, "The verifier"): found where each pose puts
// it, its offset tested (verify()), the four points tested together and fitted
// (fit_with_verifier()), and two triples that fit the layout settled by it.
#include "tracker_internal.hpp"

#include <algorithm>
#include <cmath>

namespace rs_optical
{

// A verifier blob settles two triples that fit the layout when it lies within this (plus 6
// centroid sigmas) of where one's unrefined pose puts it (settle_by_verifier()).
constexpr double k_verifier_settle_px = 3.0;

// The blob of view v nearest to `at` (undistorted pixels) within `radius` px, other than
// the triple's own (`used`); -1 if none.
static int nearest_unused_blob(const rs_optical_tracker &t, int v, cv::Vec2d at, const int used[3],
                               double radius)
{
	int best = -1;
	double best_d = radius;
	for (int b = 0; b < (int)t.und[v].size(); ++b) {
		if (b == used[0] || b == used[1] || b == used[2])
			continue;
		double d = std::hypot(t.und[v][b].x - at[0], t.und[v][b].y - at[1]);
		if (d <= best_d) {
			best_d = d;
			best = b;
		}
	}
	return best;
}

// Where the pose of markers P puts the layout's verifier (camera-0 frame).
static bool verifier_at(const rs_pose_layout &layout, const cv::Vec3d P[3], cv::Vec3d *V)
{
	rs_pose T;
	if (!fit_layout(layout, P, 3, &T))
		return false;
	double v[3];
	rs_pose_transform_point(&T, layout.verifier, v);
	*V = cv::Vec3d(v[0], v[1], v[2]);
	return true;
}

// The verifier test (docs/optical.md, "The verifier"). Where the pose of the labelled
// markers puts the layout's fourth light, with the covariance of that prediction (each
// marker's triangulation covariance through the rigid fit, by central differences); in each
// view the blob the triple does not use nearest to its image, if within reach_m of it in
// space (the integrity bound: any pose that passed the other tests is at most that far
// off, so a verifier that is in view is found); over the views it is found in, its offset
// against the prediction's and its centroid's covariance, chi-square with 2 degrees of
// freedom a view. Not found in either view: unverified, not refused (a hand over it).
// Found in both views and passed: *out_V is it triangulated, *out_S its covariance.
rs_optical_verdict verify(const rs_optical_tracker &t, const cv::Vec3d pts[3],
                          const cv::Matx33d cov[3], const int used[2][3], rs_optical_quality &q,
                          cv::Vec3d *out_V, cv::Matx33d *out_S)
{
	cv::Vec3d V;
	if (!verifier_at(t.d.layout, pts, &V))
		return RS_OPTICAL_SIDE_RESIDUAL; // collinear: the side test cannot have passed
	// how far the verifier can be from where this pose puts it: the integrity bound turned
	// about the farthest marker, and moved
	double lever = 0;
	for (int k = 0; k < 3; ++k)
		lever = std::max(lever, cv::norm(V - pts[k]));
	const double reach_m = q.bound_rotation_rad * lever + q.bound_position_m;
	cv::Matx33d CV = cv::Matx33d::zeros(), Jm[3];
	const double h = 1e-6;
	for (int i = 0; i < 3; ++i) {
		cv::Matx33d &J = Jm[i];
		for (int k = 0; k < 3; ++k) {
			cv::Vec3d P[3] = {pts[0], pts[1], pts[2]}, Vp, Vm;
			P[i][k] += h;
			bool ok = verifier_at(t.d.layout, P, &Vp);
			P[i][k] -= 2 * h;
			if (!ok || !verifier_at(t.d.layout, P, &Vm))
				return RS_OPTICAL_SIDE_RESIDUAL;
			cv::Vec3d d = (Vp - Vm) / (2 * h);
			for (int r = 0; r < 3; ++r)
				J(r, k) = d[r];
		}
		CV += J * cov[i] * J.t();
	}
	const cv::Matx34d *M[2] = {&t.P0, &t.P1};
	const double s2 = t.d.centroid_sigma_px * t.d.centroid_sigma_px;
	// rows of the views the verifier is found in: offsets e, Jacobians G, centroid noise N
	cv::Mat_<double> e(0, 1), G(0, 3), N = cv::Mat_<double>::zeros(4, 4);
	int found[2] = {-1, -1};
	for (int v = 0; v < 2; ++v) {
		cv::Matx23d Jv;
		cv::Vec2d at;
		if (!project_jacobian(*M[v], V, cv::Point2d(0, 0), &Jv, &at))
			continue;
		// reach in pixels: the largest image of a reach_m move (the Jacobian's Frobenius
		// norm bounds its largest singular value) plus the prediction's own spread
		cv::Matx22d Cp = Jv * CV * Jv.t();
		double reach_px = cv::norm(Jv) * reach_m + 6.0 * std::sqrt(cv::trace(Cp)) +
		                  6.0 * t.d.centroid_sigma_px;
		int best = nearest_unused_blob(t, v, at, used[v], reach_px);
		cv::Matx22d Wi;
		if (best < 0 || !cv::invert(t.W[v][best], Wi, cv::DECOMP_CHOLESKY))
			continue;
		found[v] = best;
		int r0 = e.rows;
		e.push_back(t.und[v][best].x - at[0]);
		e.push_back(t.und[v][best].y - at[1]);
		G.push_back(cv::Mat_<double>(cv::Mat(Jv)));
		for (int r = 0; r < 2; ++r)
			for (int c = 0; c < 2; ++c)
				N(r0 + r, r0 + c) = s2 * Wi(r, c);
	}
	int n = e.rows / 2;
	q.verifier_views = (uint32_t)n;
	if (n == 0)
		return RS_OPTICAL_SOLVED;
	cv::Mat_<double> C =
	    G * cv::Mat_<double>(cv::Mat(CV)) * G.t() + N(cv::Rect(0, 0, 2 * n, 2 * n));
	cv::Mat_<double> x;
	if (!cv::solve(C, e, x, cv::DECOMP_CHOLESKY)) {
		q.verifier_chi2 = INFINITY;
		return RS_OPTICAL_VERIFIER;
	}
	q.verifier_chi2 = e.dot(x);
	double bound = n == 2 ? RS_OPTICAL_CHI2_4DOF : RS_OPTICAL_CHI2_2DOF;
	if (!(q.verifier_chi2 <= bound))
		return RS_OPTICAL_VERIFIER;
	// The fault three markers cannot see moves one marker along one camera's ray: for each
	// of those six directions u the offset it would make, g = -G J_i u per unit move, and
	// the offset's component along it, (g^T C^-1 e)^2 / g^T C^-1 g (1 degree of freedom), a
	// sharper test of that one fault than the total above.
	cv::Vec3d c1 = -(R_of(t.d.rig).t() * t_of(t.d.rig));
	for (int i = 0; i < 3; ++i)
		for (int v = 0; v < 2; ++v) {
			cv::Vec3d u = v == 0 ? pts[i] : pts[i] - c1;
			u /= cv::norm(u);
			cv::Mat_<double> g = -(G * cv::Mat_<double>(cv::Mat(Jm[i] * u))), y;
			if (!cv::solve(C, g, y, cv::DECOMP_CHOLESKY))
				continue;
			double info = g.dot(y), along = y.dot(e);
			if (info > 0 && !(along * along / info <= RS_OPTICAL_CHI2_1DOF)) {
				q.verifier_chi2 = std::max(q.verifier_chi2, along * along / info);
				return RS_OPTICAL_VERIFIER;
			}
		}
	if (n == 2) {
		const cv::Point2d obs[2] = {t.und[0][found[0]], t.und[1][found[1]]};
		const cv::Matx22d W[2] = {t.W[0][found[0]], t.W[1][found[1]]};
		*out_V = refine(t, triangulate(t, obs[0], obs[1]), obs, W);
		*out_S = point_cov(t, *out_V, W);
	}
	return RS_OPTICAL_SOLVED;
}

// The verifier seen in both views is a fourth point of the rigid body. Each point's fault
// along either camera's ray (a stray taken for it; the verifier's own included) is tested
// by Baarda's w-test against the residuals of the generalised least-squares fit to all
// four (RS_OPTICAL_VERIFIER when one fails): all six degrees of freedom of the four
// points, where verify() used the verifier's offset alone. The pose is then the closed-form
// fit to the four, the sample's markers become where it puts them (the solver's fit of
// them is then this pose), the stated errors and the bound's noise part its law. Not the
// weighted fit's pose: its law, half the closed form's, trusts the modelled centroid
// noise's shape, and on rendered frames the error did not shrink with it (docs/optical.md,
// "The verifier"). A fault the tests let through moves this pose less than the three
// markers' (it is one point of four), and the verifier's own lever steadies the rotation.
// The fault part of the integrity bound with four points: a fault of point i along u
// passes the w-test while |w + d per_m| <= k, d from (-k - w) / per_m to (k - w) / per_m;
// the pose T (the closed-form fit) moves most at an edge of that interval. False when a
// fault is untested (per_m 0) or a moved fit degenerate: then only the three markers' part
// holds.
static bool four_point_fault_part(const rs_pose_layout &layout, const cv::Vec3d P4[4],
                                  const rs_pose &T, const cv::Vec3d u[4][2], const double w[4][2],
                                  const double per_m[4][2], double k, double *out_rot,
                                  double *out_pos)
{
	double o[3];
	rs_pose_transform_point(&T, layout.T_markers_display.position, o);
	const cv::Vec3d o0(o[0], o[1], o[2]);
	double fr = 0, fp = 0;
	for (int i = 0; i < 4; ++i)
		for (int v = 0; v < 2; ++v)
			for (int sign = -1; sign <= 1; sign += 2) {
				if (!(per_m[i][v] > 0))
					return false;
				cv::Vec3d Q[4] = {P4[0], P4[1], P4[2], P4[3]};
				Q[i] += u[i][v] * ((sign * k - w[i][v]) / per_m[i][v]);
				rs_pose Te;
				if (!fit_layout(layout, Q, 4, &Te))
					return false;
				rs_pose_transform_point(&Te, layout.T_markers_display.position, o);
				fr = std::max(fr, rs_pose_angle_between(&Te, &T));
				fp = std::max(fp, cv::norm(cv::Vec3d(o[0], o[1], o[2]) - o0));
			}
	*out_rot = fr;
	*out_pos = fp;
	return true;
}

rs_optical_verdict fit_with_verifier(const rs_optical_tracker &t, const cv::Vec3d &V,
                                     const cv::Matx33d &S, double fault_rot, double fault_pos,
                                     cv::Vec3d pts[3], const cv::Matx33d cov[3],
                                     rs_optical_quality &q)
{
	const cv::Vec3d P4[4] = {pts[0], pts[1], pts[2], V};
	const cv::Matx33d S4[4] = {cov[0], cov[1], cov[2], S};
	WeightedFit G;
	rs_pose T;
	if (!fit_layout_weighted(t.d.layout, P4, S4, 4, &G) || !fit_layout(t.d.layout, P4, 4, &T))
		return RS_OPTICAL_SOLVED; // cannot happen for a triple that passed the side tests;
		                          // keep the three
	const cv::Vec3d c1 = -(R_of(t.d.rig).t() * t_of(t.d.rig));
	const double k = std::sqrt(RS_OPTICAL_CHI2_1DOF);
	cv::Vec3d u[4][2];
	double w[4][2], per_m[4][2];
	for (int i = 0; i < 4; ++i)
		for (int v = 0; v < 2; ++v) {
			u[i][v] = v == 0 ? P4[i] : P4[i] - c1;
			u[i][v] /= cv::norm(u[i][v]);
			w[i][v] = fault_w(G, i, u[i][v], &per_m[i][v]);
			if (!(std::fabs(w[i][v]) <= k)) {
				q.verifier_chi2 = std::max(q.verifier_chi2, w[i][v] * w[i][v]);
				return RS_OPTICAL_VERIFIER;
			}
		}
	// a stray must pass the three markers' tests too: the smaller of the two parts
	double fr, fp;
	if (four_point_fault_part(t.d.layout, P4, T, u, w, per_m, k, &fr, &fp)) {
		fault_rot = std::min(fault_rot, fr);
		fault_pos = std::min(fault_pos, fp);
	}
	double rot, pos;
	pose_error_law(t.d.layout, P4, S4, 4, &rot, &pos);
	if (!std::isfinite(rot) || !std::isfinite(pos))
		return RS_OPTICAL_SOLVED;
	for (int i = 0; i < 3; ++i) {
		double x[3];
		rs_pose_transform_point(&T, t.d.layout.markers[i], x);
		pts[i] = cv::Vec3d(x[0], x[1], x[2]);
	}
	state_errors(rot, pos, fault_rot, fault_pos, q);
	return RS_OPTICAL_SOLVED;
}

// Two triples fit the layout (a verifier light seen along a marker's epipolar line makes a
// second one): the one whose pose has a blob it does not use where it puts the verifier, in
// either view, if exactly one does (docs/optical.md, "The verifier"). It then stands alone
// in t.candidates and is the verifier test's to judge.
void settle_by_verifier(rs_optical_tracker &t, int best[3], int *order, double *worst)
{
	const double reach_px = k_verifier_settle_px + 6.0 * t.d.centroid_sigma_px;
	const cv::Matx34d *M[2] = {&t.P0, &t.P1};
	int seen = -1;
	for (size_t c = 0; c < t.candidate_triples.size(); ++c) {
		const cv::Vec4i &tr = t.candidate_triples[c];
		cv::Vec3d pts[3], V;
		int used[2][3];
		for (int k = 0; k < 3; ++k) {
			const Pair &p = t.pairs[tr[k]];
			pts[k_perms[tr[3]][k]] = p.X;
			used[0][k] = p.i;
			used[1][k] = p.j;
		}
		if (!verifier_at(t.d.layout, pts, &V))
			continue;
		bool found = false;
		for (int v = 0; v < 2 && !found; ++v) {
			cv::Matx23d J;
			cv::Vec2d at;
			if (!project_jacobian(*M[v], V, cv::Point2d(0, 0), &J, &at))
				continue;
			found = nearest_unused_blob(t, v, at, used[v], reach_px) >= 0;
		}
		if (!found)
			continue;
		if (seen >= 0)
			return; // two see it: still ambiguous
		seen = (int)c;
	}
	if (seen < 0)
		return;
	const cv::Vec4i &tr = t.candidate_triples[seen];
	best[0] = tr[0];
	best[1] = tr[1];
	best[2] = tr[2];
	cv::Vec3d X[3] = {t.pairs[tr[0]].X, t.pairs[tr[1]].X, t.pairs[tr[2]].X};
	double cost;
	*order = best_order(t.layout_sides, X, &cost, worst);
	t.candidates.assign(1, t.candidates[seen]);
}

} // namespace rs_optical
