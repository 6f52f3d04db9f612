/**
 * @file rs_codec.h
 * JPEG for streamed frames (module rs_codec, libjpeg-turbo's TurboJPEG API): an encoder
 * and a decoder object each wrapping one reusable TurboJPEG handle, over caller-owned
 * RGBA8 buffers (row 0 = top, 4 bytes per pixel, alpha ignored on encode and 255 on
 * decode). Nothing is allocated per frame. One object per thread.
 */
#ifndef RS_CODEC_H
#define RS_CODEC_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Chroma subsampling of the encoder. */
enum rs_jpeg_subsampling {
	RS_JPEG_420 = 0, /**< 4:2:0 (default): smallest, what video links use */
	RS_JPEG_444 = 1, /**< no chroma subsampling: sharper colour edges, ~1.5x the bytes */
};

/** Largest image side the codec accepts (JPEG's own limit is 65535). */
#define RS_JPEG_MAX_SIDE 16384u

struct rs_jpeg;

/** Create an encoder/decoder. Destroy with rs_jpeg_destroy(). RS_ERR_DEVICE if
 * TurboJPEG cannot start. */
enum rs_status rs_jpeg_create(struct rs_jpeg **out, struct rs_error *err);

/** Free; accepts NULL and sets *jpeg to NULL. */
void rs_jpeg_destroy(struct rs_jpeg **jpeg);

/** Worst-case JPEG bytes of a width x height image (0 for sizes out of range). */
size_t rs_jpeg_bound(uint32_t width, uint32_t height);

/**
 * Encode RGBA8 pixels at `quality` (1..100) into `out` (`cap` bytes; rs_jpeg_bound()
 * is always enough). RS_ERR_INVALID for a bad size or quality, RS_ERR_LIMIT when `cap` is
 * too small, RS_ERR_DEVICE when TurboJPEG fails (its message in `err`).
 */
enum rs_status rs_jpeg_encode(struct rs_jpeg *jpeg, const uint8_t *rgba, uint32_t width,
                              uint32_t height, int quality, enum rs_jpeg_subsampling sub,
                              uint8_t *out, size_t cap, size_t *out_size, struct rs_error *err);

/** Read the size of a JPEG without decoding. RS_ERR_PARSE for data that is not one. */
enum rs_status rs_jpeg_size(struct rs_jpeg *jpeg, const uint8_t *data, size_t size,
                            uint32_t *out_width, uint32_t *out_height, struct rs_error *err);

/**
 * Decode a JPEG that must be exactly `width` x `height` into RGBA8 `out_rgba` (caller-owned,
 * width * height * 4 bytes). RS_ERR_PARSE for corrupt data (nothing is trusted from a
 * half-decoded image), RS_ERR_BAD_DATA for another size.
 */
enum rs_status rs_jpeg_decode(struct rs_jpeg *jpeg, const uint8_t *data, size_t size,
                              uint32_t width, uint32_t height, uint8_t *out_rgba,
                              struct rs_error *err);

/**
 * Write RGBA8 pixels (alpha ignored) as a JPEG file at `quality` (1..100, 4:4:4), through a
 * temporary file and a rename like every file the library writes: all or nothing.
 */
enum rs_status rs_jpeg_write(const char *path, const uint8_t *rgba, uint32_t width, uint32_t height,
                             int quality, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
