/* rs_track simulator: reproducibility, ground truth, injected faults, parameters. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <math.h>

#include "raystream/rs_sim.h"
#include "raystream/rs_track.h"

static void rotate(const double q[4], const double v[3], double out[3])
{
	double u[3] = {q[0], q[1], q[2]}, w = q[3];
	double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
	               u[0] * v[1] - u[1] * v[0]};
	double cc[3] = {u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2],
	                u[0] * c[1] - u[1] * c[0]};
	for (int i = 0; i < 3; i++)
		out[i] = v[i] + 2 * w * c[i] + 2 * cc[i];
}

static void run(const struct rs_sim_desc *d, int n, struct rs_marker_sample *samples,
                struct rs_pose *truth)
{
	struct rs_sim *sim = NULL;
	assert_int_equal(rs_sim_create(d, &sim, NULL), RS_OK);
	for (int i = 0; i < n; i++)
		assert_int_equal(rs_sim_next(sim, &samples[i], truth ? &truth[i] : NULL, NULL),
		                 RS_OK);
	rs_sim_destroy(&sim);
	assert_null(sim);
}

static void same_seed_same_stream(void **state)
{
	struct rs_sim_desc d = {.seed = 42,
	                        .noise_sigma_m = 0.001,
	                        .dropout_prob = 0.1,
	                        .occlusion_prob = 0.05,
	                        .swap_prob = 0.05,
	                        .clock_jitter_s = 0.0005};
	static struct rs_marker_sample a[600], b[600];
	run(&d, 600, a, NULL);
	run(&d, 600, b, NULL);
	assert_memory_equal(a, b, sizeof a);
}

static void different_seed_different_noise(void **state)
{
	struct rs_sim_desc d = {.seed = 1, .noise_sigma_m = 0.001};
	struct rs_marker_sample a[4], b[4];
	run(&d, 4, a, NULL);
	d.seed = 2;
	run(&d, 4, b, NULL);
	assert_true(a[3].markers[0].position[0] != b[3].markers[0].position[0]);
}

static void noiseless_markers_follow_truth(void **state)
{
	/* With sigma = 0 every marker is exactly R * layout + t (to rounding, 1e-12 m). */
	double layout[3][3];
	rs_sim_default_layout(layout);
	struct rs_sim_desc d = {.seed = 3};
	static struct rs_marker_sample s[1200];
	static struct rs_pose t[1200];
	run(&d, 1200, s, t); /* 10 s: the whole default script */
	for (int i = 0; i < 1200; i++) {
		double qn = 0;
		for (int k = 0; k < 4; k++)
			qn += t[i].orientation[k] * t[i].orientation[k];
		assert_true(fabs(qn - 1) < 1e-12);
		assert_true(t[i].orientation[3] >= 0);
		for (int m = 0; m < 3; m++) {
			double w[3];
			rotate(t[i].orientation, layout[m], w);
			for (int a = 0; a < 3; a++)
				assert_true(fabs(w[a] + t[i].position[a] -
				                 s[i].markers[m].position[a]) < 1e-12);
			assert_int_equal(s[i].markers[m].flags, RS_MARKER_VALID);
		}
	}
}

static void script_moves_and_rests(void **state)
{
	/* "still:1,walk:2": the first second does not move; walking covers > 0.3 m
	 * (0.6 m/s peak with a sin^2 profile averages 0.3 m/s over 2 s = 0.6 m). */
	struct rs_sim_desc d = {.script = "still:1,walk:2", .rate_hz = 100};
	static struct rs_marker_sample s[300];
	static struct rs_pose t[300];
	run(&d, 300, s, t);
	assert_true(fabs(t[99].position[0] - t[0].position[0]) < 1e-12);
	double dx = t[299].position[0] - t[100].position[0];
	double dy = t[299].position[1] - t[100].position[1];
	assert_true(sqrt(dx * dx + dy * dy) > 0.5);
}

static void turn_rotates_a_quarter(void **state)
{
	/* A turn segment integrates to 90 degrees about z (the tilt returns to zero);
	 * tolerance 0.5 degree covers the 4-substep midpoint integration at 120 Hz. */
	struct rs_sim_desc d = {.script = "turn:2,still:1"};
	static struct rs_marker_sample s[300];
	static struct rs_pose t[300];
	run(&d, 300, s, t);
	double angle = 2 * acos(fmin(1.0, t[290].orientation[3])) * 180 / RS_PI;
	assert_true(fabs(angle - 90) < 0.5);
}

/* A shake segment wobbles the orientation (peak body rates 1.5 and 1 rad/s at 4-5 Hz give
 * swings of a few degrees) and moves the position by about a centimetre, then settles:
 * bounds 1 deg < peak angle < 20 deg, lateral excursion < 3 cm, and the next still
 * segment does not move at all (1e-12: rounding). */
static void shake_wobbles_then_settles(void **state)
{
	struct rs_sim_desc d = {.script = "shake:1,still:1", .rate_hz = 200};
	static struct rs_marker_sample s[400];
	static struct rs_pose t[400];
	run(&d, 400, s, t);
	double peak = 0, excursion = 0;
	for (int i = 0; i < 200; i++) {
		double a = 2 * acos(fmin(1.0, t[i].orientation[3])) * 180 / RS_PI;
		peak = fmax(peak, a);
		excursion = fmax(excursion, fabs(t[i].position[1] - t[0].position[1]));
	}
	assert_true(peak > 1.0 && peak < 20.0);
	assert_true(excursion > 0.0 && excursion < 0.03);
	for (int i = 201; i < 400; i++) {
		assert_true(fabs(t[i].position[1] - t[201].position[1]) < 1e-12);
		assert_true(fabs(t[i].orientation[3] - t[201].orientation[3]) < 1e-12);
	}
}

static void noise_has_requested_sigma(void **state)
{
	/* Still script: marker scatter is pure noise; 3 x 3 x 2000 draws give the sample
	 * sigma within 5 % (its relative standard error is ~0.6 %). */
	struct rs_sim_desc d = {.script = "still", .noise_sigma_m = 0.0005, .seed = 9};
	static struct rs_marker_sample s[2000];
	static struct rs_pose t[2000];
	run(&d, 2000, s, t);
	double layout[3][3], sum2 = 0;
	rs_sim_default_layout(layout);
	for (int i = 0; i < 2000; i++)
		for (int m = 0; m < 3; m++)
			for (int a = 0; a < 3; a++) {
				double e = s[i].markers[m].position[a] - layout[m][a];
				sum2 += e * e;
			}
	double sigma = sqrt(sum2 / (2000 * 9));
	assert_true(fabs(sigma - 0.0005) < 0.05 * 0.0005);
}

static void faults_appear_at_their_rates(void **state)
{
	/* 6000 samples: expected 1800 dropped markers at p = 0.1 (sd ~ 40), 600 swaps at
	 * 0.1 (sd ~ 23); bounds of +-20 % are > 8 sd, so this never flakes for a fixed seed
	 * yet catches a rate that is wrong by a factor. Occlusions (about 4 % of markers)
	 * take precedence over dropouts, hence the lower bound of 0.75. */
	struct rs_sim_desc d = {.seed = 5,
	                        .dropout_prob = 0.1,
	                        .swap_prob = 0.1,
	                        .occlusion_prob = 0.01,
	                        .occlusion_s = 0.1};
	static struct rs_marker_sample s[6000];
	run(&d, 6000, s, NULL);
	int dropped = 0, swapped = 0, occluded = 0;
	for (int i = 0; i < 6000; i++) {
		for (int m = 0; m < 3; m++) {
			if (s[i].markers[m].flags == 0)
				dropped++;
			if (s[i].markers[m].flags == RS_MARKER_OCCLUDED)
				occluded++;
		}
		if (s[i].markers[0].id != 0 || s[i].markers[1].id != 1 || s[i].markers[2].id != 2)
			swapped++;
	}
	assert_true(dropped > 0.75 * 1800 && dropped < 1.2 * 1800);
	assert_true(swapped > 0.8 * 600 && swapped < 1.2 * 600);
	assert_true(occluded > 0);
}

static void occlusion_hides_one_marker_with_stale_position(void **state)
{
	struct rs_sim_desc d = {.seed = 8, .occlusion_prob = 1.0, .occlusion_s = 1.0};
	struct rs_marker_sample s[10];
	run(&d, 10, s, NULL);
	int which = -1;
	for (int m = 0; m < 3; m++)
		if (s[0].markers[m].flags == RS_MARKER_OCCLUDED)
			which = m;
	assert_true(which >= 0);
	for (int i = 1; i < 10; i++) {
		assert_int_equal(s[i].markers[which].flags, RS_MARKER_OCCLUDED);
		for (int m = 0; m < 3; m++)
			if (m != which)
				assert_int_equal(s[i].markers[m].flags, RS_MARKER_VALID);
	}
}

static void timestamps_and_sequences(void **state)
{
	/* Jitter of 1 ms at 120 Hz may reorder raw stamps; the simulator keeps them
	 * strictly increasing, and sequences count up from first_sequence with wrap. */
	struct rs_sim_desc d = {.clock_jitter_s = 0.001, .first_sequence = 0xFFFFFFFEu};
	struct rs_marker_sample s[100];
	run(&d, 100, s, NULL);
	int jittered = 0;
	for (int i = 1; i < 100; i++) {
		assert_true(s[i].device_time_us > s[i - 1].device_time_us);
		assert_int_equal(s[i].sequence, (uint32_t)(0xFFFFFFFEu + (uint32_t)i));
		if (llabs((long long)s[i].device_time_us - (long long)llround(i * 1e6 / 120)) > 10)
			jittered++;
	}
	assert_true(jittered > 50);
}

static void duration_ends_the_run(void **state)
{
	struct rs_sim_desc d = {.rate_hz = 100, .duration_s = 0.5};
	struct rs_sim *sim = NULL;
	struct rs_marker_sample s;
	assert_int_equal(rs_sim_create(&d, &sim, NULL), RS_OK);
	int n = 0;
	while (rs_sim_next(sim, &s, NULL, NULL) == RS_OK)
		n++;
	assert_int_equal(n, 50);
	rs_sim_destroy(&sim);
}

static void bad_descriptors_are_rejected(void **state)
{
	struct rs_sim *sim = NULL;
	struct rs_error err;
	struct rs_sim_desc d = {.dropout_prob = 1.5};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	assert_null(sim);
	d = (struct rs_sim_desc){.noise_sigma_m = NAN};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	d = (struct rs_sim_desc){.script = "walk,jump"};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "jump"));
	d = (struct rs_sim_desc){.script = "walk:-1"};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	d = (struct rs_sim_desc){.rate_hz = -5};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	/* So slow that one step leaves the wire format's range (and the timestamp's). */
	d = (struct rs_sim_desc){.rate_hz = 1e-300};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "rate"));
	d = (struct rs_sim_desc){.clock_jitter_s = 1e300};
	assert_int_equal(rs_sim_create(&d, &sim, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "jitter"));
	assert_null(sim);
}

static void params_parse_units(void **state)
{
	struct rs_sim_desc d;
	char script[64];
	assert_int_equal(rs_sim_parse_params("seed=7&noise=0.5mm&rate=200&jitter=200us&"
	                                     "duration=3s&script=walk:1,still&swap=0.01",
	                                     &d, script, sizeof script, NULL),
	                 RS_OK);
	assert_true(d.seed == 7);
	assert_true(fabs(d.noise_sigma_m - 0.0005) < 1e-15);
	assert_true(d.rate_hz == 200);
	assert_true(fabs(d.clock_jitter_s - 0.0002) < 1e-15);
	assert_true(d.duration_s == 3);
	assert_string_equal(d.script, "walk:1,still");
	assert_true(d.swap_prob == 0.01);
}

static void params_reject_bad_input(void **state)
{
	struct rs_sim_desc d;
	char script[16];
	struct rs_error err;
	const char *bad[] = {"seed",
	                     "seed=x",
	                     "noise=0.5km",
	                     "noise=-1mm",
	                     "color=red",
	                     "=5",
	                     "rate=nan",
	                     "script=walk:1,still:1,turn:1",
	                     "seed=99999999999999999999",
	                     "rate=0", /* not "the default" when written out */
	                     "rate=0Hz",
	                     "rate=2e6"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(rs_sim_parse_params(bad[i], &d, script, sizeof script, &err),
		                 RS_ERR_PARSE);
		assert_true(err.message[0] != '\0');
	}
}

static void script_length_is_one_pass(void **state)
{
	(void)state;
	double s = 0;
	assert_int_equal(rs_sim_script_seconds(NULL, &s, NULL), RS_OK);
	assert_true(s == 6.0); /* still:0.5,walk:2,turn:2,shake:1,still:0.5 */
	assert_int_equal(rs_sim_script_seconds("still,walk:0.25", &s, NULL), RS_OK);
	assert_true(s == 1.25);
	struct rs_error err;
	assert_int_equal(rs_sim_script_seconds("fly", &s, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "fly"));
}

static void sim_source_delivers_quantised_samples(void **state)
{
	/* The sim source round-trips through the wire format: positions to 0.5 um. */
	struct rs_track_sim_source_desc d = {.sim = {.seed = 4, .noise_sigma_m = 0.001}};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_sim_open(&d, &src, NULL), RS_OK);
	struct rs_marker_sample ref[50], got;
	run(&d.sim, 50, ref, NULL);
	for (int i = 0; i < 50; i++) {
		assert_int_equal(rs_track_source_read(src, &got, 0, NULL), RS_OK);
		assert_int_equal(got.sequence, ref[i].sequence);
		for (int m = 0; m < 3; m++)
			for (int a = 0; a < 3; a++)
				assert_true(fabs(got.markers[m].position[a] -
				                 ref[i].markers[m].position[a]) <= 0.5e-6 + 1e-12);
	}
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_true(st.samples == 50 && st.proto.frames == 50);
	/* Reopen restarts the same run. */
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &got, 0, NULL), RS_OK);
	assert_int_equal(got.sequence, ref[0].sequence);
	rs_track_source_destroy(&src);
	assert_null(src);
}

static void sim_source_realtime_paces(void **state)
{
	/* 20 samples at 200 Hz in realtime take >= 95 ms of host time (19 periods). */
	struct rs_track_sim_source_desc d = {.sim = {.rate_hz = 200}, .realtime = 1};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_sim_open(&d, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	double t0 = rs_track_now_s();
	for (int i = 0; i < 20; i++)
		while (rs_track_source_read(src, &s, 5, NULL) == RS_TIMEOUT) {
		}
	assert_true(rs_track_now_s() - t0 >= 0.094);
	rs_track_source_destroy(&src);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(same_seed_same_stream),
	    cmocka_unit_test(different_seed_different_noise),
	    cmocka_unit_test(noiseless_markers_follow_truth),
	    cmocka_unit_test(script_moves_and_rests),
	    cmocka_unit_test(turn_rotates_a_quarter),
	    cmocka_unit_test(shake_wobbles_then_settles),
	    cmocka_unit_test(noise_has_requested_sigma),
	    cmocka_unit_test(faults_appear_at_their_rates),
	    cmocka_unit_test(occlusion_hides_one_marker_with_stale_position),
	    cmocka_unit_test(timestamps_and_sequences),
	    cmocka_unit_test(duration_ends_the_run),
	    cmocka_unit_test(bad_descriptors_are_rejected),
	    cmocka_unit_test(params_parse_units),
	    cmocka_unit_test(params_reject_bad_input),
	    cmocka_unit_test(script_length_is_one_pass),
	    cmocka_unit_test(sim_source_delivers_quantised_samples),
	    cmocka_unit_test(sim_source_realtime_paces),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
