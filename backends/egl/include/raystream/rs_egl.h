/**
 * @file rs_egl.h
 * The GLES ray tracer (rs_gles.h) on a headless EGL context: GLES 3.0 or later, no window
 * system. Platforms, tried in this order unless one is named: "device"
 * (EGL_EXT_platform_device: NVIDIA headless, Mesa's software device), "gbm" (a DRM render
 * node through GBM), "surfaceless" (EGL_MESA_platform_surfaceless: Mesa, llvmpipe without
 * a GPU). rs_render_desc.egl_platform, else the RS_EGL_PLATFORM environment variable,
 * names one ("device", "gbm", "surfaceless") and then only that one is tried.
 */
#ifndef RS_EGL_H
#define RS_EGL_H

#include "raystream/rs_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Open an EGL context and make a GLES renderer on it (rs_renderer_destroy() frees both).
 * RS_ERR_DEVICE: no EGL display or no GLES 3 context on any platform tried (the message
 * names the platforms and the last EGL error); RS_ERR_INVALID: an unknown platform name;
 * RS_ERR_UNSUPPORTED: the context lacks float render targets.
 */
enum rs_status rs_renderer_create_egl(const struct rs_render_desc *desc, struct rs_renderer **out,
                                      struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
