/* A frame-rate target by dynamic resolution (the viewer's --target-fps): from the time each
 * frame took, choose the fraction of the window's size to render at. Steps down when the
 * budget is missed, back up only with clear headroom (hysteresis), so a frame time near
 * the budget does not make the scale flicker. No clock inside: the caller passes times, so
 * tests drive it with forced budgets. */
#ifndef RS_APP_PACE_H
#define RS_APP_PACE_H

#include <stdint.h>

/* The render scales, largest first (each about half the pixels of the one before). */
#define APP_PACE_LEVELS 5
extern const double app_pace_scales[APP_PACE_LEVELS];

struct app_pace {
	double budget_ms; /* 1000 / target fps; 0: no target (level stays 0) */
	int level;        /* index into app_pace_scales */
	double avg_ms;    /* recent frame time at this level (exponential average) */
	int over, under;  /* consecutive frames over budget / with headroom */
	uint32_t steps_down, steps_up;
};

/* target_fps 0: no target. */
void app_pace_init(struct app_pace *p, double target_fps);

/* Account one frame that took `frame_ms` at the current level; returns the level for the
 * next frame (changed at most one step, and the average restarts after a step). */
int app_pace_update(struct app_pace *p, double frame_ms);

/* The render size at `level` for a w x h window: the scale applied, at least 1 pixel. */
void app_pace_size(int level, uint32_t w, uint32_t h, uint32_t *out_w, uint32_t *out_h);

/* Scale RGBA8 image `src` (w x h, row 0 = top) up or down to `dst` (dw x dh) with the
 * bilinear filter and rounding of the display step (present.glsl: texel centres, edges
 * clamped), for frames that arrive smaller (a server's --target-fps) and must be full size
 * in files. Alpha is 255. */
void app_pace_resample(const uint8_t *src, uint32_t w, uint32_t h, uint8_t *dst, uint32_t dw,
                       uint32_t dh);

#endif
