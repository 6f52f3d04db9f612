/* Dynamic resolution for a frame-rate target (app_pace.h). The rules, in frames so they
 * do not depend on the rate itself:
 *  - down one level after 3 frames in a row over the budget (a single slow frame, e.g. a
 *    page fault, does not cost resolution);
 *  - up one level after 20 frames in a row whose time, scaled by the next level's pixel
 *    count, still fits 80 % of the budget: the step up must not immediately miss it, and
 *    the gap between "over" and "fits at 80 %" is the hysteresis. */
#include <math.h>
#include <stddef.h>

#include "app_pace.h"

const double app_pace_scales[APP_PACE_LEVELS] = {1.0, 0.71, 0.5, 0.35, 0.25};

#define DOWN_AFTER 3
#define UP_AFTER 20
#define UP_HEADROOM 0.8

void app_pace_init(struct app_pace *p, double target_fps)
{
	*p = (struct app_pace){.budget_ms = target_fps > 0 ? 1000.0 / target_fps : 0.0};
}

static int step(struct app_pace *p, int by)
{
	p->level += by;
	p->avg_ms = 0.0;
	p->over = p->under = 0;
	if (by > 0)
		++p->steps_down;
	else
		++p->steps_up;
	return p->level;
}

int app_pace_update(struct app_pace *p, double frame_ms)
{
	if (p->budget_ms <= 0.0 || !(frame_ms >= 0.0) || !isfinite(frame_ms))
		return p->level;
	p->avg_ms = p->avg_ms > 0.0 ? 0.7 * p->avg_ms + 0.3 * frame_ms : frame_ms;
	p->over = frame_ms > p->budget_ms ? p->over + 1 : 0;
	if (p->over >= DOWN_AFTER && p->level + 1 < APP_PACE_LEVELS)
		return step(p, +1);
	if (p->level > 0) {
		double up = app_pace_scales[p->level - 1] / app_pace_scales[p->level];
		int fits = p->avg_ms * up * up <= UP_HEADROOM * p->budget_ms &&
		           frame_ms * up * up <= UP_HEADROOM * p->budget_ms;
		p->under = fits ? p->under + 1 : 0;
		if (p->under >= UP_AFTER)
			return step(p, -1);
	}
	return p->level;
}

static float texel(const uint8_t *src, uint32_t w, uint32_t h, long x, long y, int c)
{
	x = x < 0 ? 0 : x >= (long)w ? (long)w - 1 : x;
	y = y < 0 ? 0 : y >= (long)h ? (long)h - 1 : y;
	return src[((size_t)y * w + (size_t)x) * 4u + (size_t)c] * (1.0f / 255.0f);
}

void app_pace_resample(const uint8_t *src, uint32_t w, uint32_t h, uint8_t *dst, uint32_t dw,
                       uint32_t dh)
{
	float sx = (float)w / (float)dw, sy = (float)h / (float)dh;
	for (uint32_t y = 0; y < dh; ++y) {
		float fy = ((float)y + 0.5f) * sy - 0.5f;
		long iy = (long)floorf(fy);
		float ty = fy - (float)iy;
		for (uint32_t x = 0; x < dw; ++x) {
			float fx = ((float)x + 0.5f) * sx - 0.5f;
			long ix = (long)floorf(fx);
			float tx = fx - (float)ix;
			uint8_t *o = dst + ((size_t)y * dw + x) * 4u;
			for (int c = 0; c < 3; ++c) {
				float a = texel(src, w, h, ix, iy, c),
				      b = texel(src, w, h, ix + 1, iy, c);
				float d = texel(src, w, h, ix, iy + 1, c);
				float e = texel(src, w, h, ix + 1, iy + 1, c);
				float v = (a + (b - a) * tx) +
				          ((d + (e - d) * tx) - (a + (b - a) * tx)) * ty;
				v = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
				o[c] = (uint8_t)floorf(v * 255.0f + 0.5f);
			}
			o[3] = 255;
		}
	}
}

void app_pace_size(int level, uint32_t w, uint32_t h, uint32_t *out_w, uint32_t *out_h)
{
	double s = app_pace_scales[level < 0 ? 0 : level < APP_PACE_LEVELS ? level : 0];
	*out_w = (uint32_t)lround(w * s);
	*out_h = (uint32_t)lround(h * s);
	if (*out_w < 1)
		*out_w = 1;
	if (*out_h < 1)
		*out_h = 1;
}
