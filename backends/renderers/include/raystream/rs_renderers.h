/**
 * @file rs_renderers.h
 * Open a renderer by backend name (module rs_renderers, above every render backend):
 *
 *   cpu      the double-precision CPU reference (always built)
 *   egl      the GLES kernels on a headless EGL context (surfaceless, device or GBM)
 *   osmesa   the GLES kernels on an OSMesa context
 *   auto     egl where a context opens, else osmesa, else cpu (the default everywhere)
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
 * Create the renderer `backend` names (NULL or "": desc->backend, else "auto").
 * RS_ERR_INVALID for an unknown name, RS_ERR_UNSUPPORTED for a backend this build lacks,
 * else the backend's status; a one-line message in `err` either way. Destroy with
 * rs_renderer_destroy(). "auto" falls back to cpu only when no GL context opens
 * (RS_ERR_DEVICE or RS_ERR_UNSUPPORTED from egl and osmesa); rs_renderer_backend() names
 * the one opened.
 */
enum rs_status rs_renderer_open(const char *backend, const struct rs_render_desc *desc,
                                struct rs_renderer **out, struct rs_error *err);

/**
 * rs_renderer_open(), and when "auto" fell back to cpu, one line in `out_note` saying so
 * and why ("auto: no GL context opened (egl: ...); rendering on cpu"); otherwise
 * `out_note` is cleared (empty message). The library never prints: a program shows the
 * line (on stderr) so a user is not left guessing why a frame is slow. NULL: no note.
 */
enum rs_status rs_renderer_open_noted(const char *backend, const struct rs_render_desc *desc,
                                      struct rs_renderer **out, struct rs_error *out_note,
                                      struct rs_error *err);

/** Whether this build has the backend `name` ("auto", "cpu", "egl", "osmesa"). */
bool rs_renderer_has_backend(const char *name);

/** Comma-separated names of the backends this build has, e.g. "cpu,egl,osmesa". */
const char *rs_renderer_backends(void);

#ifdef __cplusplus
}
#endif
#endif
