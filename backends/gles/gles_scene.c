/* Scene storage on the GPU: the four packed textures (2D or buffer textures, gles_storage.c),
 * the per-pixel ping-pong targets the plans draw into, the display target and the raster
 * depth buffer; and the one place that frees what set_scene made. */
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"

/* A one-level texture (immutable storage: a driver may then know no other level is ever
 * read; llvmpipe 22.3 still does per-lane level arithmetic in texelFetch, no measured
 * difference). */
static GLuint texture(const struct rs_gl *gl, GLint format, GLsizei w, GLsizei h, GLenum type,
                      const void *data)
{
	GLuint t;
	gl->GenTextures(1, &t);
	gl->BindTexture(GL_TEXTURE_2D, t);
	gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
	gl->TexStorage2D(GL_TEXTURE_2D, 1, (GLenum)format, w, h);
	if (data)
		gl->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h,
		                  format == GL_RGBA32UI ? GL_RGBA_INTEGER : GL_RGBA, type, data);
	return t;
}

GLuint rs_gles_target(const struct gles *g, uint8_t ref)
{
	if (ref >= REF_STATE && ref < REF_HIT)
		return g->state[(ref - REF_STATE) / ST_COUNT][(ref - REF_STATE) % ST_COUNT];
	if (ref >= REF_HIT && ref < REF_CNT)
		return g->hit[ref - REF_HIT];
	if (ref >= REF_CNT && ref < REF_COLOR)
		return g->cnt[ref - REF_CNT];
	return ref == REF_COLOR ? g->color : 0;
}

/* Each allocation is checked on its own (rs_gles_allocated), so out of GPU memory names
 * the texture; what was made stays in g for rs_gles_scene_delete(). */
enum rs_status rs_gles_scene_upload(struct gles *g, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	const struct rs_packed *p = &g->accel.packed;
	const struct rs_texture *t[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	static const char *const names[4] = {
	    "the scene's node texture", "the scene's triangle texture",
	    "the scene's normal texture", "the scene's material texture"};
	enum rs_status st = RS_OK;
	for (int i = 0; st == RS_OK && i < 4; ++i) {
		bool words = t[i]->format == RS_TEXEL_RGBA32UI;
		GLenum format = words ? GL_RGBA32UI : GL_RGBA32F;
		if (g->storage == RS_SCENE_STORAGE_BUFFER)
			st = rs_gles_buffer_texture(g, &g->scene_buf[i], &g->scene_tex[i], format,
			                            t[i], names[i], err);
		else
			g->scene_tex[i] =
			    texture(gl, (GLint)format, (GLsizei)t[i]->width, (GLsizei)t[i]->height,
			            words ? GL_UNSIGNED_INT : GL_FLOAT, t[i]->texels);
		if (st == RS_OK) /* the 2D storage; or glTexBuffer after the buffer's own check */
			st = rs_gles_allocated(gl, names[i], format, (GLsizei)t[i]->width,
			                       (GLsizei)t[i]->height, 1, err);
	}
	const struct rs_texture *inst = &g->accel.two_level.instances;
	if (st == RS_OK && g->accel.two_level.instance_count) {
		if (g->storage == RS_SCENE_STORAGE_BUFFER)
			st = rs_gles_buffer_texture(g, &g->instance_buf, &g->instance_tex,
			                            GL_RGBA32F, inst, "the instance texture", err);
		else
			g->instance_tex = texture(gl, GL_RGBA32F, (GLsizei)inst->width,
			                          (GLsizei)inst->height, GL_FLOAT, inst->texels);
		if (st == RS_OK)
			st = rs_gles_allocated(gl, "the instance texture", GL_RGBA32F,
			                       (GLsizei)inst->width, (GLsizei)inst->height, 1, err);
	}
	/* The cube map captures run the plans over face_size squares in the same targets. */
	uint32_t face = g->desc.reflections != RS_REFLECT_TRACE ? g->face_size : 0;
	GLsizei w = (GLsizei)(g->desc.width > face ? g->desc.width : face),
	        h = (GLsizei)(g->desc.height > face ? g->desc.height : face);
	GLuint *targets[2 * (ST_COUNT + 2)];
	int n = 0;
	for (int k = 0; k < 2; ++k) {
		for (int s = 0; s < ST_COUNT; ++s)
			targets[n++] = &g->state[k][s];
		targets[n++] = &g->hit[k];
		if (g->desc.counters)
			targets[n++] = &g->cnt[k];
	}
	for (int i = 0; st == RS_OK && i < n; ++i) {
		*targets[i] = texture(gl, GL_RGBA32F, w, h, GL_FLOAT, NULL);
		st = rs_gles_allocated(gl, "a per-pixel state target", GL_RGBA32F, w, h, 1, err);
	}
	if (st == RS_OK) {
		GLsizei cw = (GLsizei)g->desc.width, ch = (GLsizei)g->desc.height;
		g->color = texture(gl, GL_RGBA8, cw, ch, GL_UNSIGNED_BYTE, NULL);
		st = rs_gles_allocated(gl, "the display target", GL_RGBA8, cw, ch, 1, err);
	}
	if (st == RS_OK && g->desc.primary == RS_PRIMARY_RASTER) {
		gl->GenRenderbuffers(1, &g->depth);
		gl->BindRenderbuffer(GL_RENDERBUFFER, g->depth);
		gl->RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
		st = rs_gles_allocated(gl, "the raster depth buffer", GL_DEPTH_COMPONENT32F, w, h,
		                       1, err);
	}
	return st;
}

/* Rows y0..y1 (exclusive) of scene texture i from `t`. */
static void send_rows(const struct gles *g, int i, const struct rs_texture *t, uint32_t y0,
                      uint32_t y1)
{
	const struct rs_gl *gl = &g->gl;
	size_t row_bytes = (size_t)t->width * 16u;
	const uint8_t *src = (const uint8_t *)t->texels + y0 * row_bytes;
	if (g->storage == RS_SCENE_STORAGE_BUFFER) {
		gl->BindBuffer(GL_TEXTURE_BUFFER, g->scene_buf[i]);
		gl->BufferSubData(GL_TEXTURE_BUFFER, (GLintptr)(y0 * row_bytes),
		                  (GLsizeiptr)((y1 - y0) * row_bytes), src);
		gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
		return;
	}
	bool words = t->format == RS_TEXEL_RGBA32UI;
	gl->BindTexture(GL_TEXTURE_2D, g->scene_tex[i]);
	gl->TexSubImage2D(GL_TEXTURE_2D, 0, 0, (GLint)y0, (GLsizei)t->width, (GLsizei)(y1 - y0),
	                  words ? GL_RGBA_INTEGER : GL_RGBA, words ? GL_UNSIGNED_INT : GL_FLOAT,
	                  src);
	gl->BindTexture(GL_TEXTURE_2D, 0);
}

enum rs_status rs_gles_scene_update(struct gles *g, const struct rs_packed *next,
                                    uint64_t *out_bytes, struct rs_error *err)
{
	const struct rs_packed *p = &g->accel.packed;
	const struct rs_texture *old[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	const struct rs_texture *now[4] = {&next->nodes, &next->triangles, &next->normals,
	                                   &next->materials};
	uint64_t bytes = 0;
	for (int i = 0; i < 4; ++i) {
		const struct rs_texture *a = old[i], *b = now[i];
		RS_ASSERT(a->width == b->width && a->height == b->height && a->format == b->format);
		size_t row_bytes = (size_t)b->width * 16u;
		/* a row is the unit: one call per run of changed rows, not per texel */
		uint32_t y = 0;
		while (y < b->height) {
			const uint8_t *ra = (const uint8_t *)a->texels + y * row_bytes;
			const uint8_t *rb = (const uint8_t *)b->texels + y * row_bytes;
			if (memcmp(ra, rb, row_bytes) == 0) {
				y++;
				continue;
			}
			uint32_t end = y + 1;
			while (end < b->height &&
			       memcmp((const uint8_t *)a->texels + end * row_bytes,
			              (const uint8_t *)b->texels + end * row_bytes, row_bytes) != 0)
				end++;
			send_rows(g, i, b, y, end);
			bytes += (uint64_t)(end - y) * row_bytes;
			y = end;
		}
	}
	*out_bytes = bytes;
	return rs_gles_check(&g->gl, "updating the scene textures", err);
}

/* Texels [first, end) of scene texture i from `t`: the rest of the first row, whole rows,
 * the start of the last (a buffer: one range). */
static void send_texels(const struct gles *g, int i, const struct rs_texture *t, size_t first,
                        size_t end)
{
	const struct rs_gl *gl = &g->gl;
	const uint8_t *base = (const uint8_t *)t->texels;
	if (g->storage == RS_SCENE_STORAGE_BUFFER) {
		gl->BindBuffer(GL_TEXTURE_BUFFER, g->scene_buf[i]);
		gl->BufferSubData(GL_TEXTURE_BUFFER, (GLintptr)(first * 16u),
		                  (GLsizeiptr)((end - first) * 16u), base + first * 16u);
		gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
		return;
	}
	bool words = t->format == RS_TEXEL_RGBA32UI;
	GLenum format = words ? GL_RGBA_INTEGER : GL_RGBA,
	       type = words ? GL_UNSIGNED_INT : GL_FLOAT;
	size_t w = t->width;
	gl->BindTexture(GL_TEXTURE_2D, g->scene_tex[i]);
	while (first < end) {
		size_t y = first / w, x = first % w, n = w - x < end - first ? w - x : end - first;
		if (x == 0 && end - first >= w) /* whole rows at once */
			n = (end - first) / w * w;
		GLsizei rows = (GLsizei)(x == 0 ? (n + w - 1) / w : 1);
		gl->TexSubImage2D(GL_TEXTURE_2D, 0, (GLint)x, (GLint)y, (GLsizei)(rows > 1 ? w : n),
		                  rows, format, type, base + first * 16u);
		first += n;
	}
	gl->BindTexture(GL_TEXTURE_2D, 0);
}

enum rs_status rs_gles_scene_update_top(struct gles *g, uint64_t *out_bytes, struct rs_error *err)
{
	const struct rs_packed_two_level *two = &g->accel.two_level;
	const struct rs_packed *p = &two->all;
	const struct rs_texture *t[2] = {&p->nodes, &p->triangles};
	/* the TLAS's items of the node and triangle textures (its normals never change) */
	size_t per = p->node_format == RS_PACK_NODES_PAPER ? RS_PACK_NODE_TEXELS
	                                                   : RS_PACK_COMPACT_NODE_TEXELS;
	size_t first[2] = {(size_t)two->top_node_base * per,
	                   (size_t)two->top_slot_base * RS_PACK_TRIANGLE_TEXELS};
	size_t end[2] = {first[0] + (size_t)two->top_node_capacity * per,
	                 first[1] + (size_t)two->instance_count * RS_PACK_TRIANGLE_TEXELS};
	const struct rs_gl *gl = &g->gl;
	uint64_t bytes = 0;
	for (int i = 0; i < 2; ++i) {
		send_texels(g, i, t[i], first[i], end[i]);
		bytes += (uint64_t)(end[i] - first[i]) * 16u;
	}
	const struct rs_texture *inst = &two->instances;
	if (g->storage == RS_SCENE_STORAGE_BUFFER) {
		gl->BindBuffer(GL_TEXTURE_BUFFER, g->instance_buf);
		gl->BufferSubData(GL_TEXTURE_BUFFER, 0,
		                  (GLsizeiptr)((size_t)inst->width * inst->height * 16u),
		                  inst->texels);
		gl->BindBuffer(GL_TEXTURE_BUFFER, 0);
	} else {
		gl->BindTexture(GL_TEXTURE_2D, g->instance_tex);
		gl->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)inst->width,
		                  (GLsizei)inst->height, GL_RGBA, GL_FLOAT, inst->texels);
		gl->BindTexture(GL_TEXTURE_2D, 0);
	}
	bytes += (uint64_t)inst->width * inst->height * 16u;
	*out_bytes = bytes;
	return rs_gles_check(gl, "updating the instances' top-level tree", err);
}

void rs_gles_scene_delete(struct gles *g)
{
	const struct rs_gl *gl = &g->gl;
	rs_gles_programs_delete(g);
	GLuint *tex[] = {g->scene_tex, &g->state[0][0], g->cnt, g->hit, &g->color};
	size_t n[] = {4, 2 * ST_COUNT, 2, 2, 1};
	for (int i = 0; i < 5; ++i) {
		gl->DeleteTextures((GLsizei)n[i], tex[i]);
		memset(tex[i], 0, n[i] * sizeof(GLuint));
	}
	gl->DeleteBuffers(4, g->scene_buf);
	memset(g->scene_buf, 0, sizeof g->scene_buf);
	GLuint rbs[2] = {g->depth, g->shadow_depth};
	gl->DeleteRenderbuffers(2, rbs);
	gl->DeleteTextures(1, &g->shadow);
	gl->DeleteTextures(1, &g->envmap);
	gl->DeleteTextures(1, &g->object_tex);
	gl->DeleteTextures(1, &g->instance_tex);
	gl->DeleteBuffers(1, &g->instance_buf);
	g->instance_tex = g->instance_buf = 0;
	gl->DeleteTextures(2 * RS_RENDER_MAX_MIRROR_OBJECTS, &g->objmap[0][0]);
	memset(g->objmap, 0, sizeof g->objmap);
	g->depth = g->shadow_depth = g->shadow = g->envmap = g->object_tex = 0;
	g->envmap_ready = false;
	g->object_count = 0;
	g->objmap_read = -1;
	memset(g->plans, 0, sizeof g->plans);
	rs_render_accel_free(&g->accel);
	free(g->scratch);
	g->scratch = NULL;
	g->scene = NULL;
}
