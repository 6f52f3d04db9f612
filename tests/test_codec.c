/* rs_codec: JPEG round trip quality against the quality setting, size ordering, and
 * refusal of corrupt, truncated, wrongly sized data and too-small buffers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_codec.h"
#include "contract.h"

#define W 96
#define H 64

static uint8_t img[W * H * 4], back[W * H * 4];
static uint8_t jpg[1 << 16];

/* A smooth gradient with one hard edge, like a rendered frame. */
static void make_image(void)
{
	for (int y = 0; y < H; ++y)
		for (int x = 0; x < W; ++x) {
			uint8_t *p = img + 4 * (y * W + x);
			p[0] = (uint8_t)(x * 255 / (W - 1));
			p[1] = (uint8_t)(y * 255 / (H - 1));
			p[2] = x > W / 2 ? 200 : 40;
			p[3] = 255;
		}
}

static double psnr(const uint8_t *a, const uint8_t *b)
{
	double se = 0;
	for (int i = 0; i < W * H; ++i)
		for (int c = 0; c < 3; ++c) {
			double d = (double)a[4 * i + c] - b[4 * i + c];
			se += d * d;
		}
	return 10.0 * log10(255.0 * 255.0 / (se / (W * H * 3)));
}

static void test_round_trip_quality(void **state)
{
	(void)state;
	make_image();
	struct rs_jpeg *j = NULL;
	assert_int_equal(rs_jpeg_create(&j, NULL), RS_OK);
	assert_true(rs_jpeg_bound(W, H) <= sizeof jpg);
	size_t n90 = 0, n30 = 0;
	assert_int_equal(rs_jpeg_encode(j, img, W, H, 90, RS_JPEG_444, jpg, sizeof jpg, &n90, NULL),
	                 RS_OK);
	uint32_t w = 0, h = 0;
	assert_int_equal(rs_jpeg_size(j, jpg, n90, &w, &h, NULL), RS_OK);
	assert_int_equal(w, W);
	assert_int_equal(h, H);
	memset(back, 0, sizeof back);
	assert_int_equal(rs_jpeg_decode(j, jpg, n90, W, H, back, NULL), RS_OK);
	/* quality 90, 4:4:4 on a smooth image: well above 38 dB; alpha comes back opaque */
	assert_true(psnr(img, back) > 38.0);
	assert_int_equal(back[3], 255);
	assert_int_equal(rs_jpeg_encode(j, img, W, H, 30, RS_JPEG_420, jpg, sizeof jpg, &n30, NULL),
	                 RS_OK);
	assert_true(n30 < n90);
	assert_int_equal(rs_jpeg_decode(j, jpg, n30, W, H, back, NULL), RS_OK);
	double p30 = psnr(img, back);
	assert_true(p30 > 25.0 && p30 < 45.0);
	rs_jpeg_destroy(&j);
	assert_null(j);
	rs_jpeg_destroy(NULL);
}

/* rs_jpeg_write: a JPEG file that decodes to the image; a bad size leaves no file. */
static void test_write_file(void **state)
{
	(void)state;
	make_image();
	char dir[] = "/tmp/rs_test_codec_XXXXXX", path[64];
	assert_non_null(mkdtemp(dir));
	snprintf(path, sizeof path, "%s/a.jpg", dir);
	assert_int_equal(rs_jpeg_write(path, img, W, H, 95, NULL), RS_OK);
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	size_t n = fread(jpg, 1, sizeof jpg, f);
	fclose(f);
	assert_true(n > 2 && jpg[0] == 0xFF && jpg[1] == 0xD8);
	struct rs_jpeg *j = NULL;
	assert_int_equal(rs_jpeg_create(&j, NULL), RS_OK);
	assert_int_equal(rs_jpeg_decode(j, jpg, n, W, H, back, NULL), RS_OK);
	assert_true(psnr(img, back) > 38.0);
	rs_jpeg_destroy(&j);
	struct rs_error err;
	snprintf(path, sizeof path, "%s/b.jpg", dir);
	assert_int_equal(rs_jpeg_write(path, img, 0, H, 95, &err), RS_ERR_INVALID);
	assert_null(fopen(path, "rb"));
	snprintf(path, sizeof path, "%s/no/c.jpg", dir);
	assert_int_equal(rs_jpeg_write(path, img, W, H, 95, &err), RS_ERR_IO);
	char cmd[64];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	assert_int_equal(system(cmd), 0);
}

static void test_bad_input_refused(void **state)
{
	(void)state;
	make_image();
	struct rs_jpeg *j = NULL;
	assert_int_equal(rs_jpeg_create(&j, NULL), RS_OK);
	size_t n = 0;
	struct rs_error err = {0};
	assert_int_equal(rs_jpeg_encode(j, img, W, H, 0, RS_JPEG_420, jpg, sizeof jpg, &n, &err),
	                 RS_ERR_INVALID);
	assert_int_equal(rs_jpeg_encode(j, img, W, H, 80, RS_JPEG_420, jpg, 100, &n, &err),
	                 RS_ERR_LIMIT);
	assert_int_equal(rs_jpeg_encode(j, img, W, H, 80, RS_JPEG_420, jpg, sizeof jpg, &n, NULL),
	                 RS_OK);
	/* wrong expected size */
	assert_int_equal(rs_jpeg_decode(j, jpg, n, W, H + 1, back, &err), RS_ERR_BAD_DATA);
	/* truncated: an error, never a half image */
	assert_int_equal(rs_jpeg_decode(j, jpg, n / 2, W, H, back, &err), RS_ERR_PARSE);
	assert_true(strlen(err.message) > 0);
	/* not a JPEG at all */
	static const uint8_t junk[64] = {1, 2, 3};
	assert_int_equal(rs_jpeg_decode(j, junk, sizeof junk, W, H, back, NULL), RS_ERR_PARSE);
	assert_int_equal(rs_jpeg_decode(j, junk, 0, W, H, back, NULL), RS_ERR_PARSE);
	assert_int_equal(rs_jpeg_bound(0, 5), 0);
	rs_jpeg_destroy(&j);
}

/* NULL handles and buffers are contract violations, not statuses. */
static void test_contracts(void **state)
{
	(void)state;
	struct rs_jpeg *j = NULL;
	size_t n = 0;
	RS_EXPECT_CONTRACT_VIOLATION(rs_jpeg_create(NULL, NULL));
	assert_int_equal(rs_jpeg_create(&j, NULL), RS_OK);
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_jpeg_encode(NULL, img, W, H, 80, RS_JPEG_420, jpg, sizeof jpg, &n, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_jpeg_encode(j, NULL, W, H, 80, RS_JPEG_420, jpg, sizeof jpg, &n, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_jpeg_decode(j, jpg, 10, W, H, NULL, NULL));
	rs_jpeg_destroy(&j);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_round_trip_quality),
	    cmocka_unit_test(test_write_file),
	    cmocka_unit_test(test_bad_input_refused),
	    cmocka_unit_test(test_contracts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
