/* Scene storage (rs_scene_storage): whether the context has buffer textures, which storage
 * a scene gets, and a packed texture as a buffer texture. Buffer textures index texels
 * directly, where a 2D texelFetch works out a row, a level and its bounds per lane: on
 * llvmpipe that is a fifth of the trace kernel's time (docs/gles.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"

void rs_gles_probe_buffers(struct gles *g, const char *version)
{
	const struct rs_gl *gl = &g->gl;
	/* GLES 3.2 core; GLES 3.1 with either extension; desktop GL that compiles ES 3.20
	 * kernels (ARB_ES3_2_compatibility). */
	const char *glsl = NULL;
	int major = 0, minor = 0;
	sscanf(g->es ? version + 9 : version, " %d.%d", &major, &minor);
	if (g->es && (major > 3 || minor >= 2))
		glsl = "#version 320 es\n";
	GLint n = 0;
	gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
	for (GLint i = 0; i < n && !glsl; ++i) {
		const char *e = (const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)i);
		if (!e)
			continue;
		if (!g->es && strcmp(e, "GL_ARB_ES3_2_compatibility") == 0)
			glsl = "#version 320 es\n";
		else if (g->es && minor == 1 && strcmp(e, "GL_OES_texture_buffer") == 0)
			glsl = "#version 310 es\n#extension GL_OES_texture_buffer : require\n";
		else if (g->es && minor == 1 && strcmp(e, "GL_EXT_texture_buffer") == 0)
			glsl = "#version 310 es\n#extension GL_EXT_texture_buffer : require\n";
	}
	g->buffer_glsl = NULL;
	g->max_tex_buffer = 0;
	if (!glsl || !gl->TexBuffer)
		return;
	gl->GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &g->max_tex_buffer);
	/* RS_GLES_MAX_TEXTURE_BUFFER_SIZE lowers the length, as a small device's would be (0:
	 * as a context without buffer textures). */
	const char *cap = getenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE");
	if (cap && *cap && atoi(cap) >= 0 && atoi(cap) < g->max_tex_buffer)
		g->max_tex_buffer = atoi(cap);
	if (g->max_tex_buffer > 0)
		g->buffer_glsl = glsl;
}

/* Does every packed texture (and a two-level scene's instance texture) fit a buffer
 * texture of this GL? */
static bool fits_buffers(const struct gles *g, const struct rs_texture *const t[5])
{
	for (int i = 0; i < 5; ++i)
		if (t[i] && (uint64_t)t[i]->width * t[i]->height > (uint64_t)g->max_tex_buffer)
			return false;
	return true;
}

/* The scene storage for this scene (rs_scene_storage): buffer textures where asked for or
 * where AUTO finds them and the scene fits, else 2D; BUFFER is refused, naming why, where
 * the context has none or the scene is over GL_MAX_TEXTURE_BUFFER_SIZE. */
enum rs_status rs_gles_choose_storage(struct gles *g, const struct rs_packed *p,
                                      const struct rs_texture *instances,
                                      enum rs_scene_storage want, struct rs_error *err)
{
	const struct rs_texture *t[5] = {&p->nodes, &p->triangles, &p->normals, &p->materials,
	                                 instances};
	g->storage = RS_SCENE_STORAGE_2D;
	g->scene_target = GL_TEXTURE_2D;
	if (want == RS_SCENE_STORAGE_2D)
		return RS_OK;
	if (want == RS_SCENE_STORAGE_BUFFER && !g->buffer_glsl)
		return rs_error_set(
		    err, RS_ERR_UNSUPPORTED,
		    "gles: this context has no buffer textures (GLES 3.2, 3.1 with "
		    "OES_texture_buffer, or ARB_ES3_2_compatibility); 2D storage works");
	if (want == RS_SCENE_STORAGE_BUFFER && !fits_buffers(g, t))
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: a scene texture is over this GL's "
		                    "GL_MAX_TEXTURE_BUFFER_SIZE of %d texels",
		                    (int)g->max_tex_buffer);
	if (g->buffer_glsl && fits_buffers(g, t)) {
		g->storage = RS_SCENE_STORAGE_BUFFER;
		g->scene_target = GL_TEXTURE_BUFFER;
	}
	return RS_OK;
}

/* Scene texture i as a buffer texture over a buffer object holding the packed texels in
 * their row-major order: texel (x, y) of the 2D layout is element y * width + x, which for
 * dense rows (rs_pack.h) is item * texels_per_item + j, what the kernels fetch. */
enum rs_status rs_gles_buffer_texture(struct gles *g, GLuint *buf, GLuint *tex, GLenum format,
                                      const struct rs_texture *t, const char *what,
                                      struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	gl->GenBuffers(1, buf);
	gl->BindBuffer(GL_TEXTURE_BUFFER, *buf);
	gl->BufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)t->width * t->height * 16, t->texels,
	               GL_STATIC_DRAW);
	gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
	enum rs_status st =
	    rs_gles_allocated(gl, what, format, (GLsizei)t->width, (GLsizei)t->height, 1, err);
	if (st != RS_OK)
		return st;
	gl->GenTextures(1, tex);
	gl->BindTexture(GL_TEXTURE_BUFFER, *tex);
	gl->TexBuffer(GL_TEXTURE_BUFFER, format, *buf);
	gl->BindTexture(GL_TEXTURE_BUFFER, 0);
	return RS_OK;
}
