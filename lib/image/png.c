/* PNG through libpng's simplified API: 8-bit RGB in and out, RGBA8 out. */
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "private/rs_atomic_file.h"
#include "raystream/rs_image.h"

void rs_image_quantize(const float *rgb, uint32_t width, uint32_t height, uint8_t *out)
{
	size_t n = (size_t)width * height * 3;
	for (size_t i = 0; i < n; ++i)
		out[i] = rs_image_quantize_value(rgb[i]);
}

static enum rs_status check_size(uint32_t width, uint32_t height, struct rs_error *err)
{
	if (width == 0 || height == 0 || width > RS_IMAGE_MAX_SIDE || height > RS_IMAGE_MAX_SIDE)
		return rs_error_set(err, RS_ERR_INVALID, "image size %ux%u is out of range", width,
		                    height);
	return RS_OK;
}

/* Write 8-bit pixels of `format` (PNG_FORMAT_RGB or _RGBA) through a temporary file. */
static enum rs_status write_bytes(const char *path, const uint8_t *bytes, uint32_t width,
                                  uint32_t height, png_uint_32 format, struct rs_error *err)
{
	struct rs_atomic_file af;
	enum rs_status status = rs_atomic_open(&af, path, err);
	if (status != RS_OK)
		return status;
	png_image image;
	memset(&image, 0, sizeof image);
	image.version = PNG_IMAGE_VERSION;
	image.width = width;
	image.height = height;
	image.format = format;
	int ok = png_image_write_to_stdio(&image, af.f, 0, bytes,
	                                  (png_int_32)(width * PNG_IMAGE_PIXEL_SIZE(format)), NULL);
	if (!ok)
		rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", path, image.message);
	png_image_free(&image);
	return rs_atomic_commit(&af, ok, err);
}

enum rs_status rs_image_write_png(const char *path, const float *rgb, uint32_t width,
                                  uint32_t height, struct rs_error *err)
{
	RS_ASSERT(path && rgb);
	enum rs_status status = check_size(width, height, err);
	if (status != RS_OK)
		return status;
	uint8_t *bytes = malloc((size_t)width * height * 3);
	if (!bytes)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory writing %s", path);
	rs_image_quantize(rgb, width, height, bytes);
	status = write_bytes(path, bytes, width, height, PNG_FORMAT_RGB, err);
	free(bytes);
	return status;
}

enum rs_status rs_image_write_png_rgba8(const char *path, const uint8_t *rgba, uint32_t width,
                                        uint32_t height, struct rs_error *err)
{
	RS_ASSERT(path && rgba);
	enum rs_status status = check_size(width, height, err);
	return status == RS_OK ? write_bytes(path, rgba, width, height, PNG_FORMAT_RGBA, err)
	                       : status;
}

enum rs_status rs_image_read_png(const char *path, uint8_t **out_pixels, uint32_t *out_width,
                                 uint32_t *out_height, struct rs_error *err)
{
	RS_ASSERT(path && out_pixels && out_width && out_height);
	*out_pixels = NULL;
	png_image image;
	memset(&image, 0, sizeof image);
	image.version = PNG_IMAGE_VERSION;
	if (!png_image_begin_read_from_file(&image, path))
		return rs_error_set(err, RS_ERR_PARSE, "cannot read %s: %s", path, image.message);
	image.format = PNG_FORMAT_RGB;
	enum rs_status status = check_size(image.width, image.height, err);
	uint8_t *pixels = status == RS_OK ? malloc(PNG_IMAGE_SIZE(image)) : NULL;
	if (status == RS_OK && !pixels)
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory reading %s", path);
	if (status != RS_OK) {
		png_image_free(&image);
		return status;
	}
	if (!png_image_finish_read(&image, NULL, pixels, 0, NULL)) {
		free(pixels);
		return rs_error_set(err, RS_ERR_PARSE, "cannot read %s: %s", path, image.message);
	}
	*out_pixels = pixels;
	*out_width = image.width;
	*out_height = image.height;
	return RS_OK;
}
