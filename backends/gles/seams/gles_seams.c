/* Test seams (gles_seams.h; test builds only): one kernel's source replaced, to check that a
 * compile error names the file and line; cube map captures forced onto their readback
 * fallback, to compare it with the GPU path; frames forced onto the display pass, to compare
 * it with the last fused pass writing the RGBA8 colour; a context made to answer that it has
 * no compute shaders. */
#include <string.h>

#include "gles_seams.h"

static const char *override_name, *override_source;

void rs__gles_override_kernel(const char *name, const char *source)
{
	override_name = name;
	override_source = source;
}

const char *rs__gles_kernel_override(const char *name)
{
	return override_name && strcmp(override_name, name) == 0 ? override_source : NULL;
}

static bool capture_readback;

void rs__gles_force_capture_readback(bool on)
{
	capture_readback = on;
}

bool rs__gles_capture_readback(void)
{
	return capture_readback;
}

static bool display_unfused;

void rs__gles_force_display_unfused(bool on)
{
	display_unfused = on;
}

bool rs__gles_display_unfused(void)
{
	return display_unfused;
}

static bool no_compute;

void rs__gles_force_no_compute(bool on)
{
	no_compute = on;
}

bool rs__gles_no_compute(void)
{
	return no_compute;
}
