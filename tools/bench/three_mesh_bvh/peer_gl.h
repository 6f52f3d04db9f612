/* raystream-peer-tmb's GL side: a headless EGL context of its own (not the renderer's), the
 * packed textures tools/bench/three_mesh_bvh/build_bvh.mjs wrote, and one fragment program
 * made of three-mesh-bvh's own GLSL chunks and a main that makes our camera ray per pixel
 * and calls its bvhIntersectFirstHit. This is a peer harness, not a renderer: it talks to
 * the driver itself, as the Embree peer (../embree/) talks to Embree, so that nothing of
 * the peer enters backends/gles. */
#ifndef RS_PEER_GL_H
#define RS_PEER_GL_H

#include <stdint.h>

#include "raystream/rs_status.h"
#include "raystream/rs_trace.h"

struct peer_gl;

/* Open the context, read DIR's textures.txt (one "NAME FORMAT WIDTH HEIGHT" per line, each
 * NAME.bin raw texels) and DIR/bvh.glsl, compile the program for a width x height image. */
enum rs_status peer_gl_create(const char *dir, uint32_t width, uint32_t height,
                              struct peer_gl **out, struct rs_error *err);
void peer_gl_destroy(struct peer_gl **gl);

/* GL_RENDERER of the peer's context. */
const char *peer_gl_renderer(const struct peer_gl *gl);

/* One frame of primary rays from `view` (glFinish'ed): its wall time in ms. */
enum rs_status peer_gl_trace(struct peer_gl *gl, const struct rs_trace_view *view, double *out_ms,
                             struct rs_error *err);

/* The last frame's hits, row 0 = top: the peer's triangle slot (UINT32_MAX on a miss) and
 * distance per pixel (either may be NULL). */
enum rs_status peer_gl_read(struct peer_gl *gl, uint32_t *out_slot, float *out_dist,
                            struct rs_error *err);

#endif
