/**
 * @file rs_gles.h
 * The GLES 3.0 fragment-kernel ray tracer (the paper's stream tracer) as a render backend
 * (rs_render.h), over any GL context a small context interface provides: backends/egl
 * (GLES 3 through EGL, headless) and backends/osmesa (desktop GL with "#version 300 es"
 * kernels) only make a context and hand it over; this module is the only one that draws.
 * Where the context has buffer textures (GLES 3.2, 3.1 with OES/EXT_texture_buffer, desktop
 * GL with ARB_ES3_2_compatibility) the scene goes into them by default and the kernels
 * compile as ES 3.20 (rs_render_desc.scene_storage); GLES 3.0 is all that is required.
 *
 * GL state: every call makes the context current, draws into the renderer's own
 * framebuffers and textures and releases the context before returning. It changes and
 * does not restore: the bound program, vertex array, framebuffer and renderbuffer, the
 * viewport, the textures bound to units 0..15 (2D, 2D-array, buffer and, with
 * RS_REFLECT_ENVMAP or RS_REFLECT_INTERREFLECT, cube-map targets) and the active texture unit,
 * the GL_TEXTURE_BUFFER buffer binding (left 0), GL_PACK_ALIGNMENT (4),
 * depth function and mask, and disables GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST,
 * GL_DITHER (which would change results). A context the caller shares must be set up again by the
 * caller after a render (docs/gles.md).
 */
#ifndef RS_GLES_H
#define RS_GLES_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where frames go in a window's default framebuffer: its size and the image's rectangle
 *  (x, y from the top-left corner, in pixels). */
struct rs_gles_display_target {
	uint32_t fb_width, fb_height;
	int32_t x, y;
	uint32_t width, height;
};

/** What a context backend provides. `ctx` is the backend's own state. */
struct rs_gl_context_ops {
	const char *backend; /**< "egl", "osmesa": becomes rs_render_stats.backend */
	/** Make the context current on the calling thread. */
	enum rs_status (*make_current)(void *ctx, struct rs_error *err);
	/** Release it from the calling thread. */
	void (*release)(void *ctx);
	/** A GL entry point by name ("glDrawArrays"), NULL when missing; context current. */
	void *(*get_proc_address)(void *ctx, const char *name);
	/** Describe the platform ("EGL surfaceless") into out (never NULL, NUL-terminated). */
	void (*describe)(const void *ctx, char *out, size_t cap);
	/** Destroy the context and `ctx` itself. */
	void (*destroy)(void *ctx);
	/** Optional, for a context on a window (backends/window): where each frame is shown.
	 *  When set, every render also runs the display step into the default framebuffer
	 *  (make_current binds the window surface) and calls swap; no readback is needed to
	 *  show a frame. NULL for headless contexts. */
	void (*display_target)(const void *ctx, struct rs_gles_display_target *out);
	/** Optional, with display_target: show what was drawn (eglSwapBuffers). */
	enum rs_status (*swap)(void *ctx, struct rs_error *err);
};

/**
 * Make a renderer drawing through the context. On success the renderer owns `ctx`
 * (ops->destroy runs when it is destroyed); on failure ops->destroy(ctx) has already run.
 * Fails with RS_ERR_UNSUPPORTED when the context is not GLES 3.0 (or desktop GL with
 * ARB_ES3_compatibility) or cannot render to float textures.
 */
enum rs_status rs_gles_renderer_create(const struct rs_gl_context_ops *ops, void *ctx,
                                       const struct rs_render_desc *desc, struct rs_renderer **out,
                                       struct rs_error *err);

/**
 * The display step on its own, for frames that come as RGBA8 bytes (a decoded remote frame,
 * a CPU or OSMesa render): the same kernel (present.glsl) that shows a renderer's frames
 * on a window context. Create with the window's context current; entry points are loaded
 * through `get_proc_address` (never linked, as for the renderer). Destroy with the same
 * context current; accepts NULL.
 */
struct rs_gles_display;
enum rs_status rs_gles_display_create(void *(*get_proc_address)(void *ctx, const char *name),
                                      void *ctx, struct rs_gles_display **out,
                                      struct rs_error *err);
void rs_gles_display_destroy(struct rs_gles_display **display);

/**
 * Draw an RGBA8 image (row 0 = top) into the current context's default framebuffer: black
 * outside `to`'s rectangle, the image scaled into it (exact bytes at scale 1). Uploads the
 * image; the caller swaps. Changes the bound program, vertex array, framebuffer (0),
 * texture unit 0 and the viewport.
 */
enum rs_status rs_gles_display_rgba8(struct rs_gles_display *display, const uint8_t *rgba,
                                     uint32_t width, uint32_t height,
                                     const struct rs_gles_display_target *to, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
