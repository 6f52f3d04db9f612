/* Classic environment mapping (RS_REFLECT_ENVMAP, the paper's Table 3 comparison): one cube
 * map captured once at set_scene from the centre of the scene's bounds, each face the
 * traced image of 1 pass (local shading, shadows, environment) seen with a 90-degree
 * camera; from the second pass on, rays read it by direction instead of being traced. The
 * faces are frames of their own plans (PLAN_ENVMAP here, the bounces' in
 * gles_interreflect.c), run as the frame's plan is: the renderer's descriptor is never
 * touched. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"

/* GL's cube face conventions (ES 3.0 table 3.21): the major axis and the directions in
 * which the face's s and t coordinates grow. */
static const double faces[6][3][3] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
    {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
};

enum rs_status rs_gles_capture_cube(struct gles *g, const struct rs_gles_plan *plan,
                                    const double eye[3], float near, GLuint tex,
                                    struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	uint32_t n = g->desc.width;
	size_t floats = (size_t)n * n * 3;
	float *rgb = malloc(floats * sizeof(float)), *face = malloc(floats * sizeof(float));
	enum rs_status st = RS_OK;
	if (!rgb || !face)
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
		struct rs_frame frame = {.rgb = rgb};
		st = rs_gles_plan_run(g, plan, &cam, near, (GLsizei)n, (GLsizei)n, &stats, err);
		if (st == RS_OK)
			st = rs_gles_readback(g, plan, &frame, &stats, err);
		for (uint32_t y = 0; st == RS_OK && y < n; ++y)
			for (uint32_t x = 0; x < n; ++x)
				memcpy(&face[((size_t)y * n + x) * 3],
				       &rgb[((size_t)y * n + (mirror ? n - 1 - x : x)) * 3],
				       3 * sizeof(float));
		if (st == RS_OK) {
			gl->ActiveTexture(GL_TEXTURE0 + UNIT_ENVMAP);
			gl->BindTexture(GL_TEXTURE_CUBE_MAP, tex);
			gl->TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)f, 0, GL_RGB16F,
			               (GLsizei)n, (GLsizei)n, 0, GL_RGB, GL_FLOAT, face);
			st = rs_gles_allocated(gl, "an environment cube map face", GL_RGB16F,
			                       (GLsizei)n, (GLsizei)n, 1, err);
		}
	}
	if (st == RS_OK) {
		gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
		gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
		gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
		gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
		st = rs_gles_check(gl, "environment map", err);
	}
	free(rgb);
	free(face);
	return st;
}

enum rs_status rs_gles_envmap(struct gles *g, struct rs_error *err)
{
	if (g->desc.height != g->desc.width)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: environment mapping needs a square image (its cube "
		                    "faces are the frame's size), not %ux%u",
		                    g->desc.width, g->desc.height);
	struct rs_bounds b;
	rs_scene_bounds(g->scene, &b);
	double centre[3];
	for (int a = 0; a < 3; ++a)
		centre[a] = 0.5 * (b.lo[a] + b.hi[a]);
	g->envmap_ready = false;
	g->gl.GenTextures(1, &g->envmap);
	/* The faces: what the centre sees directly (1 pass). */
	enum rs_status st =
	    rs_gles_capture_cube(g, &g->plans[PLAN_ENVMAP], centre, 0.0f, g->envmap, err);
	g->envmap_ready = st == RS_OK;
	return st;
}
