/* Still-pose refinement (apps/common/app_refine.c): a still pose walks the sub-pixel samples
 * 1, 2, 3 ... of one camera (the resting pose's), motion past the stated thresholds (0.5 mm,
 * 0.05 degrees), a new render scale or a recentre restart at sample 0, and the C mean of
 * byte frames is the running mean. Exit 0 = pass. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app_refine.h"

static int failures;
static void check(int cond, const char *what, const struct app_refine *r)
{
	printf("%s: %s (sample %u, %u restarts)\n", cond ? "ok" : "FAIL", what, r->sample,
	       r->restarts);
	failures += !cond;
}

/* the camera of a pose: its eye at the pose's position (any map will do here) */
static struct rs_camera cam_of(const struct rs_pose *p)
{
	struct rs_camera c = {.target = {0, 0, -1}, .up = {0, 1, 0}};
	memcpy(c.eye, p->position, sizeof c.eye);
	return c;
}

static uint32_t frame(struct app_refine *r, const struct rs_pose *p, int level)
{
	struct rs_camera c = cam_of(p);
	app_refine_camera(r, p, level, &c);
	return c.sample;
}

int main(void)
{
	struct app_refine r = {.enabled = 1};
	struct rs_pose p = {.position = {0.1, 0.2, 0.3}, .orientation = {0, 0, 0, 1}};
	int seq = 1;
	for (uint32_t k = 0; k < 5; ++k)
		seq &= frame(&r, &p, 0) == k;
	check(seq, "a still pose: samples 0, 1, 2, 3, 4", &r);
	struct rs_pose q = p;
	q.position[0] += 0.0004; /* 0.4 mm: within the threshold */
	struct rs_camera c = cam_of(&q);
	app_refine_camera(&r, &q, 0, &c);
	check(c.sample == 5 && c.eye[0] == p.position[0],
	      "0.4 mm: still, and the resting pose's camera is rendered", &r);
	q.position[0] = p.position[0] + 0.0006; /* 0.6 mm */
	check(frame(&r, &q, 0) == 0 && r.restarts == 1, "0.6 mm: restart at sample 0", &r);
	check(frame(&r, &q, 0) == 1, "then still again: sample 1", &r);
	struct rs_pose t = q; /* 0.1 degrees about y */
	double h = 0.1 * 3.14159265358979323846 / 360.0;
	t.orientation[1] = sin(h), t.orientation[3] = cos(h);
	check(frame(&r, &t, 0) == 0, "0.1 degrees: restart", &r);
	struct rs_pose s = t; /* 0.04 degrees more */
	h = 0.14 * 3.14159265358979323846 / 360.0;
	s.orientation[1] = sin(h), s.orientation[3] = cos(h);
	check(frame(&r, &s, 0) == 1, "0.04 degrees: still", &r);
	check(frame(&r, &s, 2) == 0, "another render scale: restart", &r);
	app_refine_restart(&r);
	check(frame(&r, &s, 2) == 0, "recentred: restart", &r);
	struct app_refine off = {.enabled = 0};
	check(frame(&off, &p, 0) == 0 && frame(&off, &p, 0) == 0, "disabled: always sample 0",
	      &off);

	/* the C mean: frames 10, 20, 60 average to 30; a sample-0 frame restarts it */
	uint8_t px[4] = {10, 10, 10, 255};
	r.sample = 0;
	int mean = app_refine_add(&r, px, 1, 1) == 0 && px[0] == 10;
	px[0] = 20, r.sample = 1;
	mean &= app_refine_add(&r, px, 1, 1) == 0 && px[0] == 15;
	px[0] = 60, r.sample = 2;
	mean &= app_refine_add(&r, px, 1, 1) == 0 && px[0] == 30 && px[3] == 255;
	check(mean, "byte frames 10, 20, 60: shown 10, 15, 30", &r);
	px[0] = 200, r.sample = 0;
	check(app_refine_add(&r, px, 1, 1) == 0 && px[0] == 200, "sample 0 starts a new mean", &r);
	app_refine_free(&r);
	printf("%s\n", failures ? "FAILED" : "all passed");
	return failures ? 1 : 0;
}
