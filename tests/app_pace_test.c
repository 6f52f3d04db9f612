/* The viewer's frame-rate target (apps/common/app_pace.c) under forced frame times: over
 * budget it steps the render scale down, with headroom back up, one level at a time, and a
 * time near the budget or one slow frame changes nothing (hysteresis). Functional: the
 * frame times are given, nothing is timed. Exit 0 = pass. */
#include <stdio.h>

#include "app_pace.h"

static int failures;
static void check(int cond, const char *what, const struct app_pace *p)
{
	printf("%s: %s (level %d, %u down, %u up)\n", cond ? "ok" : "FAIL", what, p->level,
	       p->steps_down, p->steps_up);
	failures += !cond;
}

static int feed(struct app_pace *p, double ms, int n)
{
	int level = p->level;
	for (int i = 0; i < n; ++i)
		level = app_pace_update(p, ms);
	return level;
}

int main(void)
{
	struct app_pace p;
	app_pace_init(&p, 30.0);
	check(feed(&p, 20.0, 50) == 0, "within budget: full size", &p);
	check(feed(&p, 100.0, 1) == 0 && feed(&p, 20.0, 5) == 0, "one slow frame: no step", &p);
	check(feed(&p, 100.0, 3) == 1, "three frames over budget: one step down", &p);
	int down = feed(&p, 100.0, 30);
	check(down == APP_PACE_LEVELS - 1, "still over: down to the smallest scale", &p);
	check(p.steps_down == APP_PACE_LEVELS - 1, "one level per step", &p);
	check(feed(&p, 5.0, 19) == APP_PACE_LEVELS - 1, "headroom: not before 20 frames", &p);
	int up = APP_PACE_LEVELS - 1;
	for (int i = 0; i < 40 && up == APP_PACE_LEVELS - 1; ++i)
		up = app_pace_update(&p, 5.0);
	check(up == APP_PACE_LEVELS - 2 && p.steps_up == 1, "headroom: one step up", &p);
	check(feed(&p, 5.0, 200) == 0, "headroom: back up to full size", &p);
	/* at level 1 a 30 ms frame fits 33 ms but would not at level 0 (x2 pixels): stays */
	app_pace_init(&p, 30.0);
	feed(&p, 100.0, 3);
	check(feed(&p, 30.0, 500) == 1, "near the budget: no flicker between levels", &p);
	check(p.steps_up == 0 && p.steps_down == 1, "exactly one step in all", &p);
	uint32_t w = 0, h = 0;
	app_pace_size(2, 256, 256, &w, &h);
	check(w == 128 && h == 128, "scale 0.5 of 256x256 is 128x128", &p);
	app_pace_init(&p, 0.0);
	check(feed(&p, 1000.0, 50) == 0, "no target: always full size", &p);
	return failures ? 1 : 0;
}
