/**
 * @file rs_image.h
 * Image output and comparison: 8-bit PNG (through libpng) for colour, PFM for float data
 * such as primary-hit depth, and the accuracy figures every backend is judged by (PSNR,
 * max error, share of bad pixels) against the CPU reference.
 *
 * Files are written to a temporary name beside the target and renamed into place, so a
 * failed write never leaves a partial file under the requested name. A target that exists
 * and is not a regular file (a device such as /dev/null, a FIFO) is refused with RS_ERR_IO
 * rather than replaced.
 */
#ifndef RS_IMAGE_H
#define RS_IMAGE_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest width or height accepted by the image calls. */
#define RS_IMAGE_MAX_SIDE 16384u

/**
 * One channel as rs_image_quantize() rounds it: floor(clamp(c, 0, 1) * 255 + 0.5), NaN -> 0.
 * The GLES display kernel's expression, evaluated alike in fp32 (C11 mode: no contraction
 * into a fused multiply-add): a tie (c * 255 exactly k + 0.5) rounds up on both sides, where
 * lrintf() rounded it to even.
 */
static inline uint8_t rs_image_quantize_value(float c)
{
	c = !(c > 0.0f) ? 0.0f : c > 1.0f ? 1.0f : c; /* !(c > 0) also catches NaN */
	return (uint8_t)floorf(c * 255.0f + 0.5f);
}

/**
 * Quantise linear RGB floats (row 0 = top) to 8 bits: floor(clamp(c, 0, 1) * 255 + 0.5); NaN
 * becomes 0. This is also what the GLES display kernel does, so images compare exactly.
 * out: caller-owned width * height * 3 bytes.
 */
void rs_image_quantize(const float *rgb, uint32_t width, uint32_t height, uint8_t *out);

/** Write linear RGB floats (row 0 = top) as an 8-bit RGB PNG, via rs_image_quantize(). */
enum rs_status rs_image_write_png(const char *path, const float *rgb, uint32_t width,
                                  uint32_t height, struct rs_error *err);

/** Write 8-bit RGBA pixels (row 0 = top; rs_frame.rgba8, what renderers hand out) as an
 * 8-bit RGBA PNG, through a temporary file like rs_image_write_png(). */
enum rs_status rs_image_write_png_rgba8(const char *path, const uint8_t *rgba, uint32_t width,
                                        uint32_t height, struct rs_error *err);

/**
 * Read an 8-bit PNG as RGB bytes. *out_pixels is allocated by the call (width*height*3,
 * row 0 = top) and freed by the caller with rs_free().
 */
enum rs_status rs_image_read_png(const char *path, uint8_t **out_pixels, uint32_t *out_width,
                                 uint32_t *out_height, struct rs_error *err);

/**
 * Write a PFM (little-endian; 1 channel "Pf" or 3 channels "PF"). data is row 0 = top, as
 * everywhere in raystream; the file stores rows bottom-up as the format requires.
 * Infinities are kept (they mean "no hit"); NaN is refused with RS_ERR_BAD_DATA.
 */
enum rs_status rs_image_write_pfm(const char *path, const float *data, uint32_t width,
                                  uint32_t height, uint32_t channels, struct rs_error *err);

/**
 * Read a PFM of either byte order. *out_data is allocated (width*height*channels floats,
 * row 0 = top) and freed by the caller with rs_free().
 */
enum rs_status rs_image_read_pfm(const char *path, float **out_data, uint32_t *out_width,
                                 uint32_t *out_height, uint32_t *out_channels,
                                 struct rs_error *err);

/** Accuracy of a test image against a reference. */
struct rs_image_diff {
	size_t pixels;
	double mse;           /**< mean squared error over all channels */
	double psnr_db;       /**< 10 log10(peak^2 / mse); +INFINITY when identical */
	double max_abs_error; /**< largest per-channel difference */
	double bad_share;     /**< share of pixels with any channel off by more than threshold */
	size_t mismatched; /**< pixels where exactly one image is infinite (depth: hit vs miss) */
	double mean_abs_error; /**< mean per-channel difference (NaN counts as peak, as in mse) */
};

/**
 * Compare two float images of `channels` channels. Pixels where both values are the same
 * infinity count as equal; where only one is infinite the pixel is "mismatched" and bad,
 * and is left out of the MSE. peak is the signal range (1 for colour).
 */
void rs_image_compare(const float *test, const float *reference, uint32_t width, uint32_t height,
                      uint32_t channels, double peak, double bad_threshold,
                      struct rs_image_diff *out);

#ifdef __cplusplus
}
#endif
#endif
