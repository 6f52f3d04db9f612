/* JPEG through TurboJPEG: one compressor and one decompressor handle per object, reused. */
#include <limits.h>
#include <stdlib.h>
#include <turbojpeg.h>

#include "private/rs_atomic_file.h"
#include "raystream/rs_codec.h"

struct rs_jpeg {
	tjhandle enc, dec;
};

enum rs_status rs_jpeg_create(struct rs_jpeg **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_jpeg *j = calloc(1, sizeof *j);
	if (!j)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "jpeg: out of memory");
	j->enc = tjInitCompress();
	j->dec = tjInitDecompress();
	if (!j->enc || !j->dec) {
		rs_error_set(err, RS_ERR_DEVICE, "jpeg: TurboJPEG would not start: %s",
		             tjGetErrorStr2(NULL));
		rs_jpeg_destroy(&j);
		return RS_ERR_DEVICE;
	}
	*out = j;
	return RS_OK;
}

void rs_jpeg_destroy(struct rs_jpeg **jpeg)
{
	if (!jpeg || !*jpeg)
		return;
	if ((*jpeg)->enc)
		tjDestroy((*jpeg)->enc);
	if ((*jpeg)->dec)
		tjDestroy((*jpeg)->dec);
	free(*jpeg);
	*jpeg = NULL;
}

static int size_ok(uint32_t w, uint32_t h)
{
	return w >= 1 && h >= 1 && w <= RS_JPEG_MAX_SIDE && h <= RS_JPEG_MAX_SIDE;
}

size_t rs_jpeg_bound(uint32_t width, uint32_t height)
{
	if (!size_ok(width, height))
		return 0;
	/* 4:4:4 is the largest bound of the subsamplings we use */
	unsigned long n = tjBufSize((int)width, (int)height, TJSAMP_444);
	return n == (unsigned long)-1 ? 0 : (size_t)n;
}

enum rs_status rs_jpeg_encode(struct rs_jpeg *jpeg, const uint8_t *rgba, uint32_t width,
                              uint32_t height, int quality, enum rs_jpeg_subsampling sub,
                              uint8_t *out, size_t cap, size_t *out_size, struct rs_error *err)
{
	RS_ASSERT(jpeg && rgba && out && out_size);
	*out_size = 0;
	if (!size_ok(width, height) || quality < 1 || quality > 100 ||
	    (sub != RS_JPEG_420 && sub != RS_JPEG_444))
		return rs_error_set(err, RS_ERR_INVALID, "jpeg: %ux%u at quality %d not encodable",
		                    width, height, quality);
	/* TJFLAG_NOREALLOC writes at most the bound, so a smaller buffer must be refused
	 * here rather than trusted to be enough for this image. */
	if (cap < rs_jpeg_bound(width, height) || cap > ULONG_MAX)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "jpeg: output buffer of %zu bytes < bound %zu", cap,
		                    rs_jpeg_bound(width, height));
	unsigned char *dst = out;
	unsigned long n = (unsigned long)cap;
	if (tjCompress2(jpeg->enc, rgba, (int)width, 0, (int)height, TJPF_RGBA, &dst, &n,
	                sub == RS_JPEG_444 ? TJSAMP_444 : TJSAMP_420, quality,
	                TJFLAG_NOREALLOC | TJFLAG_FASTDCT) != 0)
		return rs_error_set(err, RS_ERR_DEVICE, "jpeg: encode failed: %s",
		                    tjGetErrorStr2(jpeg->enc));
	*out_size = (size_t)n;
	return RS_OK;
}

enum rs_status rs_jpeg_size(struct rs_jpeg *jpeg, const uint8_t *data, size_t size,
                            uint32_t *out_width, uint32_t *out_height, struct rs_error *err)
{
	RS_ASSERT(jpeg && (data || size == 0) && out_width && out_height);
	int w = 0, h = 0, sub = 0, cs = 0;
	if (size == 0 || size > ULONG_MAX ||
	    tjDecompressHeader3(jpeg->dec, data, (unsigned long)size, &w, &h, &sub, &cs) != 0 ||
	    w < 1 || h < 1)
		return rs_error_set(err, RS_ERR_PARSE, "jpeg: not a JPEG header (%zu bytes)", size);
	*out_width = (uint32_t)w;
	*out_height = (uint32_t)h;
	return RS_OK;
}

enum rs_status rs_jpeg_decode(struct rs_jpeg *jpeg, const uint8_t *data, size_t size,
                              uint32_t width, uint32_t height, uint8_t *out_rgba,
                              struct rs_error *err)
{
	RS_ASSERT(jpeg && out_rgba);
	uint32_t w, h;
	enum rs_status st = rs_jpeg_size(jpeg, data, size, &w, &h, err);
	if (st != RS_OK)
		return st;
	if (w != width || h != height)
		return rs_error_set(err, RS_ERR_BAD_DATA, "jpeg: image is %ux%u, expected %ux%u", w,
		                    h, width, height);
	/* TJFLAG_STOPONWARNING: a truncated or corrupt stream is an error, not a grey tail. */
	if (tjDecompress2(jpeg->dec, data, (unsigned long)size, out_rgba, (int)width, 0,
	                  (int)height, TJPF_RGBA, TJFLAG_FASTDCT | TJFLAG_STOPONWARNING) != 0)
		return rs_error_set(err, RS_ERR_PARSE, "jpeg: decode failed: %s",
		                    tjGetErrorStr2(jpeg->dec));
	return RS_OK;
}

enum rs_status rs_jpeg_write(const char *path, const uint8_t *rgba, uint32_t width, uint32_t height,
                             int quality, struct rs_error *err)
{
	RS_ASSERT(path && rgba);
	size_t cap = rs_jpeg_bound(width, height);
	if (cap == 0)
		return rs_error_set(err, RS_ERR_INVALID, "jpeg: image size %ux%u is out of range",
		                    width, height);
	struct rs_jpeg *jpeg = NULL;
	uint8_t *data = malloc(cap);
	size_t size = 0;
	enum rs_status st =
	    data ? rs_jpeg_create(&jpeg, err)
	         : rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory writing %s", path);
	if (st == RS_OK)
		st = rs_jpeg_encode(jpeg, rgba, width, height, quality, RS_JPEG_444, data, cap,
		                    &size, err);
	struct rs_atomic_file af;
	if (st == RS_OK && (st = rs_atomic_open(&af, path, err)) == RS_OK) {
		bool ok = fwrite(data, 1, size, af.f) == size;
		if (!ok)
			rs_error_set(err, RS_ERR_IO, "cannot write %s", path);
		st = rs_atomic_commit(&af, ok, err);
	}
	rs_jpeg_destroy(&jpeg);
	free(data);
	return st;
}
