/* Test seam (gles_seams.h; test builds only): one kernel's source replaced, to check that a
 * compile error names the file and line. */
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
