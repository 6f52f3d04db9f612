/* Portable float maps: the plain format every image tool reads, used for depth. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "private/rs_atomic_file.h"
#include "raystream/rs_image.h"

static int host_is_little_endian(void)
{
	const uint16_t probe = 1;
	return *(const uint8_t *)&probe == 1;
}

static void swap_bytes(float *v)
{
	uint8_t b[4];
	memcpy(b, v, 4);
	uint8_t s[4] = {b[3], b[2], b[1], b[0]};
	memcpy(v, s, 4);
}

enum rs_status rs_image_write_pfm(const char *path, const float *data, uint32_t width,
                                  uint32_t height, uint32_t channels, struct rs_error *err)
{
	RS_ASSERT(path && data);
	if (width == 0 || height == 0 || width > RS_IMAGE_MAX_SIDE || height > RS_IMAGE_MAX_SIDE)
		return rs_error_set(err, RS_ERR_INVALID, "image size %ux%u is out of range", width,
		                    height);
	if (channels != 1 && channels != 3)
		return rs_error_set(err, RS_ERR_INVALID, "PFM needs 1 or 3 channels, not %u",
		                    channels);
	size_t n = (size_t)width * height * channels;
	for (size_t i = 0; i < n; ++i)
		if (isnan(data[i]))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "refusing to write NaN at pixel %zu", i / channels);
	struct rs_atomic_file af;
	enum rs_status status = rs_atomic_open(&af, path, err);
	if (status != RS_OK)
		return status;
	FILE *f = af.f;
	int little = host_is_little_endian();
	fprintf(f, "%s\n%u %u\n%s\n", channels == 3 ? "PF" : "Pf", width, height,
	        little ? "-1.0" : "1.0");
	for (uint32_t row = height; row-- > 0;)
		fwrite(data + (size_t)row * width * channels, sizeof(float),
		       (size_t)width * channels, f);
	return rs_atomic_commit(&af, true, err);
}

enum rs_status rs_image_read_pfm(const char *path, float **out_data, uint32_t *out_width,
                                 uint32_t *out_height, uint32_t *out_channels, struct rs_error *err)
{
	RS_ASSERT(path && out_data && out_width && out_height && out_channels);
	*out_data = NULL;
	FILE *f = fopen(path, "rb");
	if (!f)
		return rs_error_set(err, errno == ENOENT ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                    "cannot open %s: %s", path, strerror(errno));
	char magic[3] = {0};
	unsigned w = 0, h = 0;
	double scale = 0.0;
	enum rs_status status = RS_OK;
	if (fscanf(f, "%2s %u %u %lf", magic, &w, &h, &scale) != 4 || fgetc(f) == EOF ||
	    (strcmp(magic, "PF") != 0 && strcmp(magic, "Pf") != 0) || scale == 0.0 ||
	    !isfinite(scale))
		status = rs_error_set(err, RS_ERR_PARSE, "%s is not a PFM file", path);
	else if (w == 0 || h == 0 || w > RS_IMAGE_MAX_SIDE || h > RS_IMAGE_MAX_SIDE)
		status =
		    rs_error_set(err, RS_ERR_PARSE, "%s: size %ux%u is out of range", path, w, h);
	uint32_t channels = magic[1] == 'F' ? 3 : 1;
	size_t n = (size_t)w * h * channels;
	float *data = status == RS_OK ? malloc(n * sizeof *data) : NULL;
	if (status == RS_OK && !data)
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory reading %s", path);
	for (uint32_t row = h; status == RS_OK && row-- > 0;)
		if (fread(data + (size_t)row * w * channels, sizeof(float), (size_t)w * channels,
		          f) != (size_t)w * channels)
			status = rs_error_set(err, RS_ERR_PARSE, "%s is truncated", path);
	fclose(f);
	if (status != RS_OK) {
		free(data);
		return status;
	}
	if ((scale < 0.0) != host_is_little_endian())
		for (size_t i = 0; i < n; ++i)
			swap_bytes(&data[i]);
	*out_data = data;
	*out_width = w;
	*out_height = h;
	*out_channels = channels;
	return RS_OK;
}
