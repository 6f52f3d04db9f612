/**
 * @file rs_osmesa.h
 * The GLES ray tracer (rs_gles.h) on an OSMesa context: Mesa's off-screen desktop GL
 * (core profile 3.3 or later) running the same "#version 300 es" kernels through
 * ARB_ES3_compatibility (320 es through ARB_ES3_2_compatibility with the scene in buffer
 * textures). No display, no EGL: for machines where only libOSMesa exists.
 */
#ifndef RS_OSMESA_H
#define RS_OSMESA_H

#include "raystream/rs_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Open an OSMesa context and make a GLES renderer on it (rs_renderer_destroy() frees both).
 * RS_ERR_DEVICE: no GL 3.3 core context; RS_ERR_UNSUPPORTED: no ARB_ES3_compatibility.
 */
enum rs_status rs_renderer_create_osmesa(const struct rs_render_desc *desc,
                                         struct rs_renderer **out, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
