/*
 * xwd_compare XWD PNG X Y: compare the PNG with the X, Y corner of an xwd screenshot
 * (TrueColor, 24 or 32 bits per pixel: what Xvfb gives). Prints the largest channel
 * difference and the share of differing pixels; exit 0 when every channel is within 1,
 * 1 when they differ, 2 when a file cannot be read.
 * xwd_compare XWD PNG X Y MIN_DB: the same, and exit 0 when the PSNR (8-bit RGB) is at
 * least MIN_DB instead (a render of the same camera by another backend, not the bytes).
 * xwd_compare XWD --lit X Y W H: exit 0 when some pixel of that rectangle has a channel
 * above 128 (text was drawn there), else 1.
 * The screenshot may also be a PNG (a file ending in .png: a headless viewer's frame),
 * compared the same way.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_image.h"

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int shift_of(uint32_t mask)
{
	int s = 0;
	while (mask && !(mask & 1u)) {
		mask >>= 1;
		++s;
	}
	return s;
}

int main(int argc, char **argv)
{
	int lit = argc == 7 && !strcmp(argv[2], "--lit");
	if (argc != 5 && argc != 6 && !lit) {
		fprintf(stderr,
		        "usage: xwd_compare XWD PNG X Y [MIN_DB] | xwd_compare XWD --lit X Y "
		        "W H\n");
		return 2;
	}
	size_t len = strlen(argv[1]);
	uint8_t *shot = NULL; /* a PNG screenshot, RGB */
	uint32_t width = 0, height = 0;
	struct rs_error err = {0};
	if (len > 4 && !strcmp(argv[1] + len - 4, ".png")) {
		if (lit || rs_image_read_png(argv[1], &shot, &width, &height, &err) != RS_OK) {
			fprintf(stderr, "xwd_compare: %s\n",
			        lit ? "--lit wants an XWD" : err.message);
			return 2;
		}
	}
	static uint8_t buf[64 << 20];
	uint32_t h[25] = {0};
	size_t data = 0;
	FILE *f = shot ? NULL : fopen(argv[1], "rb");
	if (!shot && !f) {
		fprintf(stderr, "xwd_compare: cannot open %s\n", argv[1]);
		return 2;
	}
	size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
	if (f)
		fclose(f);
	if (!shot && n < 100) {
		fprintf(stderr, "xwd_compare: %s is too short\n", argv[1]);
		return 2;
	}
	for (int i = 0; !shot && i < 25; ++i)
		h[i] = be32(buf + 4 * i);
	uint32_t header = h[0], format = h[2], order = h[7];
	uint32_t bpp = h[11], bpl = h[12], rmask = h[14], gmask = h[15], bmask = h[16];
	uint32_t ncolors = h[19];
	if (!shot) {
		width = h[4];
		height = h[5];
		data = (size_t)header + (size_t)ncolors * 12u;
	}
	if (!shot && (format != 2 || (bpp != 32 && bpp != 24) || data + (size_t)bpl * height > n)) {
		fprintf(stderr, "xwd_compare: unsupported or truncated XWD (format %u, %u bpp)\n",
		        format, bpp);
		return 2;
	}
	uint8_t *png = NULL;
	uint32_t pw = 0, ph = 0;
	if (lit) {
		uint32_t x0 = (uint32_t)atoi(argv[3]), y0 = (uint32_t)atoi(argv[4]);
		uint32_t rw = (uint32_t)atoi(argv[5]), rh = (uint32_t)atoi(argv[6]), count = 0;
		for (uint32_t y = y0; y < y0 + rh && y < height; ++y)
			for (uint32_t x = x0; x < x0 + rw && x < width; ++x)
				for (uint32_t b = 0; b < 3;
				     ++b) /* 8-bit channels of 24/32-bit TrueColor */
					count += buf[data + (size_t)y * bpl +
					             (size_t)x * (bpp / 8) + b] > 128;
		printf("xwd_compare: %u bright channels in %ux%u at %u,%u\n", count, rw, rh, x0,
		       y0);
		return count > 0 ? 0 : 1;
	}
	if (rs_image_read_png(argv[2], &png, &pw, &ph, &err) != RS_OK) {
		fprintf(stderr, "xwd_compare: %s\n", err.message);
		return 2;
	}
	uint32_t x0 = (uint32_t)atoi(argv[3]), y0 = (uint32_t)atoi(argv[4]);
	if (x0 + pw > width || y0 + ph > height) {
		fprintf(stderr, "xwd_compare: %ux%u at %u,%u is outside the %ux%u screenshot\n", pw,
		        ph, x0, y0, width, height);
		free(png);
		free(shot);
		return 2;
	}
	int maxd = 0;
	uint64_t differ = 0;
	double sq = 0.0;
	for (uint32_t y = 0; y < ph; ++y)
		for (uint32_t x = 0; x < pw; ++x) {
			int got[3];
			if (shot) {
				const uint8_t *q = shot + 3 * ((size_t)(y0 + y) * width + x0 + x);
				for (int c = 0; c < 3; ++c)
					got[c] = q[c];
			} else {
				const uint8_t *p = buf + data + (size_t)(y0 + y) * bpl +
				                   (size_t)(x0 + x) * (bpp / 8);
				uint32_t v = 0;
				for (uint32_t b = 0; b < bpp / 8; ++b) /* byte order 0: LSB first */
					v |= (uint32_t)p[order == 0 ? b : bpp / 8 - 1 - b]
					     << (8 * b);
				got[0] = (int)((v & rmask) >> shift_of(rmask));
				got[1] = (int)((v & gmask) >> shift_of(gmask));
				got[2] = (int)((v & bmask) >> shift_of(bmask));
			}
			int bad = 0;
			for (int c = 0; c < 3; ++c) {
				int d = abs(got[c] - png[3 * ((size_t)y * pw + x) + c]);
				if (d > maxd)
					maxd = d;
				sq += (double)d * d;
				bad |= d > 1;
			}
			differ += (uint64_t)bad;
		}
	double mse = sq / (3.0 * pw * ph);
	double psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : 99.0;
	printf("xwd_compare: %ux%u at %u,%u: max channel difference %d, %llu pixels differ, "
	       "PSNR %.1f dB\n",
	       pw, ph, x0, y0, maxd, (unsigned long long)differ, psnr);
	free(png);
	free(shot);
	if (argc == 6)
		return psnr >= atof(argv[5]) ? 0 : 1;
	return maxd <= 1 ? 0 : 1;
}
