/* Still-pose refinement: stillness, the sample sequence and the C running mean. */
#include "app_refine.h"

#include <math.h>
#include <stdlib.h>

#include "raystream/rs_image.h"
#include "raystream/rs_status.h"

int app_refine_is_still(const struct rs_pose *a, const struct rs_pose *b)
{
	double d2 = 0.0, dot = 0.0;
	for (int i = 0; i < 3; ++i)
		d2 += (a->position[i] - b->position[i]) * (a->position[i] - b->position[i]);
	for (int i = 0; i < 4; ++i)
		dot += a->orientation[i] * b->orientation[i];
	/* the rotation between two unit quaternions: 2 acos |q1 . q2| */
	double deg = 2.0 * acos(fmin(1.0, fabs(dot))) * (180.0 / RS_PI);
	return isfinite(d2) && isfinite(deg) && sqrt(d2) * 1e3 <= APP_REFINE_STILL_MM &&
	       deg <= APP_REFINE_STILL_DEG;
}

void app_refine_camera(struct app_refine *r, const struct rs_pose *pose, int level,
                       struct rs_camera *cam)
{
	cam->sample = 0;
	if (!r->enabled)
		return;
	if (r->have && level == r->level && app_refine_is_still(&r->anchor, pose)) {
		if (r->sample + 1 < APP_REFINE_MAX_SAMPLES)
			++r->sample;
		*cam = r->camera;
		cam->sample = r->sample;
		return;
	}
	if (r->have && r->sample > 0)
		++r->restarts;
	r->have = 1;
	r->anchor = *pose;
	r->camera = *cam;
	r->level = level;
	r->sample = 0;
}

int app_refine_mean(float **acc, uint32_t sample, uint8_t *rgba, uint32_t w, uint32_t h)
{
	size_t n = (size_t)w * h;
	if (!*acc) {
		*acc = malloc(n * 3 * sizeof **acc);
		if (!*acc)
			return -1;
		sample = 0; /* nothing to add to */
	}
	/* the running mean m_k = m_{k-1} + (x_k - m_{k-1}) / (k + 1): no sum to overflow,
	 * the same rule as accumulate.glsl */
	float wgt = 1.0f / (float)((double)sample + 1.0);
	float *m = *acc;
	for (size_t i = 0; i < n; ++i) {
		for (int c = 0; c < 3; ++c) {
			float x = rgba[4 * i + c] * (1.0f / 255.0f);
			float *mc = &m[3 * i + c];
			*mc = sample == 0 ? x : *mc + (x - *mc) * wgt;
			rgba[4 * i + c] = rs_image_quantize_value(*mc);
		}
	}
	return 0;
}

int app_refine_add(struct app_refine *r, uint8_t *rgba, uint32_t w, uint32_t h)
{
	if (r->acc && (r->acc_w != w || r->acc_h != h)) { /* a new size: a new level, sample 0 */
		free(r->acc);
		r->acc = NULL;
	}
	r->acc_w = w;
	r->acc_h = h;
	return app_refine_mean(&r->acc, r->sample, rgba, w, h);
}

void app_refine_restart(struct app_refine *r)
{
	r->have = 0;
}

uint32_t app_refine_samples(const struct app_refine *r)
{
	return r->enabled ? r->sample + 1 : 1;
}

void app_refine_free(struct app_refine *r)
{
	free(r->acc);
	r->acc = NULL;
	r->acc_w = r->acc_h = 0;
}
