/* Still-pose refinement (docs/view.md): while the handheld's pose stays within
 * APP_REFINE_STILL_MM and APP_REFINE_STILL_DEG of the pose where it came to rest, every
 * frame renders the camera of that pose at the next sub-pixel sample (rs_camera.sample,
 * the R2 sequence of rs_trace_sample_offset()) and the frames are averaged: antialiasing
 * that converges to the supersampled image. Any larger motion, a change of render scale
 * or of the camera itself restarts at sample 0. The average lives on the GPU for a
 * renderer drawing into the window (gles_display.c, accumulate.glsl) and here, in C, for
 * frames that arrive as bytes (CPU, OSMesa, readback). No clock inside. */
#ifndef RS_APP_REFINE_H
#define RS_APP_REFINE_H

#include <stdint.h>

#include "raystream/rs_scene.h"
#include "raystream/rs_track_types.h"

/* Still: the pose moved less than this from where the accumulation started. 0.5 mm and
 * 0.05 degrees are above a good tracker's filtered noise and below what moves the image
 * of a scene a metre away by a pixel of a 512-px, 45-degree view (about 1.5 mm, 0.09°). */
#define APP_REFINE_STILL_MM 0.5
#define APP_REFINE_STILL_DEG 0.05
/* The sample number stops here (it never wraps to 0, which would restart); the running
 * mean keeps taking frames with weight 1 / (n + 1), so a capped count would pull it
 * towards one sample's image instead. */
#define APP_REFINE_MAX_SAMPLES 0xfffffff0u

struct app_refine {
	int enabled;
	int have;                /* anchor and camera are set */
	struct rs_pose anchor;   /* the pose the accumulation started at */
	struct rs_camera camera; /* its camera: every refining frame renders this one */
	int level;               /* the render scale the accumulation is at */
	uint32_t sample;         /* the sample of the frame app_refine_camera() gave last */
	uint32_t restarts;
	/* the C average (app_refine_add) */
	float *acc;
	uint32_t acc_w, acc_h;
};

/* Whether `a` and `b` are within the still thresholds of each other. */
int app_refine_is_still(const struct rs_pose *a, const struct rs_pose *b);

/* The camera of the next frame into *cam, for `pose` and the camera made from it at
 * render scale `level`: cam itself with sample 0 on motion (a new anchor), else the
 * anchor's camera with the next sample. Disabled: cam is left as it is (sample 0). */
void app_refine_camera(struct app_refine *r, const struct rs_pose *pose, int level,
                       struct rs_camera *cam);

/* The running mean of byte frames in *acc (w * h * 3 floats; allocated when NULL, which
 * starts the mean): frame `sample` (0 starts it again) is added with weight 1 / (sample + 1)
 * and the mean, rounded, written back into `rgba`. Returns 0, or -1 when out of memory. */
int app_refine_mean(float **acc, uint32_t sample, uint8_t *rgba, uint32_t w, uint32_t h);

/* Start again at the next frame whatever the pose (the view was recentred). */
void app_refine_restart(struct app_refine *r);

/* Average a w x h RGBA8 frame rendered with sample r->sample into the running mean (a
 * sample 0 frame starts it) and write the mean, rounded, back into `rgba`. Returns 0, or
 * -1 when out of memory (the frame is then left as rendered). */
int app_refine_add(struct app_refine *r, uint8_t *rgba, uint32_t w, uint32_t h);

/* Samples in the image shown after the frame of r->sample: r->sample + 1. */
uint32_t app_refine_samples(const struct app_refine *r);

void app_refine_free(struct app_refine *r);

#endif
