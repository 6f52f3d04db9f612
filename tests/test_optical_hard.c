/* The optical path's hard cases (issue 19), frame sequences through the tracker and a
 * persistent pose solver: spots walking across each image edge of either camera, markers
 * at the image corners, a stray spot on a hidden marker's epipolar line, a reflection of
 * the whole display, masks, and clean frames. Asserted on each: every frame that is not
 * solved says why, and no pose reported good is beyond its integrity bound
 * (bound_rotation_rad / bound_position_m: what one undetected stray could cause, plus 5x
 * the noise). Asserted on each but the marker-like stray on a hidden marker's epipolar line
 * (which no test of one frame pair can refuse, docs/optical.md): no pose reported good is
 * more than 5 times its stated error (stated_rotation_rad / stated_position_m: the expected
 * error, the noise law with lens distortion) off. The worst ratios are printed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#ifdef RS_HAVE_OPTICAL
#include "test_optical_fixture.h"

#define W 640
#define H 480
/* Stated centroid noise: rendered spots at 2 grey levels of noise measure 0.015 px (and up
 * to 0.017 px of shape bias, test_optical.c). */
#define SIGMA_PX 0.02
#define MAX_RATIO 5.0

static uint8_t g_img[2][W * H];

/* One sequence: a tracker, a solver fed by it, and the tally. */
struct seq {
	struct rs_optical_tracker *tracker;
	struct rs_pose_solver *solver;
	struct rs_optical_rig rig;
	struct rs_pose_layout layout;
	int frames, good, unexplained;
	double worst;      /* largest error / stated error (the law) of a good pose */
	double t, dt;      /* frame time, interval (0: 60 Hz) */
	double tag, small; /* stray offset of this frame; worst ratio below 5 mm of it */
	double bound;      /* largest error / integrity bound of a good pose */
	int marker_like;   /* the stray spots are marker-sized: error/stated printed only... */
	int verified;      /* ...unless the layout has a verifier (asserted then) */
	int unverified;    /* good poses whose verifier was seen in neither view */
	int refused;       /* frames the verifier refused (RS_OPTICAL_VERIFIER) */
	int tracked;       /* good poses with a prior (prior_frames > 0) */
	double claim[2];   /* sums of bound / stated rotation errors, cold and tracked */
	/* sums over good poses: squared errors and squared stated errors */
	double se_rot, se_pos, st_rot, st_pos;
};

static void seq_open_layout(struct seq *s, double baseline, const struct rs_optical_mask *mask1,
                            int verified)
{
	memset(s, 0, sizeof *s);
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = SIGMA_PX};
	if (mask1)
		d.mask[1] = *mask1;
	make_rig(baseline, &d.rig);
	s->rig = d.rig;
	if (verified)
		rs_pose_layout_default_verified(&s->layout);
	else
		rs_pose_layout_default(&s->layout);
	s->verified = verified;
	d.layout = s->layout;
	assert_int_equal(rs_optical_tracker_create(&d, &s->tracker, NULL), RS_OK);
	/* The solver's own gates assume isotropic noise: told the largest per-axis marker
	 * noise (depth, ~0.2 mm at 0.05 px, 1 m and a 0.4 m baseline). */
	struct rs_pose_solver_desc sd = {.noise_sigma_m = 0.0003};
	assert_int_equal(rs_pose_solver_create(&sd, &s->layout, &s->solver, NULL), RS_OK);
}

static void seq_open_masked(struct seq *s, double baseline, const struct rs_optical_mask *mask1)
{
	seq_open_layout(s, baseline, mask1, 0);
}

static void seq_open(struct seq *s, double baseline)
{
	seq_open_masked(s, baseline, NULL);
}

static void seq_close(struct seq *s, const char *name)
{
	printf("# %-28s %3d frames, %3d good (%3d tracked), worst error/stated %.2f%s, "
	       "error/bound %.2f\n",
	       name, s->frames, s->good, s->tracked, s->worst,
	       s->marker_like && !s->verified ? " (printed, not asserted)" : "", s->bound);
	if (s->verified)
		printf("#   verifier: %d frames refused, %d good poses unverified\n", s->refused,
		       s->unverified);
	if (s->good)
		printf("#   mean bound/stated rotation: cold %.2f, tracked %.2f\n",
		       s->good > s->tracked ? s->claim[0] / (s->good - s->tracked) : 0.0,
		       s->tracked ? s->claim[1] / s->tracked : 0.0);
	assert_int_equal(s->unexplained, 0);
	if (!s->marker_like || s->verified)
		assert_true(s->worst <= MAX_RATIO);
	/* the marker-like stray passes every other test (the runs without the verifier): with
	 * it in view, it must be what refuses some of those frames (cold, it refuses all that
	 * the others let through, so no pose is left to compare) */
	if (s->marker_like && s->verified)
		assert_true(s->refused > 0);
	assert_true(s->bound <= 1.0);
	rs_optical_tracker_destroy(&s->tracker);
	rs_pose_solver_destroy(&s->solver);
}

/* One frame's sample through the solver; the tally. */
static void seq_account(struct seq *s, const struct rs_marker_sample *smp,
                        const struct rs_optical_quality *oq, const struct rs_pose *truth)
{
	struct rs_pose pose;
	struct rs_pose_quality pq;
	assert_int_equal(rs_pose_solver_update(s->solver, smp, &pose, &pq), RS_OK);
	s->frames++;
	if (pq.status == RS_POSE_OK || pq.status == RS_POSE_RELABELED) {
		assert_int_equal(oq->verdict, RS_OPTICAL_SOLVED);
		double a = rs_pose_angle_between(&pose, truth), e = pos_error(&pose, truth);
		s->se_rot += a * a;
		s->se_pos += e * e;
		s->st_rot += oq->stated_rotation_rad * oq->stated_rotation_rad;
		s->st_pos += oq->stated_position_m * oq->stated_position_m;
		/* the claim is the expected error: the noise law with distortion */
		assert_true(oq->stated_rotation_rad == oq->rotation_rms_rad &&
		            oq->stated_position_m == oq->position_rms_m);
		/* the integrity bound holds at least the noise part (5x the law) */
		assert_true(oq->bound_rotation_rad >= MAX_RATIO * oq->stated_rotation_rad &&
		            oq->bound_position_m >= MAX_RATIO * oq->stated_position_m);
		double r = a / oq->stated_rotation_rad, p = e / oq->stated_position_m;
		r = r > p ? r : p;
		s->tracked += oq->prior_frames > 0;
		/* how much of the fault bound the prior rules out: bound / stated, by prior */
		s->claim[oq->prior_frames > 0] += oq->bound_rotation_rad / oq->stated_rotation_rad;
		if (s->tag > 0 && s->tag < 0.005)
			s->small = r > s->small ? r : s->small;
		/* Every good pose is within its integrity bound: the worst one stray spot the
		 * side tests cannot see could do, plus its noise. */
		double fr = a / oq->bound_rotation_rad, fp = e / oq->bound_position_m;
		fr = fr > fp ? fr : fp;
		s->bound = fr > s->bound ? fr : s->bound;
		if (r > MAX_RATIO && getenv("HARD_DEBUG"))
			printf("#   t %.3f ratio %.1f (%.3f deg, stated %.3f) step %.1f side %.1f "
			       "marker %.1f reproj %.1f\n",
			       s->t, r, a * 57.3, oq->stated_rotation_rad * 57.3, oq->step_score,
			       oq->side_chi2, oq->marker_chi2, oq->reprojection_chi2);
		s->worst = r > s->worst ? r : s->worst;
		s->unverified += s->verified && oq->verifier_views == 0;
		if (!s->verified)
			assert_int_equal(oq->verifier_views, 0);
		s->good++;
		return;
	}
	s->refused += oq->verdict == RS_OPTICAL_VERIFIER;
	/* Not solved: the tracker's verdict or the solver's message says why. */
	if (oq->verdict == RS_OPTICAL_SOLVED && !rs_pose_solver_last_error(s->solver)[0])
		s->unexplained++;
}

static void add_spot(uint8_t *img, double cx, double cy, double sigma, double level)
{
	for (int y = (int)cy - 6; y <= (int)cy + 6; ++y)
		for (int x = (int)cx - 6; x <= (int)cx + 6; ++x) {
			if (x < 0 || y < 0 || x >= W || y >= H)
				continue;
			double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
			double v = img[y * W + x] + level * exp(-d2 / (2 * sigma * sigma));
			img[y * W + x] = (uint8_t)(v > 255 ? 255 : v);
		}
}

/* Render T, add `ghosts` spots (pixel positions per view, NAN: none), track and solve. */
static double g_ghost_sigma = 1.6, g_ghost_level = 150; /* a stray spot's shape */

static struct rs_optical_quality seq_frame(struct seq *s, const struct rs_pose *T,
                                           int occluded_marker, const double ghosts[][2][2],
                                           int n_ghosts, uint64_t seed)
{
	struct rs_optical_synth_desc sd = {
	    .noise_grey = 2, .occluded_marker = occluded_marker, .seed = seed};
	assert_int_equal(
	    rs_optical_synth_render(&s->rig, &s->layout, T, &sd, g_img[0], g_img[1], NULL), RS_OK);
	for (int g = 0; g < n_ghosts; ++g)
		for (int v = 0; v < 2; ++v)
			if (!isnan(ghosts[g][v][0]))
				add_spot(g_img[v], ghosts[g][v][0], ghosts[g][v][1], g_ghost_sigma,
				         g_ghost_level);
	struct rs_optical_image im[2] = {{g_img[0], W, H, W}, {g_img[1], W, H, W}};
	struct rs_marker_sample smp;
	struct rs_optical_quality oq;
	s->t += s->dt > 0 ? s->dt : 1.0 / 60;
	assert_int_equal(
	    rs_optical_tracker_process(s->tracker, &im[0], &im[1], s->t, &smp, &oq, NULL), RS_OK);
	struct rs_pose truth = *T;
	truth.time_s = s->t;
	seq_account(s, &smp, &oq, &truth);
	return oq;
}

/* The display turned by q (x y z w) with marker m at depth 1 m on camera v's ray through
 * pixel (u, w). */
static void place(const struct rs_optical_rig *rig, int v, int m, const double q[4], double u,
                  double w, struct rs_pose *T)
{
	const double *K = rig->cam[v].K;
	double Xv[3] = {(u - K[2]) / K[0], (w - K[5]) / K[4], 1.0}, X0[3];
	if (v) { /* x0 = R^T (x1 - t) */
		const double *R = rig->R_cam1_cam0, *t = rig->t_cam1_cam0;
		for (int i = 0; i < 3; ++i)
			X0[i] = R[i] * (Xv[0] - t[0]) + R[3 + i] * (Xv[1] - t[1]) +
			        R[6 + i] * (Xv[2] - t[2]);
	} else {
		memcpy(X0, Xv, sizeof X0);
	}
	memset(T, 0, sizeof *T);
	memcpy(T->orientation, q, 4 * sizeof(double));
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	double mr[3];
	rs_pose_transform_point(T, L.markers[m], mr); /* R m (position still 0) */
	for (int k = 0; k < 3; ++k)
		T->position[k] = X0[k] - mr[k];
}

/* A marker's spot walks from 4 px beyond each edge of either camera to 8 px inside it. */
static void test_spots_walk_across_each_edge(void **state)
{
	(void)state;
	static const double id[4] = {0, 0, 0, 1};
	/* edge: marker that lies outermost there (identity orientation: 0 left and top, 1
	 * right, 2 bottom) */
	static const char *names[4] = {"left", "right", "top", "bottom"};
	static const int marker[4] = {0, 1, 0, 2};
	for (int v = 0; v < 2; ++v)
		for (int e = 0; e < 4; ++e) {
			struct seq s;
			seq_open(&s, 0.4);
			char name[64];
			snprintf(name, sizeof name, "edge %s, camera %d", names[e], v);
			int edge_blobs = 0, other_sees = 0;
			for (double off = -4; off <= 8; off += 0.5) {
				double u = W / 2.0 - 40, w = H / 2.0 - 30;
				if (e == 0)
					u = off;
				else if (e == 1)
					u = W - 1 - off;
				else if (e == 2)
					w = off;
				else
					w = H - 1 - off;
				struct rs_pose T;
				place(&s.rig, v, marker[e], id, u, w, &T);
				struct rs_optical_quality oq =
				    seq_frame(&s, &T, 0, NULL, 0, (uint64_t)(off * 4 + 100));
				edge_blobs += oq.blobs_at_edge[v] > 0;
				/* the other camera: does it see all three markers 4 px inside? */
				int inside = 1;
				for (int i = 0; i < 3; ++i) {
					double X[3], x, y;
					rs_pose_transform_point(&T, s.layout.markers[i], X);
					project_point(&s.rig, !v, X, &x, &y);
					inside &= x >= 4 && y >= 4 && x <= W - 5 && y <= H - 5;
				}
				other_sees += inside;
			}
			/* the frames with the spot cut by the edge say so */
			assert_true(edge_blobs >= 8);
			/* Camera 1 is 0.4 m to the side and toed in: ~8 % farther from the display,
			 * its field there is wider than camera 0's, and a marker at its left, top
			 * or bottom edge is outside camera 0's image (24-37 px beyond it at 1 m;
			 * docs/optical.md): no partner to match, TOO_FEW_MATCHES. Such a run solves
			 * nothing, honestly. */
			printf("# %s: the other camera sees all markers in %d of 25 frames\n", name,
			       other_sees);
			if (!other_sees)
				assert_int_equal(s.good, 0);
			seq_close(&s, name);
		}
}

/* A marker at each corner of camera 0, from 3 px outside to 8 px inside both edges. */
static void test_markers_at_the_corners(void **state)
{
	(void)state;
	static const double id[4] = {0, 0, 0, 1}, half[4] = {0, 0, 1, 0}; /* 180 deg about z */
	struct {
		const double *q;
		int m, right, bottom;
	} c[4] = {{id, 0, 0, 0}, {id, 1, 1, 0}, {half, 1, 0, 1}, {half, 0, 1, 1}};
	struct seq s;
	seq_open(&s, 0.4);
	for (int k = 0; k < 4; ++k)
		for (double off = -3; off <= 8; off += 0.5) {
			double u = c[k].right ? W - 1 - off : off;
			double w = c[k].bottom ? H - 1 - off : off;
			struct rs_pose T;
			place(&s.rig, 0, c[k].m, c[k].q, u, w, &T);
			seq_frame(&s, &T, 0, NULL, 0, (uint64_t)(k * 100 + off * 2 + 50));
		}
	seq_close(&s, "corners, camera 0");
}

/* Camera 0 sees marker k; camera 1 does not, but sees a stray spot on its epipolar line:
 * what camera 1 would see of a point d along camera 0's ray through the marker. Tracked:
 * after five clean frames the spot slides out from 1 to 45 mm (0.4 s), on one side of the
 * marker, then the other. Cold: each frame on its own (a second apart). The worst ratio
 * below 5 mm (where the side lengths cannot see the stray) is printed apart; the bound of
 * 5x holds at every offset. */
static void stray_sequence(struct seq *s, const struct rs_pose *T, int k, int tracked)
{
	double X[3], u, w;
	rs_pose_transform_point(T, s->layout.markers[k], X);
	double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
	s->dt = tracked ? 0.0 : 1.0;
	for (int sign = -1; sign <= 1; sign += 2) {
		for (int f = 0; f < 5 * tracked; ++f)
			seq_frame(s, T, 0, NULL, 0, (uint64_t)f);
		for (double d = 0.001; d <= 0.0451; d += 0.002) {
			double G[3];
			for (int c = 0; c < 3; ++c)
				G[c] = X[c] * (1 + sign * d / n);
			project_point(&s->rig, 1, G, &u, &w);
			double ghost[1][2][2] = {{{NAN, NAN}, {u, w}}};
			s->tag = d;
			seq_frame(s, T, k + 1, ghost, 1, (uint64_t)(d * 1e4 + sign + 7));
			s->tag = 0;
		}
	}
}

static void stray_runs(int marker_like, int verified)
{
	struct rng r = {.s = 1919};
	for (int tracked = 1; tracked >= 0; --tracked) {
		struct seq s;
		seq_open_layout(&s, 0.4, NULL, verified);
		s.marker_like = marker_like;
		/* marker-like: about a marker's spot (3.2 px disc at 230 grey) */
		g_ghost_sigma = marker_like ? 2.4 : 1.6;
		g_ghost_level = marker_like ? 240 : 150;
		for (int trial = 0; trial < 3; ++trial) { /* each marker hidden once */
			struct rs_pose T;
			facing_pose(&r, &T);
			s.t += 1.0; /* a new scene: no history */
			stray_sequence(&s, &T, trial % 3, tracked);
		}
		/* Within 5 mm the side lengths cannot tell the stray from the marker moved along
		 * camera 0's ray (docs/optical.md): a smaller or larger spot is refused by its
		 * size; a marker-like one passes: its poses are within their integrity bound
		 * (asserted) but up to 5.43x tracked, 30.9x cold their stated error (printed). */
		printf("# %sstray within 5 mm of the hidden marker: worst error/stated %.2f\n",
		       marker_like ? "marker-like " : "", s.small);
		char name[64];
		snprintf(name, sizeof name, "%s, %s%s",
		         marker_like ? "marker-like stray" : "stray on epipolar",
		         tracked ? "tracked" : "cold", verified ? ", verifier" : "");
		seq_close(&s, name);
	}
	g_ghost_sigma = 1.6;
	g_ghost_level = 150;
}

static void test_stray_spot_on_hidden_markers_epipolar_line(void **state)
{
	(void)state;
	stray_runs(0, 0);
}

/* A stray spot as large and bright as a marker's: no test of one frame pair can refuse it
 * where the ray runs along the display's normal; every good pose, tracked or cold, is
 * within its integrity bound at every offset (its error against the stated one printed). */
static void test_marker_like_stray_within_its_integrity_bound(void **state)
{
	(void)state;
	stray_runs(1, 0);
}

/* The same with the layout's verifier light in view (docs/optical.md, "The verifier"): the
 * stray is refused where it moves the pose, and no pose reported good is more than 5 times
 * its stated error off, tracked or cold. */
static void test_marker_like_stray_refused_by_the_verifier(void **state)
{
	(void)state;
	stray_runs(1, 1);
}

/* The pose of a sample's three markers (id order) fitted to layout L. */
static void fit_sample(const struct rs_pose_layout *L, const struct rs_marker_sample *smp,
                       struct rs_pose *P)
{
	double model[3][3], meas[3][3];
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k) {
			model[i][k] = L->markers[i][k];
			meas[i][k] = smp->markers[i].position[k];
		}
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])meas, 3, P, NULL, NULL),
	    RS_OK);
}

/* The mirror depth: marker 2 hidden from camera 1 and a stray there where camera 1 would see
 * marker 2 moved along camera 0's ray to the depth at which the triangle, tilted the other
 * way, is congruent again (the display turned 10 degrees about the side 0-1, which is
 * perpendicular to that ray: both sides meeting at marker 2 return to their lengths at the
 * same depth). The side tests pass it exactly and the pose is 20 degrees off; the integrity
 * bound must reach it (the fault bound's far region along the ray). Exact projections
 * through rs_optical_tracker_process_blobs, cold. */
static void test_stray_at_the_mirror_depth_within_its_integrity_bound(void **state)
{
	(void)state;
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = SIGMA_PX};
	make_rig(0.4, &d.rig);
	struct rs_optical_tracker *t = NULL;
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_OK);
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	int good = 0;
	for (int k = 0; k < 4; ++k) {
		double th = (8.0 + 2.0 * k) * RS_PI / 180; /* 8..14 degrees */
		struct rs_pose T = {.orientation = {sin(th / 2), 0, 0, cos(th / 2)}};
		double m2[3];
		rs_pose_transform_point(&T, L.markers[2], m2); /* R m2, position still 0 */
		for (int c = 0; c < 3; ++c)                    /* marker 2 on camera 0's axis */
			T.position[c] = (c == 2 ? 1.0 : 0.0) - m2[c];
		double X[3][3];
		for (int i = 0; i < 3; ++i)
			rs_pose_transform_point(&T, L.markers[i], X[i]);
		/* u = (0, 0, 1): the second root of |X2 + d u - X0| = |X2 - X0| */
		double dm = -2 * (X[2][2] - X[0][2]), G[3] = {X[2][0], X[2][1], X[2][2] + dm};
		struct rs_optical_blob b[2][3] = {{{0}}};
		for (int i = 0; i < 3; ++i) {
			project_point(&d.rig, 0, X[i], &b[0][i].x, &b[0][i].y);
			project_point(&d.rig, 1, i == 2 ? G : X[i], &b[1][i].x, &b[1][i].y);
		}
		struct rs_marker_sample smp;
		struct rs_optical_quality oq;
		assert_int_equal(rs_optical_tracker_process_blobs(t, b[0], 3, b[1], 3, 10.0 * k,
		                                                  &smp, &oq, NULL),
		                 RS_OK);
		if (oq.verdict != RS_OPTICAL_SOLVED)
			continue;
		struct rs_pose P;
		fit_sample(&L, &smp, &P);
		double a = rs_pose_angle_between(&P, &T);
		printf(
		    "# mirror depth at %.0f degrees: %.1f mm along the ray, pose %.1f degrees off, "
		    "bound %.1f, stated %.3f (error/stated %.0f, printed)\n",
		    th * 180 / RS_PI, dm * 1e3, a * 180 / RS_PI,
		    oq.bound_rotation_rad * 180 / RS_PI, oq.stated_rotation_rad * 180 / RS_PI,
		    a / oq.stated_rotation_rad);
		assert_true(a <= oq.bound_rotation_rad);
		good++;
	}
	assert_true(good >= 3); /* the case is there: the side tests pass it */
	rs_optical_tracker_destroy(&t);
}

/* A marker-like light where the room always shows one (a lamp), on camera 1's epipolar line
 * of a marker hidden there, 2 mm out along camera 0's ray: unmasked, the side lengths
 * cannot refuse it (up to 30x the stated error, test_marker_like_stray_within_its_integrity_bound);
 * with a mask rectangle over it the blob is not used and counted, and no pose is wrong. A
 * rectangle that only reaches into a marker's 3 px centroid margin refuses that marker. */
static void test_camera_mask_refuses_a_static_light(void **state)
{
	(void)state;
	struct rng r = {.s = 1919};
	g_ghost_sigma = 2.4;
	g_ghost_level = 240;
	int masked_frames = 0, frames = 0, unmasked_bad = 0;
	for (int trial = 0; trial < 6; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		int k = trial % 3;
		double X[3], G[3], u, w;
		struct seq probe;
		seq_open(&probe, 0.4);
		rs_pose_transform_point(&T, probe.layout.markers[k], X);
		double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
		for (int c = 0; c < 3; ++c)
			G[c] = X[c] * (1 + 0.002 / n);
		project_point(&probe.rig, 1, G, &u, &w);
		double ghost[1][2][2] = {{{NAN, NAN}, {u, w}}};
		/* unmasked: the pose the mask is for, far beyond its noise law (printed) */
		probe.dt = 1.0;
		seq_frame(&probe, &T, k + 1, ghost, 1, (uint64_t)trial);
		unmasked_bad += probe.worst > MAX_RATIO;
		rs_optical_tracker_destroy(&probe.tracker);
		rs_pose_solver_destroy(&probe.solver);
		struct rs_optical_mask m = {.count = 1};
		m.rects[0] = (struct rs_optical_rect){(int)u - 6, (int)w - 6, 13, 13};
		struct seq s;
		seq_open_masked(&s, 0.4, &m);
		s.dt = 1.0;
		struct rs_optical_quality oq = seq_frame(&s, &T, k + 1, ghost, 1, (uint64_t)trial);
		masked_frames += oq.blobs_masked[1] == 1;
		frames++;
		seq_close(&s, "masked static light");
		/* a rectangle 1-2 px beyond a clean marker's spot (radius ~3.2 px): inside its
		 * centroid window */
		project_point(&s.rig, 1, X, &u, &w);
		m.rects[0] = (struct rs_optical_rect){(int)u + 5, (int)w - 2, 4, 4};
		seq_open_masked(&s, 0.4, &m);
		s.dt = 1.0;
		oq = seq_frame(&s, &T, 0, NULL, 0, (uint64_t)trial);
		assert_int_equal(oq.blobs_masked[1], 1);
		assert_int_not_equal(oq.verdict, RS_OPTICAL_SOLVED);
		seq_close(&s, "mask next to a marker");
	}
	printf("# unmasked: %d of 6 frames a good pose beyond %.0fx its noise law\n", unmasked_bad,
	       MAX_RATIO);
	assert_int_equal(masked_frames, frames);
	g_ghost_sigma = 1.6;
	g_ghost_level = 150;
}

/* The same static light masked by a mask image (a nonzero disc of 7 px radius around it in
 * camera 1's image) instead of a rectangle: the blob is not used and counted, no pose is
 * wrong; an all-zero image masks nothing (the clean frame solves). */
static void test_camera_mask_image_refuses_a_static_light(void **state)
{
	(void)state;
	static uint8_t mask_img[W * H];
	struct rng r = {.s = 1919};
	g_ghost_sigma = 2.4;
	g_ghost_level = 240;
	for (int trial = 0; trial < 3; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		int k = trial % 3;
		struct rs_optical_rig rig;
		make_rig(0.4, &rig);
		struct rs_pose_layout L;
		rs_pose_layout_default(&L);
		double X[3], G[3], u, w;
		rs_pose_transform_point(&T, L.markers[k], X);
		double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
		for (int c = 0; c < 3; ++c)
			G[c] = X[c] * (1 + 0.002 / n);
		project_point(&rig, 1, G, &u, &w);
		double ghost[1][2][2] = {{{NAN, NAN}, {u, w}}};
		memset(mask_img, 0, sizeof mask_img);
		struct rs_optical_mask m = {
		    .pixels = mask_img, .width = W, .height = H, .stride = W};
		/* all zero: nothing masked */
		struct seq s;
		seq_open_masked(&s, 0.4, &m);
		s.dt = 1.0;
		struct rs_optical_quality oq = seq_frame(&s, &T, 0, NULL, 0, (uint64_t)trial);
		assert_int_equal(oq.blobs_masked[1], 0);
		assert_int_equal(oq.verdict, RS_OPTICAL_SOLVED);
		seq_close(&s, "zero mask image");
		for (int y = 0; y < H; ++y)
			for (int x = 0; x < W; ++x)
				mask_img[y * W + x] = hypot(x - u, y - w) <= 7 ? 255 : 0;
		seq_open_masked(&s, 0.4, &m);
		memset(mask_img, 0, sizeof mask_img); /* the tracker copied it */
		s.dt = 1.0;
		oq = seq_frame(&s, &T, k + 1, ghost, 1, (uint64_t)trial);
		assert_int_equal(oq.blobs_masked[1], 1);
		assert_int_not_equal(oq.verdict, RS_OPTICAL_SOLVED);
		seq_close(&s, "mask image over a light");
	}
	g_ghost_sigma = 1.6;
	g_ghost_level = 150;
}

/* The integrity bound: cold, the whole fault bound plus 5x the stated error; tracked (the
 * same exact frame again 1/60 s later, so the prior predicts it), at most that (the step
 * gate only removes faults), and never below 5x the stated error. Exact projections through
 * rs_optical_tracker_process_blobs. */
static void test_tracked_bound_at_most_the_cold_one(void **state)
{
	(void)state;
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = SIGMA_PX};
	make_rig(0.4, &d.rig);
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rng r = {.s = 77};
	int tighter = 0;
	for (int trial = 0; trial < 20; ++trial) {
		struct rs_optical_tracker *t = NULL;
		assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_OK);
		struct rs_pose T;
		facing_pose(&r, &T);
		struct rs_optical_blob b[2][3] = {{{0}}};
		for (int i = 0; i < 3; ++i) {
			double X[3];
			rs_pose_transform_point(&T, L.markers[i], X);
			for (int v = 0; v < 2; ++v)
				project_point(&d.rig, v, X, &b[v][i].x, &b[v][i].y);
		}
		struct rs_marker_sample smp;
		struct rs_optical_quality q[3];
		for (int f = 0; f < 3; ++f)
			assert_int_equal(rs_optical_tracker_process_blobs(
			                     t, b[0], 3, b[1], 3, f / 60.0, &smp, &q[f], NULL),
			                 RS_OK);
		assert_int_equal(q[0].verdict, RS_OPTICAL_SOLVED);
		assert_int_equal(q[0].prior_frames, 0);
		assert_true(q[0].bound_rotation_rad > MAX_RATIO * q[0].stated_rotation_rad &&
		            q[0].bound_position_m > MAX_RATIO * q[0].stated_position_m);
		for (int f = 1; f < 3; ++f) {
			assert_int_equal(q[f].verdict, RS_OPTICAL_SOLVED);
			/* the second pose of a row has no prior: no velocity yet */
			assert_int_equal(q[f].prior_frames, f == 1 ? 0u : 2u);
			assert_true(q[f].bound_rotation_rad <=
			                q[0].bound_rotation_rad * (1 + 1e-9) &&
			            q[f].bound_position_m <= q[0].bound_position_m * (1 + 1e-9));
			assert_true(q[f].bound_rotation_rad >=
			                MAX_RATIO * q[f].stated_rotation_rad &&
			            q[f].bound_position_m >= MAX_RATIO * q[f].stated_position_m);
		}
		tighter += q[2].bound_rotation_rad < 0.999 * q[0].bound_rotation_rad;
		rs_optical_tracker_destroy(&t);
	}
	printf("# tracked integrity bound tighter than the cold one in %d of 20 poses\n", tighter);
}

/* A bad mask is refused at creation. */
static void test_bad_mask_refused(void **state)
{
	(void)state;
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = SIGMA_PX};
	make_rig(0.4, &d.rig);
	struct rs_optical_tracker *t = NULL;
	d.mask[0].count = 1; /* an empty rectangle */
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_ERR_INVALID);
	d.mask[0].count = RS_OPTICAL_MAX_MASK_RECTS + 1;
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_ERR_INVALID);
	/* a mask image of another size than the camera's, or a stride below its width */
	static uint8_t px[W * H];
	d.mask[0].count = 0;
	d.mask[1] =
	    (struct rs_optical_mask){.pixels = px, .width = W / 2, .height = H, .stride = W};
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_ERR_INVALID);
	d.mask[1] =
	    (struct rs_optical_mask){.pixels = px, .width = W, .height = H, .stride = W - 1};
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_ERR_INVALID);
	assert_null(t);
}

/* The display mirrored in a glossy table 10 cm below camera 0 (y down): a dimmer copy of
 * all three markers, congruent, so its triple fits the layout as well as the display's.
 * From the first frame (no history: ambiguous) and after five clean frames (the last
 * triple settles it). */
static void test_reflection_of_the_display(void **state)
{
	(void)state;
	struct rng r = {.s = 2525};
	struct seq s;
	seq_open(&s, 0.4);
	int settled = 0;
	for (int trial = 0; trial < 6; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		s.t += 1.0;
		for (int f = 0; f < 12; ++f) {
			int with_ghosts = trial % 2 ? f >= 5 : 1;
			double ghost[3][2][2];
			for (int i = 0; i < 3; ++i) {
				double X[3];
				rs_pose_transform_point(&T, s.layout.markers[i], X);
				X[1] = 2 * 0.1 - X[1];
				for (int v = 0; v < 2; ++v)
					project_point(&s.rig, v, X, &ghost[i][v][0],
					              &ghost[i][v][1]);
			}
			int before = s.good;
			seq_frame(&s, &T, 0, (const double(*)[2][2])ghost, with_ghosts ? 3 : 0,
			          (uint64_t)(trial * 20 + f));
			settled += with_ghosts && s.good > before;
		}
	}
	seq_close(&s, "reflection of the display");
	assert_true(settled >= 15); /* the tracked half: 3 x 7 frames with the reflection */
}

/* Clean rendered frames (2 grey levels of noise), independent poses: >= 99 % solved, RMS
 * errors within 1.2 x the law at the measured centroid noise. */
static void test_clean_frames_at_the_law(void **state)
{
	(void)state;
	struct rng r = {.s = 99};
	struct seq s;
	seq_open(&s, 0.4);
	s.dt = 1.0; /* independent frames */
	double ce = 0;
	int n_c = 0, trials = 200;
	for (int trial = 0; trial < trials; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		seq_frame(&s, &T, 0, NULL, 0, (uint64_t)trial);
		/* centroid error against the true projections */
		for (int v = 0; v < 2; ++v) {
			struct rs_optical_image im = {g_img[v], W, H, W};
			struct rs_optical_blob b[8];
			size_t n = 0;
			assert_int_equal(rs_optical_detect(NULL, &im, b, 8, &n, NULL), RS_OK);
			for (int i = 0; i < 3; ++i) {
				double X[3], u, w, best = INFINITY;
				rs_pose_transform_point(&T, s.layout.markers[i], X);
				project_point(&s.rig, v, X, &u, &w);
				for (size_t j = 0; j < n; ++j) {
					double e = hypot(b[j].x - u, b[j].y - w);
					best = e < best ? e : best;
				}
				ce += best * best;
				n_c += 2;
			}
		}
	}
	/* The law is linear in the centroid noise: the stated errors (for SIGMA_PX) scaled to
	 * the measured noise. */
	double k = sqrt(ce / n_c) / SIGMA_PX;
	double rot = sqrt(s.se_rot / s.good), rot_law = k * sqrt(s.st_rot / s.good);
	double pos = sqrt(s.se_pos / s.good), pos_law = k * sqrt(s.st_pos / s.good);
	printf("# clean: %d/%d solved, centroid noise %.4f px; rotation RMS %.4f deg = %.2f x "
	       "law, position RMS %.4f mm = %.2f x law\n",
	       s.good, trials, k * SIGMA_PX, rot * 180 / RS_PI, rot / rot_law, pos * 1e3,
	       pos / pos_law);
	assert_true(s.good >= 0.99 * trials);
	assert_true(rot <= 1.2 * rot_law && pos <= 1.2 * pos_law);
	seq_close(&s, "clean frames");
}

/* OpenCV's 5-term lens model applied to camera v's pinhole projection of X. */
static void project_distorted(const struct rs_optical_rig *rig, int v, const double X[3], double *u,
                              double *w)
{
	const double *K = rig->cam[v].K, *d = rig->cam[v].dist;
	project_point(rig, v, X, u, w);
	double x = (*u - K[2]) / K[0], y = (*w - K[5]) / K[4], r2 = x * x + y * y;
	double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
	double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
	double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
	*u = xd * K[0] + K[2];
	*w = yd * K[4] + K[5];
}

/* A strongly distorted lens (barrel, k1 = -0.5, and tangential terms), the display off
 * centre where the distortion compresses the image most: the stated errors carry the
 * lens's Jacobian, so their RMS matches the measured one within 5 % (~2 % sampling
 * error; without the Jacobian they understate it by about 9 %). 1500 trials, centroid
 * noise 0.1 px. */
static void test_stated_error_includes_distortion(void **state)
{
	(void)state;
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = 0.1};
	make_rig(0.4, &d.rig);
	const double dist[5] = {-0.5, 0.2, 0.002, -0.002, 0};
	for (int v = 0; v < 2; ++v)
		memcpy(d.rig.cam[v].dist, dist, sizeof dist);
	struct rs_optical_tracker *t = NULL;
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_OK);
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rng r = {.s = 4242};
	double se_r = 0, se_p = 0, st_r = 0, st_p = 0;
	int n = 0;
	for (int trial = 0; trial < 1500; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		T.position[0] -= 0.22; /* towards camera 0's left edge, both views off centre */
		T.position[1] -= 0.17;
		struct rs_optical_blob b[2][3] = {{{0}}};
		for (int i = 0; i < 3; ++i) {
			double X[3];
			rs_pose_transform_point(&T, L.markers[i], X);
			for (int v = 0; v < 2; ++v) {
				project_distorted(&d.rig, v, X, &b[v][i].x, &b[v][i].y);
				b[v][i].x += 0.1 * gauss(&r);
				b[v][i].y += 0.1 * gauss(&r);
			}
		}
		struct rs_marker_sample smp;
		struct rs_optical_quality oq;
		assert_int_equal(
		    rs_optical_tracker_process_blobs(t, b[0], 3, b[1], 3, trial, &smp, &oq, NULL),
		    RS_OK);
		if (oq.markers != 3)
			continue;
		struct rs_pose P;
		fit_sample(&L, &smp, &P);
		double a = rs_pose_angle_between(&P, &T), e = pos_error(&P, &T);
		se_r += a * a;
		se_p += e * e;
		st_r += oq.rotation_rms_rad * oq.rotation_rms_rad;
		st_p += oq.position_rms_m * oq.position_rms_m;
		++n;
	}
	double kr = sqrt(se_r / st_r), kp = sqrt(se_p / st_p);
	printf("# distorted lens, off centre: %d/1500 solved; measured / law RMS: rotation "
	       "%.3f, position %.3f\n",
	       n, kr, kp);
	assert_true(n >= 1470); /* a few refused: markers within 4 px of the edge */
	assert_true(fabs(kr - 1) < 0.05 && fabs(kp - 1) < 0.05);
	rs_optical_tracker_destroy(&t);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_spots_walk_across_each_edge),
	    cmocka_unit_test(test_markers_at_the_corners),
	    cmocka_unit_test(test_stray_spot_on_hidden_markers_epipolar_line),
	    cmocka_unit_test(test_marker_like_stray_within_its_integrity_bound),
	    cmocka_unit_test(test_marker_like_stray_refused_by_the_verifier),
	    cmocka_unit_test(test_stray_at_the_mirror_depth_within_its_integrity_bound),
	    cmocka_unit_test(test_tracked_bound_at_most_the_cold_one),
	    cmocka_unit_test(test_camera_mask_refuses_a_static_light),
	    cmocka_unit_test(test_camera_mask_image_refuses_a_static_light),
	    cmocka_unit_test(test_bad_mask_refused),
	    cmocka_unit_test(test_reflection_of_the_display),
	    cmocka_unit_test(test_clean_frames_at_the_law),
	    cmocka_unit_test(test_stated_error_includes_distortion),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* opencv backend not built: nothing to test (as test_optical.c) */
}
#endif
