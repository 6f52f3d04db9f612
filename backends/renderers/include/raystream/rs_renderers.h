/**
 * @file rs_renderers.h
 * Open a renderer by backend name (module rs_renderers, above every render backend):
 *
 *   cpu      the double-precision CPU reference (always built)
 *   egl      the GLES kernels on a headless EGL context (surfaceless, device or GBM)
 *   osmesa   the GLES kernels on an OSMesa context
 *
 * The result is an rs_renderer (rs_render.h): set_scene, render, stats, destroy.
 */
#ifndef RS_RENDERERS_H
#define RS_RENDERERS_H

#include <stdbool.h>

#include "raystream/rs_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Create the renderer `backend` names (NULL or "" -> "cpu"). RS_ERR_INVALID for an unknown
 * name, RS_ERR_UNSUPPORTED for a backend this build lacks, else the backend's status; a
 * one-line message in `err` either way. Destroy with rs_renderer_destroy().
 */
enum rs_status rs_renderer_open(const char *backend, const struct rs_render_desc *desc,
                                struct rs_renderer **out, struct rs_error *err);

/** Whether this build has the backend `name` ("cpu", "egl", "osmesa"). */
bool rs_renderer_has_backend(const char *name);

/** Comma-separated names of the backends this build has, e.g. "cpu,egl,osmesa". */
const char *rs_renderer_backends(void);

#ifdef __cplusplus
}
#endif
#endif
