/* Classic environment mapping (RS_REFLECT_ENVMAP, the paper's Table 3 comparison): one cube
 * map captured once at set_scene from the centre of the scene's bounds, each face the
 * traced image of 1 pass (local shading, shadows, environment) seen with a 90-degree
 * camera; from the second pass on, rays read it by direction instead of being traced. The
 * faces are frames of their own plans (PLAN_ENVMAP here, the bounces' in
 * gles_interreflect.c), run as the frame's plan is, g->face_size texels a side: the
 * renderer's descriptor is never touched. Each face's colour is then copied into its cube
 * face on the GPU (a blit into the face as a colour attachment); only where the probe finds
 * an RGBA16F face no render target is it read back and uploaded (docs/gles.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"
#include "gles_seams.h"

/* GL's cube face conventions (ES 3.0 table 3.21): the major axis and the directions in
 * which the face's s and t coordinates grow. */
static const double faces[6][3][3] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
    {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
};

enum rs_status rs_gles_cube_alloc(struct gles *g, GLuint tex, const char *what,
                                  struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	GLsizei n = (GLsizei)g->face_size;
	gl->ActiveTexture(GL_TEXTURE0 + UNIT_ENVMAP);
	gl->BindTexture(GL_TEXTURE_CUBE_MAP, tex);
	/* RGBA, not RGB: RGB16F is no colour attachment even with EXT_color_buffer_float. */
	gl->TexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_RGBA16F, n, n);
	enum rs_status st = rs_gles_allocated(gl, what, GL_RGBA16F, n, n, 6, err);
	gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
	gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
	gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
	return st;
}

/* The fallback where a cube face is no render target: face `f` read back, its columns
 * reversed with `mirror`, uploaded. */
static enum rs_status upload_face(struct gles *g, const struct rs_gles_plan *plan, GLuint tex,
                                  int f, bool mirror, float *face, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	uint32_t n = g->face_size;
	enum rs_status st = rs_gles_read_face(g, plan, (GLsizei)n, err);
	for (uint32_t y = 0; st == RS_OK && y < n; ++y)
		for (uint32_t x = 0; x < n; ++x)
			memcpy(&face[((size_t)y * n + x) * 4],
			       &g->scratch[((size_t)y * n + (mirror ? n - 1 - x : x)) * 4],
			       4 * sizeof(float));
	if (st == RS_OK) {
		gl->ActiveTexture(GL_TEXTURE0 + UNIT_ENVMAP);
		gl->BindTexture(GL_TEXTURE_CUBE_MAP, tex);
		gl->TexSubImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)f, 0, 0, 0, (GLsizei)n,
		                  (GLsizei)n, GL_RGBA, GL_FLOAT, face);
	}
	return st;
}

enum rs_status rs_gles_capture_cube(struct gles *g, const struct rs_gles_plan *plan,
                                    const double eye[3], float near, GLuint tex,
                                    struct rs_error *err)
{
	uint32_t n = g->face_size;
	float *face = NULL;
	enum rs_status st = RS_OK;
	if (!g->face_direct && !(face = malloc((size_t)n * n * 4 * sizeof(float))))
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory for a cube map");
	for (int f = 0; f < 6 && st == RS_OK; ++f) {
		/* up = -t: image row 0 is the face's t = 0 row; the camera's right (forward x
		 * up) is then either +s or -s, and the columns are mirrored when it is -s. */
		struct rs_camera cam = {.fov_y_deg = 90.0, .width = n, .height = n};
		const double *ax = faces[f][0], *sd = faces[f][1], *td = faces[f][2];
		for (int a = 0; a < 3; ++a) {
			cam.eye[a] = eye[a];
			cam.target[a] = cam.eye[a] + ax[a];
			cam.up[a] = -td[a];
		}
		double right[3] = {ax[1] * cam.up[2] - ax[2] * cam.up[1],
		                   ax[2] * cam.up[0] - ax[0] * cam.up[2],
		                   ax[0] * cam.up[1] - ax[1] * cam.up[0]};
		bool mirror = right[0] * sd[0] + right[1] * sd[1] + right[2] * sd[2] < 0.0;
		struct rs_render_stats stats = {0};
		st = rs_gles_plan_run(g, plan, &cam, near, (GLsizei)n, (GLsizei)n, false, &stats,
		                      err);
		if (st == RS_OK)
			st = g->face_direct
			         ? rs_gles_to_face(g, plan, tex, f, (GLsizei)n, mirror, err)
			         : upload_face(g, plan, tex, f, mirror, face, err);
	}
	if (st == RS_OK)
		st = rs_gles_check(&g->gl, "environment map", err);
	free(face);
	return st;
}

enum rs_status rs_gles_envmap(struct gles *g, struct rs_error *err)
{
	struct rs_bounds b;
	rs_scene_bounds(g->scene, &b);
	double centre[3];
	for (int a = 0; a < 3; ++a)
		centre[a] = 0.5 * (b.lo[a] + b.hi[a]);
	g->envmap_ready = false;
	g->gl.GenTextures(1, &g->envmap);
	enum rs_status st = rs_gles_cube_alloc(g, g->envmap, "the environment cube map", err);
	/* Probed on the first cube map, not assumed: a float colour attachment needs
	 * EXT_color_buffer_float on GLES 3.0 (the per-pixel targets need it too). */
	bool forced = rs__gles_capture_readback && rs__gles_capture_readback();
	g->face_direct = st == RS_OK && !forced && rs_gles_face_probe(g, g->envmap);
	/* The faces: what the centre sees directly (1 pass). */
	if (st == RS_OK)
		st = rs_gles_capture_cube(g, &g->plans[PLAN_ENVMAP], centre, 0.0f, g->envmap, err);
	g->envmap_ready = st == RS_OK;
	return st;
}
