/* rs_image: PNG and PFM round trips, atomic writes, accuracy figures. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "raystream/rs_image.h"

static char dir[256];

static int make_dir(void **state)
{
	snprintf(dir, sizeof dir, "/tmp/rs_test_image_XXXXXX");
	return mkdtemp(dir) ? 0 : -1;
}

static int remove_dir(void **state)
{
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	return system(cmd) == 0 ? 0 : -1;
}

static void path_in_dir(char *out, size_t size, const char *name)
{
	snprintf(out, size, "%s/%s", dir, name);
}

static void png_round_trip_is_exact_after_quantizing(void **state)
{
	float rgb[4 * 3 * 3];
	for (size_t i = 0; i < sizeof rgb / sizeof rgb[0]; ++i)
		rgb[i] = (float)i / 40.0f;
	rgb[5] = NAN;
	rgb[6] = -2.0f;
	rgb[7] = 9.0f;
	char path[300];
	path_in_dir(path, sizeof path, "a.png");
	assert_int_equal(rs_image_write_png(path, rgb, 4, 3, NULL), RS_OK);
	uint8_t expect[4 * 3 * 3];
	rs_image_quantize(rgb, 4, 3, expect);
	assert_int_equal(expect[5], 0);
	assert_int_equal(expect[6], 0);
	assert_int_equal(expect[7], 255);
	uint8_t *got;
	uint32_t w, h;
	assert_int_equal(rs_image_read_png(path, &got, &w, &h, NULL), RS_OK);
	assert_int_equal(w, 4);
	assert_int_equal(h, 3);
	assert_memory_equal(got, expect, sizeof expect);
	rs_free(got);
}

/* A tie (c * 255 exactly k + 0.5 in fp32) rounds up, as the GLES display kernel's
 * floor(c * 255 + 0.5) does: lrintf() rounded half of them down (to even), so a GPU byte
 * and the CPU's differed by one there. */
static void quantize_rounds_ties_up_as_the_display_kernel(void **state)
{
	int ties = 0, even = 0;
	for (int k = 0; k < 255; ++k) {
		float c = ((float)k + 0.5f) / 255.0f;
		for (int step = 0; step < 4; ++step)
			c = nextafterf(c, 0.0f);
		for (int step = 0; step < 9; ++step, c = nextafterf(c, 1.0f)) {
			float x = c * 255.0f;
			uint8_t q = rs_image_quantize_value(c);
			if (x == (float)k + 0.5f) {
				assert_int_equal(q, k + 1);
				++ties;
				even += k % 2 == 0;
			} else { /* the nearest step (x + 0.5 may round up in fp32, as on the GPU)
				  */
				assert_true(fabsf((float)q - x) <= 0.5f);
			}
		}
	}
	assert_true(ties >= 100); /* the loop found ties of both parities to check */
	assert_true(even >= 50);
}

/* RGBA8 as renderers hand it out (rs_frame.rgba8) is written as it is: an RGBA PNG whose
 * colours read back exactly. */
static void png_from_rgba8_keeps_every_byte(void **state)
{
	uint8_t rgba[5 * 2 * 4];
	for (size_t i = 0; i < sizeof rgba; ++i)
		rgba[i] = (uint8_t)(i % 4 == 3 ? 255 : i * 7);
	char path[300];
	path_in_dir(path, sizeof path, "rgba.png");
	assert_int_equal(rs_image_write_png_rgba8(path, rgba, 5, 2, NULL), RS_OK);
	uint8_t *got;
	uint32_t w, h;
	assert_int_equal(rs_image_read_png(path, &got, &w, &h, NULL), RS_OK);
	assert_int_equal(w, 5);
	assert_int_equal(h, 2);
	for (size_t i = 0; i < 10; ++i)
		assert_memory_equal(got + i * 3, rgba + i * 4, 3);
	rs_free(got);
	/* IHDR colour type 6: RGBA, the alpha kept. */
	FILE *f = fopen(path, "rb");
	uint8_t head[26];
	assert_non_null(f);
	assert_int_equal(fread(head, 1, sizeof head, f), sizeof head);
	fclose(f);
	assert_int_equal(head[25], 6);
	struct rs_error err;
	path_in_dir(path, sizeof path, "none.png");
	assert_int_equal(rs_image_write_png_rgba8(path, rgba, 0, 2, &err), RS_ERR_INVALID);
	assert_int_equal(access(path, F_OK), -1);
}

static void pfm_round_trip_keeps_rows_and_infinity(void **state)
{
	float depth[3 * 2] = {1.0f, 2.5f, INFINITY, 4.0f, 5.0f, 1e30f};
	char path[300];
	path_in_dir(path, sizeof path, "d.pfm");
	assert_int_equal(rs_image_write_pfm(path, depth, 3, 2, 1, NULL), RS_OK);
	float *got;
	uint32_t w, h, c;
	assert_int_equal(rs_image_read_pfm(path, &got, &w, &h, &c, NULL), RS_OK);
	assert_true(w == 3 && h == 2 && c == 1);
	assert_memory_equal(got, depth, sizeof depth);
	rs_free(got);
}

static void nan_is_refused_without_leaving_a_file(void **state)
{
	float depth[2] = {1.0f, NAN};
	char path[300];
	path_in_dir(path, sizeof path, "nan.pfm");
	struct rs_error err = {0};
	assert_int_equal(rs_image_write_pfm(path, depth, 2, 1, 1, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "NaN"));
	assert_int_not_equal(access(path, F_OK), 0);
}

static void unwritable_path_fails_cleanly(void **state)
{
	float rgb[3] = {1, 1, 1};
	struct rs_error err = {0};
	assert_int_equal(rs_image_write_png("/nonexistent-dir/x.png", rgb, 1, 1, &err), RS_ERR_IO);
	assert_non_null(strstr(err.message, "/nonexistent-dir/x.png"));
}

/* Write-then-rename over a device or FIFO replaced the node itself: `--out /dev/null` run
 * as root turned /dev/null into a regular file. Such targets are refused and kept. */
static void fifo_target_is_refused_and_kept(void **state)
{
	float rgb[3] = {1, 1, 1};
	char path[300];
	struct stat st;
	struct rs_error err = {0};
	path_in_dir(path, sizeof path, "fifo.png");
	assert_int_equal(mkfifo(path, 0600), 0);
	assert_int_equal(rs_image_write_png(path, rgb, 1, 1, &err), RS_ERR_IO);
	assert_non_null(strstr(err.message, "not a regular file"));
	assert_int_equal(rs_image_write_pfm(path, rgb, 1, 1, 1, NULL), RS_ERR_IO);
	assert_int_equal(stat(path, &st), 0);
	assert_true(S_ISFIFO(st.st_mode));
	unlink(path);
}

static void reading_garbage_is_a_parse_error(void **state)
{
	char path[300];
	path_in_dir(path, sizeof path, "junk.png");
	FILE *f = fopen(path, "wb");
	fputs("this is not an image", f);
	fclose(f);
	uint8_t *px;
	uint32_t w, h, c;
	float *data;
	assert_int_equal(rs_image_read_png(path, &px, &w, &h, NULL), RS_ERR_PARSE);
	assert_int_equal(rs_image_read_pfm(path, &data, &w, &h, &c, NULL), RS_ERR_PARSE);
	assert_null(px);
	assert_null(data);
}

static void compare_reports_psnr_max_and_bad_share(void **state)
{
	float ref[4] = {0.5f, 0.5f, 0.5f, INFINITY};
	float test[4] = {0.5f, 0.6f, 0.5f, 3.0f};
	struct rs_image_diff d;
	rs_image_compare(test, ref, 4, 1, 1, 1.0, 0.05, &d);
	/* Three finite samples, one off by 0.1: mse = 0.01 / 3. */
	assert_true(fabs(d.mse - 0.01 / 3.0) < 1e-8);
	assert_true(fabs(d.psnr_db - 10.0 * log10(300.0)) < 1e-5);
	assert_true(fabs(d.max_abs_error - 0.1) < 1e-6);
	assert_int_equal(d.mismatched, 1);
	assert_true(fabs(d.bad_share - 0.5) < 1e-12);
	rs_image_compare(ref, ref, 4, 1, 1, 1.0, 0.0, &d);
	assert_true(isinf(d.psnr_db) && d.bad_share == 0.0);
}

static void compare_reports_mean_abs_error(void **state)
{
	(void)state;
	/* Two channels of three pixels: |d| = 0, 0.3, 0.1, 0, 0.2, 0 -> mean 0.1; the infinite
	 * pair (equal) is left out of the mean like it is of the mse. */
	float ref[8] = {0.5f, 0.5f, 0.2f, 0.2f, 0.4f, 0.7f, INFINITY, 1.0f};
	float test[8] = {0.5f, 0.8f, 0.1f, 0.2f, 0.6f, 0.7f, INFINITY, 1.0f};
	struct rs_image_diff d;
	rs_image_compare(test, ref, 4, 1, 2, 1.0, 0.25, &d);
	assert_true(fabs(d.mean_abs_error - 0.6 / 7.0) < 1e-6);
	assert_true(fabs(d.bad_share - 0.25) < 1e-12);
	rs_image_compare(ref, ref, 4, 1, 2, 1.0, 0.0, &d);
	assert_true(d.mean_abs_error == 0.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(png_round_trip_is_exact_after_quantizing),
	    cmocka_unit_test(quantize_rounds_ties_up_as_the_display_kernel),
	    cmocka_unit_test(png_from_rgba8_keeps_every_byte),
	    cmocka_unit_test(pfm_round_trip_keeps_rows_and_infinity),
	    cmocka_unit_test(nan_is_refused_without_leaving_a_file),
	    cmocka_unit_test(unwritable_path_fails_cleanly),
	    cmocka_unit_test(fifo_target_is_refused_and_kept),
	    cmocka_unit_test(reading_garbage_is_a_parse_error),
	    cmocka_unit_test(compare_reports_psnr_max_and_bad_share),
	    cmocka_unit_test(compare_reports_mean_abs_error),
	};
	return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
