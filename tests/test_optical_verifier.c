/* The layout's verifier light (issue 19; docs/optical.md, "The verifier"): a fourth light
 * that is not part of the pose's triangle, checked where each pose puts it. Three markers
 * and two cameras cannot refuse a marker-like stray spot on a hidden marker's epipolar
 * line (test_optical_hard.c: up to 30x the stated error, cold); with the verifier in view
 * such poses are refused where they are far off (no pose reported good more than 5x its
 * stated error off over nine sets of poses, against 40-93x without it), and on clean data
 * it refuses at most 0.1 % of the samples. Also its layout file, its checks, and a verifier
 * hidden in one view or both. Blob centroids are exact projections plus Gaussian noise at
 * the stated sigma (rs_optical_tracker_process_blobs). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include <cmocka.h>

#ifdef RS_HAVE_OPTICAL
#include "test_optical_fixture.h"

#define SIGMA_PX 0.05
#define MAX_RATIO 5.0

static struct rs_optical_tracker *make_tracker(const struct rs_pose_layout *L, double sigma_px)
{
	struct rs_optical_tracker_desc d = {.centroid_sigma_px = sigma_px, .layout = *L};
	make_rig(0.4, &d.rig);
	struct rs_optical_tracker *t = NULL;
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_OK);
	return t;
}

/* Blob i of view v: the projection of X plus noise. */
static void blob_at(const double X[3], int v, double sigma_px, struct rng *r,
                    struct rs_optical_blob *b)
{
	struct rs_optical_rig rig;
	make_rig(0.4, &rig);
	memset(b, 0, sizeof *b);
	project_point(&rig, v, X, &b->x, &b->y);
	b->x += sigma_px * gauss(r);
	b->y += sigma_px * gauss(r);
}

/* The pose of the sample's markers (layout id order): its rotation (rad) and position (m)
 * errors against the truth. */
static void pose_errors(const struct rs_pose_layout *L, const struct rs_marker_sample *smp,
                        const struct rs_pose *truth, double *rot, double *pos)
{
	double model[3][3], meas[3][3];
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k) {
			model[i][k] = L->markers[i][k];
			meas[i][k] = smp->markers[i].position[k];
		}
	struct rs_pose P;
	assert_int_equal(
	    rs_pose_fit((const double(*)[3])model, (const double(*)[3])meas, 3, &P, NULL, NULL),
	    RS_OK);
	*rot = rs_pose_angle_between(&P, truth);
	*pos = pos_error(&P, truth);
}

/* What the integrity bound was worth over the poses error_ratio saw: the worst error over
 * the bound, and the bound over the stated error (position; their sums for the mean). */
static struct {
	double worst_of_bound, bound_over_stated;
	int n;
} g_bound;

/* The same in stated errors, the larger of rotation and position; and asserted within the
 * integrity bound. */
static double error_ratio(const struct rs_pose_layout *L, const struct rs_marker_sample *smp,
                          const struct rs_optical_quality *oq, const struct rs_pose *truth)
{
	double rot, pos;
	pose_errors(L, smp, truth, &rot, &pos);
	assert_true(rot <= oq->bound_rotation_rad && pos <= oq->bound_position_m);
	double b = fmax(rot / oq->bound_rotation_rad, pos / oq->bound_position_m);
	g_bound.worst_of_bound = fmax(g_bound.worst_of_bound, b);
	g_bound.bound_over_stated += oq->bound_position_m / oq->stated_position_m;
	g_bound.n++;
	double a = rot / oq->stated_rotation_rad, e = pos / oq->stated_position_m;
	if (getenv("VERIFIER_DEBUG") && (a > MAX_RATIO || e > MAX_RATIO))
		printf("#   rotation %.2fx, position %.2fx\n", a, e);
	return a > e ? a : e;
}

/* The layout file's "verifier", and the checks that keep it from being a marker. */
static void test_verifier_layout_file_and_checks(void **state)
{
	(void)state;
	char path[] = "/tmp/rs_verifier_XXXXXX";
	int fd = mkstemp(path);
	assert_true(fd >= 0);
	close(fd);
	struct rs_pose_layout L, D;
	struct rs_error err = {0};
	write_text(path, "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]],"
	                 " \"verifier\": [0.04, 0.03, 0.12]}");
	assert_int_equal(rs_pose_layout_load(path, &L, &err), RS_OK);
	rs_pose_layout_default_verified(&D);
	assert_true(L.has_verifier == 1 && L.verifier[2] == D.verifier[2]);
	assert_int_equal(rs_pose_layout_check(&D, &err), RS_OK);
	/* without one: none */
	write_text(path, "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]]}");
	assert_int_equal(rs_pose_layout_load(path, &L, &err), RS_OK);
	assert_int_equal(L.has_verifier, 0);
	/* malformed */
	write_text(path, "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]], \"verifier\": [1, 2]}");
	assert_int_equal(rs_pose_layout_load(path, &L, &err), RS_ERR_PARSE);
	assert_non_null(strstr(err.message, "verifier"));
	/* on the line of markers 0 and 1 (a turn about that side would not move it) */
	write_text(path, "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]],"
	                 " \"verifier\": [0.05, 0.005, 0.0]}");
	assert_int_equal(rs_pose_layout_load(path, &L, &err), RS_ERR_DEGENERATE);
	assert_non_null(strstr(err.message, "line"));
	/* making a triangle congruent to the layout's with markers 0 and 1: the mirror image
	 * of marker 2 across their side */
	write_text(path, "{\"markers\": [[0,0,0],[0.1,0,0],[0.02,0.08,0]],"
	                 " \"verifier\": [0.02, -0.08, 0.0]}");
	assert_int_equal(rs_pose_layout_load(path, &L, &err), RS_ERR_DEGENERATE);
	assert_non_null(strstr(err.message, "taken for a marker"));
	remove(path);
	D.verifier[0] = NAN;
	assert_int_equal(rs_pose_layout_check(&D, &err), RS_ERR_BAD_DATA);
	/* a triple tolerance that reaches the verifier's triangles is refused by the tracker */
	rs_pose_layout_default_verified(&D);
	struct rs_optical_tracker_desc d = {.layout = D, .side_tolerance_m = 0.05};
	make_rig(0.4, &d.rig);
	struct rs_optical_tracker *t = NULL;
	assert_int_equal(rs_optical_tracker_create(&d, &t, &err), RS_ERR_DEGENERATE);
	assert_null(t);
	assert_non_null(strstr(err.message, "verifier"));
}

/* Clean samples, the verifier in both views: found in both, its chi-square averages its 4
 * degrees of freedom (the prediction's covariance is right: one twice too small or large
 * moves the mean by ~1/3), and at most 0.1 % of samples are refused. Then hidden in view
 * 1, and in both: found in 1 and 0 views, the pose still solved. */
static void check_clean(double sigma_px)
{
	struct rs_pose_layout L;
	rs_pose_layout_default_verified(&L);
	struct rs_optical_tracker *t = make_tracker(&L, sigma_px);
	struct rng r = {.s = 4242 + (uint64_t)(sigma_px * 1000)};
	/* VERIFIER_CLEAN_TRIALS=N: a longer run for the false-alarm rate (docs/benchmarks.md) */
	const int trials =
	    getenv("VERIFIER_CLEAN_TRIALS") ? atoi(getenv("VERIFIER_CLEAN_TRIALS")) : 3000;
	assert_true(trials >= 3);
	int refused = 0, refused_in_both = 0, solved = 0, views[3] = {0};
	double chi2_sum = 0, se[2][2] = {{0}}, st[2][2] = {{0}};
	for (int trial = 0; trial < trials; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		int hide = trial % 3; /* 0: in both views, 1: hidden in view 1, 2: in neither */
		struct rs_optical_blob b[2][4];
		size_t n[2] = {3, 3};
		for (int i = 0; i < 4; ++i) {
			double X[3];
			rs_pose_transform_point(&T, i < 3 ? L.markers[i] : L.verifier, X);
			for (int v = 0; v < 2; ++v)
				if (i < 3 || (v == 0 && hide < 2) || (v == 1 && hide == 0))
					blob_at(X, v, sigma_px, &r, &b[v][i]);
		}
		/* the blobs above fill 0..2 with markers and 3 with the verifier where seen */
		n[0] = hide < 2 ? 4 : 3;
		n[1] = hide == 0 ? 4 : 3;
		struct rs_marker_sample smp;
		struct rs_optical_quality oq;
		assert_int_equal(rs_optical_tracker_process_blobs(t, b[0], n[0], b[1], n[1],
		                                                  2.0 * trial, &smp, &oq, NULL),
		                 RS_OK);
		if (oq.verdict == RS_OPTICAL_VERIFIER) {
			refused++;
			refused_in_both += hide == 0;
			continue;
		}
		if (oq.verdict != RS_OPTICAL_SOLVED) {
			if (getenv("VERIFIER_DEBUG"))
				printf("#   trial %d (verifier hidden %d): %s\n", trial, hide,
				       rs_optical_verdict_name(oq.verdict));
			continue; /* the other gates' false alarms: test_optical.c */
		}
		solved++;
		int expect = hide == 0 ? 2 : hide == 1 ? 1 : 0;
		assert_int_equal(oq.verifier_views, expect);
		views[expect]++;
		if (expect == 2)
			chi2_sum += oq.verifier_chi2;
		double rot, pos;
		pose_errors(&L, &smp, &T, &rot, &pos);
		int four = expect == 2; /* fitted to four points, else to the three markers */
		se[four][0] += rot * rot;
		se[four][1] += pos * pos;
		st[four][0] += oq.stated_rotation_rad * oq.stated_rotation_rad;
		st[four][1] += oq.stated_position_m * oq.stated_position_m;
		assert_true(error_ratio(&L, &smp, &oq, &T) < 8.0);
	}
	double mean = chi2_sum / views[2];
	/* the stated error is the real one, for the four-point fit as for three markers */
	for (int four = 0; four <= 1; ++four) {
		double kr = sqrt(se[four][0] / st[four][0]), kp = sqrt(se[four][1] / st[four][1]);
		printf("# %.2f px, %s: measured / stated RMS: rotation %.3f, position %.3f\n",
		       sigma_px, four ? "four points (verifier in both views)" : "three markers",
		       kr, kp);
		assert_true(fabs(kr - 1) < 0.15 && fabs(kp - 1) < 0.15);
	}
	const int in_both = (trials + 2) / 3;
	printf("# %.2f px: %d/%d solved (verifier in 2/1/0 views: %d/%d/%d), %d refused by the "
	       "verifier (%.3f %%; in both views %d of %d, %.3f %%), mean chi-square in both "
	       "views %.2f (4 degrees)\n",
	       sigma_px, solved, trials, views[2], views[1], views[0], refused,
	       100.0 * refused / trials, refused_in_both, in_both,
	       100.0 * refused_in_both / in_both, mean);
	/* The bars: at most 0.1 % refused, at least 99 % solved. What else is not
	 * solved is AMBIGUOUS: the verifier's image within the epipolar gate of a marker's in
	 * one view, so that both make a triple that fits (in a rendered frame the two spots
	 * would merge); VERIFIER_DEBUG=1 prints them. */
	assert_true(refused <= trials / 1000);
	assert_true(solved >= trials * 99 / 100);
	assert_true(mean > 3.4 && mean < 4.6);
	rs_optical_tracker_destroy(&t);
}

static void test_verifier_on_clean_samples(void **state)
{
	(void)state;
	check_clean(0.05);
	check_clean(0.3);
}

/* Camera 0 sees marker k; camera 1 does not, but sees a stray spot on its epipolar line
 * where it would see a point d along camera 0's ray through the marker (0.2-45 mm, both
 * ways), cold (each sample a second apart) and tracked (60 Hz after five clean samples).
 * The verifier's worst error/stated of a good pose, against the same sweep without it. */
static double stray_sweep(uint64_t seed, int verified, int tracked, int *out_good, int *out_refused,
                          int *out_beyond)
{
	struct rs_pose_layout L;
	rs_pose_layout_default_verified(&L);
	if (!verified)
		L.has_verifier = 0;
	struct rs_optical_tracker *t = make_tracker(&L, SIGMA_PX);
	struct rng r = {.s = seed};
	static const double offsets_mm[] = {0.2, 0.5, 1,  1.5, 2,  3,  4,  5,  6,
	                                    8,   10,  12, 16,  20, 25, 30, 38, 45};
	const int n_off = (int)(sizeof offsets_mm / sizeof offsets_mm[0]);
	double worst = 0, time_s = 0;
	int good = 0, refused = 0, beyond = 0;
	for (int trial = 0; trial < 60; ++trial) {
		struct rs_pose T;
		facing_pose(&r, &T);
		int k = trial % 3;
		double X[4][3];
		for (int i = 0; i < 4; ++i)
			rs_pose_transform_point(&T, i < 3 ? L.markers[i] : L.verifier, X[i]);
		double nk = sqrt(X[k][0] * X[k][0] + X[k][1] * X[k][1] + X[k][2] * X[k][2]);
		time_s += 1.0; /* a new scene: no history */
		for (int sign = -1; sign <= 1; sign += 2)
			for (int o = -5 * tracked; o < n_off; ++o) {
				struct rs_optical_blob b[2][4];
				size_t n[2] = {0, 0};
				for (int i = 0; i < 3 + verified; ++i)
					for (int v = 0; v < 2; ++v)
						if (!(v == 1 && i == k && o >= 0))
							blob_at(X[i], v, SIGMA_PX, &r,
							        &b[v][n[v]++]);
				if (o >= 0) { /* the stray, in camera 1 only */
					double d = offsets_mm[o] * 1e-3, G[3];
					for (int c = 0; c < 3; ++c)
						G[c] = X[k][c] * (1 + sign * d / nk);
					blob_at(G, 1, SIGMA_PX, &r, &b[1][n[1]++]);
				}
				time_s += tracked ? 1.0 / 60 : 1.0;
				struct rs_marker_sample smp;
				struct rs_optical_quality oq;
				assert_int_equal(
				    rs_optical_tracker_process_blobs(t, b[0], n[0], b[1], n[1],
				                                     time_s, &smp, &oq, NULL),
				    RS_OK);
				if (o < 0)
					continue;
				refused += oq.verdict == RS_OPTICAL_VERIFIER;
				if (oq.verdict != RS_OPTICAL_SOLVED)
					continue;
				if (verified) /* in view: found in both */
					assert_int_equal(oq.verifier_views, 2);
				double ratio = error_ratio(&L, &smp, &oq, &T);
				if (ratio > MAX_RATIO && getenv("VERIFIER_DEBUG"))
					printf("#   trial %d marker %d %+.1f mm: %.2fx, verifier "
					       "chi2 %.1f\n",
					       trial, k, sign * offsets_mm[o], ratio,
					       oq.verifier_chi2);
				worst = ratio > worst ? ratio : worst;
				beyond += ratio > MAX_RATIO;
				good++;
			}
	}
	rs_optical_tracker_destroy(&t);
	*out_good = good;
	*out_refused = refused;
	*out_beyond = beyond;
	return worst;
}

/* VERIFIER_SEED=N: other poses (the figures in docs/benchmarks.md) */
static uint64_t sweep_seed(void)
{
	return getenv("VERIFIER_SEED") ? strtoull(getenv("VERIFIER_SEED"), NULL, 10) : 1919;
}

static void test_verifier_refuses_a_marker_like_stray(void **state)
{
	(void)state;
	for (int tracked = 0; tracked <= 1; ++tracked) {
		int good[2], refused[2], beyond[2];
		double without =
		    stray_sweep(sweep_seed(), 0, tracked, &good[0], &refused[0], &beyond[0]);
		double with =
		    stray_sweep(sweep_seed(), 1, tracked, &good[1], &refused[1], &beyond[1]);
		printf(
		    "# stray on a hidden marker's epipolar line, %s, 2160 samples: without a "
		    "verifier %d good, %d beyond 5x, worst error/stated %.2f; with it %d good, %d "
		    "beyond 5x, %d refused by it, worst %.2f\n",
		    tracked ? "tracked" : "cold", good[0], beyond[0], without, good[1], beyond[1],
		    refused[1], with);
		/* the case is hard: three markers alone report such poses good */
		assert_true(without > MAX_RATIO);
		assert_true(refused[1] > 0);
		assert_true(with <= MAX_RATIO);
	}
}

/* The bar over eight more sets of poses, with the verifier: no good pose beyond
 * 5x its stated error. The verifier's offset alone (verify()) left 5 of 6,242 poses at
 * 5.1-5.6x over these seeds: a stray on the display origin's own marker (a corner, the
 * point of most leverage) found at 4.24 sigma of that offset moves the origin ~5x. Tested
 * against all six degrees of freedom of the four-point fit (Baarda's w-test per fault
 * direction, fit_with_verifier) the worst is 4.83 here; over 16 further seeds 2 of ~9,600
 * poses reach 5.15 and 5.44, both a 1 mm stray on the origin's marker that no test at
 * 4.24 sigma sees, plus the noise (docs/benchmarks.md). */
static void test_verifier_bar_over_seeds(void **state)
{
	(void)state;
	int total = 0, over = 0;
	double worst = 0;
	memset(&g_bound, 0, sizeof g_bound);
	for (uint64_t seed = 1; seed <= 8; ++seed)
		for (int tracked = 0; tracked <= 1; ++tracked) {
			int good, refused, beyond;
			double w = stray_sweep(seed, 1, tracked, &good, &refused, &beyond);
			worst = w > worst ? w : worst;
			total += good;
			over += beyond;
		}
	printf("# seeds 1-8, cold and tracked, with the verifier: %d good poses, %d beyond 5x, "
	       "worst error/stated %.2f; integrity bound: worst error/bound %.3f, mean "
	       "bound/stated (position) %.1f\n",
	       total, over, worst, g_bound.worst_of_bound, g_bound.bound_over_stated / g_bound.n);
	assert_int_equal(over, 0);
	assert_true(worst <= MAX_RATIO);
	/* The four points' fault part of the bound (fit_with_verifier): 8.8x the stated error
	 * on average, where the three markers' part alone gave 38.9x. */
	assert_true(g_bound.bound_over_stated / g_bound.n < 15.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_verifier_layout_file_and_checks),
	    cmocka_unit_test(test_verifier_on_clean_samples),
	    cmocka_unit_test(test_verifier_refuses_a_marker_like_stray),
	    cmocka_unit_test(test_verifier_bar_over_seeds),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* opencv backend not built: nothing to test (as test_optical.c) */
}
#endif
