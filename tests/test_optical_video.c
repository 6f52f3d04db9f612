/* rs_optical video: source: synthetic frame pairs written as PNG sequences with their rig
 * file are read back as marker samples; unreadable, malformed and mismatched input fails
 * with one-line errors. */
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

#define W 640
#define H 480
#define FRAMES 4

static uint8_t g_img[2][W * H];
static struct rs_pose g_truth[FRAMES];

static void write_sequence(const char *dir, int right_width)
{
	char path[256];
	struct rs_optical_rig rig;
	make_rig(0.4, &rig);
	snprintf(path, sizeof path, "%s/rig.yaml", dir);
	assert_int_equal(rs_optical_rig_save(path, &rig, NULL), RS_OK);
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rng r = {.s = 3};
	for (int i = 0; i < FRAMES; ++i) {
		facing_pose(&r, &g_truth[i]);
		assert_int_equal(
		    rs_optical_synth_render(&rig, &L, &g_truth[i], NULL, g_img[0], g_img[1], NULL),
		    RS_OK);
		snprintf(path, sizeof path, "%s/l_%02d.png", dir, i);
		assert_int_equal(rs_optical_write_png(path, g_img[0], W, H, NULL), RS_OK);
		snprintf(path, sizeof path, "%s/r_%02d.png", dir, i);
		assert_int_equal(rs_optical_write_png(path, g_img[1], right_width, H, NULL), RS_OK);
	}
}

static void test_video_source_reads_sequence(void **state)
{
	(void)state;
	char dir[] = "test_optical_video_XXXXXX", rest[512];
	assert_non_null(mkdtemp(dir));
	write_sequence(dir, W);
	/* Unrelated random poses: a second apart (rate 1), or the step gate would hold them. */
	snprintf(rest, sizeof rest,
	         "%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&rate=1&sigma_px=0.05", dir, dir,
	         dir);
	struct rs_track_source *src = NULL;
	struct rs_error err;
	assert_int_equal(rs_optical_open_uri("video", rest, &src, &err), RS_OK);
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose_solver *solver = NULL;
	struct rs_pose_solver_desc sd = {.noise_sigma_m = 0.001};
	assert_int_equal(rs_pose_solver_create(&sd, &L, &solver, NULL), RS_OK);
	for (int i = 0; i < FRAMES; ++i) {
		struct rs_marker_sample s;
		assert_int_equal(rs_track_source_read(src, &s, 100, NULL), RS_OK);
		assert_int_equal(s.sequence, i);
		assert_float_equal(s.host_time_s, i / 1.0, 1e-12);
		assert_int_equal(s.marker_count, 3);
		struct rs_pose p;
		struct rs_pose_quality q;
		assert_int_equal(rs_pose_solver_update(solver, &s, &p, &q), RS_OK);
		assert_int_equal(q.status, RS_POSE_OK);
		assert_true(rs_pose_angle_between(&p, &g_truth[i]) < 0.01);
		assert_true(pos_error(&p, &g_truth[i]) < 0.002);
	}
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 100, NULL), RS_END);
	rs_track_source_destroy(&src);
	rs_pose_solver_destroy(&solver);

	/* A mask over all of camera 0 (mask0=, two rectangles): every blob there is refused and
	 * counted, no markers. */
	char masked[600];
	snprintf(masked, sizeof masked, "%s&mask0=0,0,%d,%d+5,5,1,1", rest, W, H);
	assert_int_equal(rs_optical_open_uri("video", masked, &src, &err), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 100, NULL), RS_OK);
	assert_int_equal(s.marker_count, 0);
	struct rs_optical_quality oq;
	assert_true(rs_optical_source_quality(src, &oq));
	assert_int_equal(oq.blobs_masked[0], 3);
	assert_int_equal(oq.blobs_masked[1], 0);
	rs_track_source_destroy(&src);

	/* Mismatched frame sizes: the right stream is narrower than calibrated. */
	write_sequence(dir, W / 2);
	assert_int_equal(rs_optical_open_uri("video", rest, &src, &err), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 100, NULL), RS_ERR_BAD_DATA);
	assert_non_null(strstr(rs_track_source_last_error(src), "320x480"));
	rs_track_source_destroy(&src);
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	assert_int_equal(system(cmd), 0);
}

/* Bad URIs and files: each one error with a one-line message, no source. */
static void test_video_source_bad_input(void **state)
{
	(void)state;
	char dir[] = "test_optical_video_XXXXXX", rest[512];
	assert_non_null(mkdtemp(dir));
	write_sequence(dir, W);
	struct {
		const char *fmt;
		enum rs_status want;
	} cases[] = {
	    {"%s/l_%%02d.png?calib=%s/rig.yaml", RS_ERR_PARSE}, /* one stream */
	    {"%s/l_%%02d.png,%s/r_%%02d.png", RS_ERR_PARSE},    /* no calib */
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/none.yaml", RS_ERR_NOT_FOUND},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/l_00.png", RS_ERR_PARSE}, /* not a rig */
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&speed=2", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&sigma_px=-1", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&sigma_px=0.1x", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&mask0=1,2,3", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&mask1=1,2,0,4", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&mask1=1,2,3,4+", RS_ERR_PARSE},
	    {"%s/l_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml&mask0=1,2,3,4x", RS_ERR_PARSE},
	    {"%s/x_%%02d.png,%s/r_%%02d.png?calib=%s/rig.yaml", RS_ERR_IO}, /* unreadable */
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		snprintf(rest, sizeof rest, cases[i].fmt, dir, dir, dir);
		struct rs_track_source *src = NULL;
		struct rs_error err;
		enum rs_status st = rs_optical_open_uri("video", rest, &src, &err);
		if (st == RS_OK) {
			/* an unreadable stream may open and fail on its first frame */
			struct rs_marker_sample s;
			st = rs_track_source_read(src, &s, 100, NULL);
			rs_track_source_destroy(&src);
			assert_int_equal(st, RS_ERR_IO);
			continue;
		}
		printf("# %s -> %s\n", rest, err.message);
		assert_int_equal(st, cases[i].want);
		assert_null(src);
		assert_null(strchr(err.message, '\n'));
	}
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	assert_int_equal(system(cmd), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_video_source_reads_sequence),
	    cmocka_unit_test(test_video_source_bad_input),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* opencv backend not built: nothing to test */
}
#endif
