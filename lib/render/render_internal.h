/* Private pieces of the render module shared by the generic renderer and the CPU backend. */
#ifndef RS_RENDER_INTERNAL_H
#define RS_RENDER_INTERNAL_H

#include "raystream/rs_render.h"

/* Copy a backend name or renderer string into a fixed field, truncating. */
void rs_render_copy_name(char *dst, size_t cap, const char *src);

#endif
