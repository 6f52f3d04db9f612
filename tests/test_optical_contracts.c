/* Contract checks of the optical backend: a NULL handle, out-pointer or path reaches
 * RS_ASSERT (as in every other module, tests/test_contracts.c) instead of coming back as
 * RS_ERR_INVALID, which a caller could mistake for bad data. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "contract.h"

#ifdef RS_HAVE_OPTICAL
#include "raystream/rs_optical.h"

static void rig_calls_check_their_arguments(void **state)
{
	(void)state;
	struct rs_optical_rig rig;
	rs_optical_rig_example(0.4, 64, 48, &rig);
	uint8_t px[4] = {0};
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_rig_check(NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_rig_load(NULL, &rig, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_rig_load("rig.yaml", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_rig_save(NULL, &rig, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_rig_save("rig.yaml", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_write_png(NULL, px, 2, 2, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_write_png("x.png", NULL, 2, 2, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_calibrate(NULL, NULL, NULL, 0, NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_calibrate(NULL, NULL, NULL, 3, &rig, NULL, NULL));
	struct rs_error err;
	/* Bad data stays a status. */
	assert_int_equal(rs_optical_write_png("x.png", px, 0, 2, &err), RS_ERR_INVALID);
}

static void tracker_calls_check_their_handles(void **state)
{
	(void)state;
	struct rs_optical_tracker_desc d = {0};
	rs_optical_rig_example(0.4, 64, 48, &d.rig);
	struct rs_optical_tracker *t = NULL;
	struct rs_marker_sample smp;
	struct rs_optical_blob b[1] = {{1, 1, 1, 1}};
	struct rs_optical_frames *f = NULL;
	struct rs_optical_image img;
	struct rs_track_source *src = NULL;
	size_t n;
	uint8_t px[64 * 48] = {0};
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_tracker_create(NULL, &t, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_tracker_create(&d, NULL, NULL));
	assert_int_equal(rs_optical_tracker_create(&d, &t, NULL), RS_OK);
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_optical_tracker_process(NULL, NULL, NULL, 0.0, &smp, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_optical_tracker_process(t, NULL, NULL, 0.0, NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_optical_tracker_process_blobs(t, NULL, 1, b, 1, 0.0, &smp, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_optical_tracker_process_blobs(NULL, b, 1, b, 1, 0.0, &smp, NULL, NULL));
	rs_optical_tracker_destroy(&t);
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_detect(NULL, NULL, b, 1, &n, NULL));
	img = (struct rs_optical_image){px, 64, 48, 64};
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_detect(NULL, &img, b, 1, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_detect(NULL, &img, NULL, 1, &n, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_frames_open(NULL, 0, &f, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_frames_open("x_%04d.png", 0, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_frames_read(NULL, &img, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_open_uri("video", NULL, &src, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_open_uri("video", "a,b?calib=r.yaml", NULL, NULL));
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	struct rs_pose T = {.orientation = {0, 0, 0, 1}};
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_synth_render(&d.rig, &L, &T, NULL, px, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_synth_render(NULL, &L, &T, NULL, px, px, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_optical_synth_board(&d.rig, NULL, &T, px, px, NULL));
	assert_null(f);
	assert_null(src);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(rig_calls_check_their_arguments),
	    cmocka_unit_test(tracker_calls_check_their_handles),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* opencv backend not built: nothing to test (as test_optical.c) */
}
#endif
