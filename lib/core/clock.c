/* The one monotonic clock (rs_status.h): every duration and deadline in the tree reads it. */
#include <time.h>

#include "raystream/rs_status.h"

double rs_now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}
