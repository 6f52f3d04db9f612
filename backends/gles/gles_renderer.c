/* The GLES renderer object: capability probe at creation, and per scene the upload of the
 * packed textures, the per-pixel state targets and the kernels specialised for the scene
 * (lights, whether any material reflects or refracts, triangle test, counters). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"

static void delete_scene(struct gles *g)
{
	const struct rs_gl *gl = &g->gl;
	for (int i = 0; i < PROG_COUNT; ++i)
		if (g->prog[i])
			gl->DeleteProgram(g->prog[i]);
	memset(g->prog, 0, sizeof g->prog);
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
	gl->DeleteTextures(2 * RS_RENDER_MAX_MIRROR_OBJECTS, &g->objmap[0][0]);
	memset(g->objmap, 0, sizeof g->objmap);
	g->depth = g->shadow_depth = g->shadow = g->envmap = g->object_tex = 0;
	g->envmap_ready = false;
	g->object_count = 0;
	g->objmap_read = -1;
	rs_render_accel_free(&g->accel);
	free(g->scratch);
	g->scratch = NULL;
	g->scene = NULL;
}

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

/* Refuse what this GL cannot hold, naming the limit (GLES 3.0 guarantees only 2048). 2D
 * storage only: buffer textures have no rows (rs_gles_choose_storage checked their length). */
static enum rs_status check_limits(const struct gles *g, const struct rs_packed *p,
                                   const struct rs_render_desc *d, struct rs_error *err)
{
	const struct rs_texture *t[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	static const char *const names[4] = {"node", "triangle", "normal", "material"};
	for (int i = 0; g->storage == RS_SCENE_STORAGE_2D && i < 4; ++i)
		if (t[i]->width > (uint32_t)g->max_tex || t[i]->height > (uint32_t)g->max_tex)
			return rs_error_set(
			    err, RS_ERR_LIMIT,
			    "gles: the scene's %s texture is %ux%u texels, over this "
			    "GL's GL_MAX_TEXTURE_SIZE of %d",
			    names[i], t[i]->width, t[i]->height, g->max_tex);
	GLint side = g->max_tex < g->max_view ? g->max_tex : g->max_view;
	if (d->width > (uint32_t)side || d->height > (uint32_t)side)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: image %ux%u is over this GL's limit of %d texels a side",
		                    d->width, d->height, side);
	if (d->shadows == RS_SHADOW_MAP && d->shadow_map_size > (uint32_t)g->max_tex)
		return rs_error_set(
		    err, RS_ERR_LIMIT,
		    "gles: shadow map side %u is over this GL's GL_MAX_TEXTURE_SIZE "
		    "of %d",
		    d->shadow_map_size, g->max_tex);
	if (d->lights > RS_GLES_MAX_LIGHTS)
		return rs_error_set(err, RS_ERR_LIMIT, "gles: %u lights (the kernels take %u)",
		                    d->lights, RS_GLES_MAX_LIGHTS);
	return RS_OK;
}

/* The constants every frame's kernels read, resolved once as rs_trace_frame_init() does. */
static void frame_constants(struct gles *g, const struct rs_scene *scene, uint32_t lights)
{
	/* R1: everything moves into the packed frame here, in double, before rounding. */
	const double *o = g->accel.packed.origin;
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	double r2 = 0.0;
	for (int a = 0; a < 3; ++a) {
		g->bounds_center[a] = b.hi[a] >= b.lo[a] ? 0.5 * (b.lo[a] + b.hi[a]) - o[a] : 0.0;
		r2 += b.hi[a] >= b.lo[a] ? 0.25 * (b.hi[a] - b.lo[a]) * (b.hi[a] - b.lo[a]) : 0.0;
	}
	g->bounds_radius = sqrt(r2);
	g->spawn_scale =
	    (float)(g->desc.ray_epsilon > 0.0 ? g->desc.ray_epsilon : RS_TRACE_SPAWN_SCALE);
	g->ambient = (float)rs_scene_ambient(scene);
	g->light_count = lights;
	const struct rs_light *l = rs_scene_lights(scene);
	for (uint32_t i = 0; i < lights; ++i)
		for (int a = 0; a < 3; ++a) {
			g->light_pos[3 * i + a] = (float)(l[i].position[a] - o[a]);
			g->light_color[3 * i + a] = (float)l[i].color[a];
		}
	struct rs_environment env;
	rs_scene_environment(scene, &env);
	for (int a = 0; a < 3; ++a)
		g->env_center[a] = (float)(env.center[a] - o[a]);
	g->env_half = (float)(env.half_size > 0.0 && isfinite(env.half_size) ? env.half_size : 1.0);
	for (int f = 0; f < 6; ++f)
		for (int c = 0; c < 3; ++c)
			g->env_color[3 * f + c] = env.face_color[f][c];
	g->env_grid = (float)(env.grid ? env.grid : 16u);
	g->env_line_width = env.line_width > 0.0f ? env.line_width : 0.06f;
	g->env_line_scale = env.line_scale > 0.0f ? env.line_scale : 0.25f;
}

static bool scene_has_optics(const struct rs_scene *scene)
{
	const struct rs_material *m = rs_scene_materials(scene);
	for (size_t i = 0; i < rs_scene_material_count(scene); ++i)
		if (m[i].reflectance > 0.0f || m[i].transmittance > 0.0f)
			return true;
	return false;
}

/* Items per texture row of the packed layout: the one place the kernels learn it. */
static uint32_t row_items(const struct rs_packed *packed)
{
	return packed->row_items;
}

/* The layout this GL can hold: the descriptor's texture limit, or GL_MAX_TEXTURE_SIZE when
 * it leaves it to the device; a limit above the device's is refused, naming both. */
static enum rs_status pack_desc(const struct gles *g, const struct rs_render_desc *desc,
                                struct rs_pack_desc *out, struct rs_error *err)
{
	*out = desc->pack;
	if (!out->max_texture_size)
		out->max_texture_size = (uint32_t)g->max_tex;
	if (out->max_texture_size > (uint32_t)g->max_tex)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: a texture size limit of %u texels is over this GL's "
		                    "GL_MAX_TEXTURE_SIZE of %d",
		                    out->max_texture_size, g->max_tex);
	return RS_OK;
}

/* log2 of a power of two, else -1 (the kernels then divide). */
static int row_shift(uint32_t items)
{
	for (int s = 0; s < 31; ++s)
		if ((1u << s) == items)
			return s;
	return -1;
}

static enum rs_status build_programs(struct gles *g, const struct rs_scene *scene,
                                     struct rs_error *err)
{
	char defines[512];
	snprintf(defines, sizeof defines,
	         "#define RS_ROW_ITEMS %u\n#define RS_ROW_SHIFT %d\n"
	         "#define RS_WATERTIGHT %d\n#define RS_LIGHTS %u\n"
	         "#define RS_COUNTERS %d\n#define RS_OPTICS %d\n#define RS_GEOMETRY %d\n"
	         "#define RS_SHADOW_MAP %d\n#define RS_ENVMAP %d\n#define RS_INTERREFLECT %d\n"
	         "#define RS_COMPACT_NODES %d\n#define RS_NODE_ORDERS %u\n"
	         "#define RS_SCENE_BUFFERS %d\n",
	         row_items(&g->accel.packed), row_shift(row_items(&g->accel.packed)),
	         g->desc.triangle_test == RS_TRIANGLE_WATERTIGHT, g->light_count,
	         g->desc.counters ? 1 : 0, scene_has_optics(scene) ? 1 : 0,
	         rs_scene_triangle_count(scene) > 0, g->desc.shadows == RS_SHADOW_MAP,
	         g->desc.reflections != RS_REFLECT_TRACE,
	         g->desc.reflections == RS_REFLECT_INTERREFLECT,
	         g->accel.packed.node_format == RS_PACK_NODES_COMPACT, g->accel.packed.node_orders,
	         g->storage == RS_SCENE_STORAGE_BUFFER);
	/* An array of 0 lights is not GLSL: loop over RS_LIGHTS, size the arrays at least 1. */
	char full[576];
	snprintf(full, sizeof full, "%s#define RS_LIGHT_SLOTS %u\n", defines,
	         g->light_count ? g->light_count : 1u);
	static const char *const files[PROG_COUNT][5] = {
	    {"camera.glsl", "raygen.glsl"},
	    {"common.glsl", "surface.glsl", "intersect.glsl"},
	    {"common.glsl", "surface.glsl", "shade.glsl"},
	    {"common.glsl", "surface.glsl", "fused.glsl"},
	    {"display.glsl"},
	    {"raster.glsl"},
	    {"shadow.glsl"},
	    {"common.glsl", "surface.glsl", "camera.glsl", "fused.glsl"},
	    {"common.glsl", "surface.glsl", "environment.glsl"},
	    {"common.glsl", "surface.glsl", "shading.glsl"},
	    {"common.glsl", "surface.glsl", "nextray.glsl"},
	    {"common.glsl", "camera.glsl", "visibility.glsl", "resolve.glsl"},
	    {"common.glsl", "surface.glsl", "camera.glsl", "visibility.glsl", "fused.glsl"},
	};
	static const size_t counts[PROG_COUNT] = {2, 3, 3, 3, 1, 1, 1, 4, 3, 3, 3, 4, 5};
	bool paper = g->desc.chain == RS_CHAIN_PAPER;
	char first[608], raster_first[640];
	snprintf(first, sizeof first, "%s#define RS_FIRST_PASS 1\n", full);
	snprintf(raster_first, sizeof raster_first, "%s#define RS_RASTER_FIRST 1\n", first);
	static const char *const raster_vertex[3] = {"common.glsl", "camera.glsl",
	                                             "raster_vertex.glsl"};
	static const char *const shadow_vertex[2] = {"common.glsl", "shadow_vertex.glsl"};
	const char *version =
	    g->storage == RS_SCENE_STORAGE_BUFFER ? g->buffer_glsl : "#version 300 es\n";
	for (int i = 0; i < PROG_COUNT; ++i) {
		bool fused = i == PROG_FUSED || i == PROG_FUSED_FIRST || i == PROG_FUSED_RASTER;
		if (fused && (g->desc.counters || paper))
			continue; /* counters run the separate chain (render targets) */
		if (i == PROG_SHADE && paper)
			continue;
		if ((i == PROG_ENVIRONMENT || i == PROG_SHADING || i == PROG_NEXTRAY) && !paper)
			continue;
		if ((i == PROG_RASTER || i == PROG_RESOLVE || i == PROG_FUSED_RASTER) &&
		    g->desc.primary != RS_PRIMARY_RASTER)
			continue;
		if (i == PROG_SHADOW && g->desc.shadows != RS_SHADOW_MAP)
			continue;
		const char *const *vs = i == PROG_RASTER   ? raster_vertex
		                        : i == PROG_SHADOW ? shadow_vertex
		                                           : NULL;
		enum rs_status st = rs_gles_program(&g->gl, version, vs, i == PROG_SHADOW ? 2 : 3,
		                                    files[i], counts[i],
		                                    i == PROG_FUSED_FIRST    ? first
		                                    : i == PROG_FUSED_RASTER ? raster_first
		                                                             : full,
		                                    &g->prog[i], err);
		if (st != RS_OK)
			return st;
	}
	return RS_OK;
}

/* Each allocation is checked on its own (rs_gles_allocated), so out of GPU memory names
 * the texture; what was made stays in g for delete_scene(). */
static enum rs_status upload(struct gles *g, struct rs_error *err)
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
			st = rs_gles_buffer_texture(g, i, format, t[i], names[i], err);
		else
			g->scene_tex[i] =
			    texture(gl, (GLint)format, (GLsizei)t[i]->width, (GLsizei)t[i]->height,
			            words ? GL_UNSIGNED_INT : GL_FLOAT, t[i]->texels);
		if (st == RS_OK) /* the 2D storage; or glTexBuffer after the buffer's own check */
			st = rs_gles_allocated(gl, names[i], format, (GLsizei)t[i]->width,
			                       (GLsizei)t[i]->height, 1, err);
	}
	GLsizei w = (GLsizei)g->desc.width, h = (GLsizei)g->desc.height;
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
		g->color = texture(gl, GL_RGBA8, w, h, GL_UNSIGNED_BYTE, NULL);
		st = rs_gles_allocated(gl, "the display target", GL_RGBA8, w, h, 1, err);
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

static enum rs_status gles_set_scene(void *impl, const struct rs_scene *scene,
                                     const struct rs_render_desc *desc,
                                     struct rs_render_stats *stats, struct rs_error *err)
{
	struct gles *g = impl;
	enum rs_status st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK)
		return st;
	delete_scene(g);
	g->desc = *desc;
	struct rs_pack_desc pack;
	st = pack_desc(g, desc, &pack, err);
	if (st == RS_OK)
		st = rs_render_accel_build(scene, &desc->bvh, &pack, &g->accel, err);
	uint32_t lights = desc->lights ? desc->lights : (uint32_t)rs_scene_light_count(scene);
	struct rs_render_desc d = *desc;
	d.lights = lights;
	if (st == RS_OK)
		st = rs_gles_choose_storage(g, &g->accel.packed, desc->scene_storage, err);
	if (st == RS_OK)
		st = check_limits(g, &g->accel.packed, &d, err);
	if (st == RS_OK)
		stats->scene_storage = g->storage;
	size_t floats = (size_t)desc->width * desc->height * 4u;
	if (st == RS_OK && !(g->scratch = malloc(floats * sizeof(float))))
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory for %ux%u",
		                  desc->width, desc->height);
	double t0 = rs_now_ms();
	if (st == RS_OK) {
		frame_constants(g, scene, lights);
		st = build_programs(g, scene, err);
	}
	if (st == RS_OK)
		st = upload(g, err);
	if (st == RS_OK && desc->shadows == RS_SHADOW_MAP)
		st = rs_gles_shadow_maps(g, err);
	bool interreflect = desc->reflections == RS_REFLECT_INTERREFLECT;
	/* Inter-reflection: rays that leave no mirror object read the classic map. */
	if (st == RS_OK && (desc->reflections == RS_REFLECT_ENVMAP || interreflect))
		st = rs_gles_envmap(g, scene, err);
	if (st == RS_OK && interreflect)
		st = rs_gles_interreflect_setup(g, scene, err);
	if (st == RS_OK) {
		struct rs_camera cam;
		rs_camera_resolve(rs_scene_camera(scene), &cam);
		st = rs_gles_warm_up(g, &cam, err);
	}
	if (st == RS_OK) {
		g->gl.Finish();
		stats->build_ms = g->accel.build_ms;
		stats->pack_ms = g->accel.pack_ms;
		stats->upload_ms = rs_now_ms() - t0;
		g->scene = scene;
	} else {
		delete_scene(g);
	}
	g->cops->release(g->ctx);
	return st;
}

static enum rs_status gles_render(void *impl, const struct rs_camera *camera,
                                  const struct rs_frame *frame, struct rs_render_stats *stats,
                                  struct rs_error *err)
{
	struct gles *g = impl;
	enum rs_status st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK)
		return st;
	/* Inter-reflection maps are dynamic: captured for every frame (and counted in its time,
	 * which is what Table 3 compares); a 1-pass frame reads none. */
	double t0 = rs_now_ms(), capture_ms = 0.0;
	if (g->desc.reflections == RS_REFLECT_INTERREFLECT && g->desc.passes > 1) {
		st = rs_gles_interreflect_capture(g, err);
		capture_ms = rs_now_ms() - t0;
	}
	if (st == RS_OK)
		st = rs_gles_frame(g, camera, frame, stats, err);
	if (st == RS_OK && capture_ms > 0.0) {
		stats->render_ms += capture_ms;
		rs_gles_kernel_time(stats, "envmap capture", capture_ms);
	}
	g->cops->release(g->ctx);
	return st;
}

static void gles_destroy(void *impl)
{
	struct gles *g = impl;
	if (!g)
		return;
	if (g->gl.DeleteTextures && g->cops->make_current(g->ctx, NULL) == RS_OK) {
		delete_scene(g);
		if (g->fbo)
			g->gl.DeleteFramebuffers(1, &g->fbo);
		if (g->vao)
			g->gl.DeleteVertexArrays(1, &g->vao);
		g->cops->release(g->ctx);
	}
	rs_render_accel_free(&g->accel);
	free(g->scratch);
	g->cops->destroy(g->ctx);
	free(g);
}

static void gles_describe(const void *impl, char *out, size_t cap)
{
	const struct gles *g = impl;
	snprintf(out, cap, "%s", g->renderer);
}

static enum rs_status probe(struct gles *g, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	const char *version = (const char *)gl->GetString(GL_VERSION);
	const char *renderer = (const char *)gl->GetString(GL_RENDERER);
	if (!version)
		return rs_error_set(err, RS_ERR_DEVICE, "gles: the context answers no GL_VERSION");
	int major = 0;
	g->es = strncmp(version, "OpenGL ES", 9) == 0;
	sscanf(g->es ? version + 9 : version, " %d", &major);
	if (major < 3)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: need GLES 3.0 or desktop GL 3.3, the context is \"%s\"",
		                    version);
	bool float_targets = !g->es, es3_compat = g->es;
	GLint n = 0;
	gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
	for (GLint i = 0; i < n; ++i) {
		const char *e = (const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)i);
		if (e && strcmp(e, "GL_EXT_color_buffer_float") == 0)
			float_targets = true;
		if (e && strcmp(e, "GL_ARB_ES3_compatibility") == 0)
			es3_compat = true;
	}
	rs_gles_probe_buffers(g, version);
	GLint dims[2] = {0, 0};
	gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &g->max_tex);
	gl->GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
	gl->GetIntegerv(GL_MAX_DRAW_BUFFERS, &g->max_draw);
	g->max_view = dims[0] < dims[1] ? dims[0] : dims[1];
	if (g->max_draw < 4)
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "gles: %d draw buffers (need 4)",
		                    (int)g->max_draw);
	if (!float_targets)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: %s cannot render to float textures "
		                    "(no EXT_color_buffer_float)",
		                    renderer ? renderer : "this GL");
	if (!es3_compat)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: desktop GL without ARB_ES3_compatibility cannot run "
		                    "the #version 300 es kernels");
	char platform[48];
	g->cops->describe(g->ctx, platform, sizeof platform);
	snprintf(g->renderer, sizeof g->renderer, "%s (%s; %s)", renderer ? renderer : "?", version,
	         platform);
	/* RS_GLES_MAX_TEXTURE_SIZE lowers the limit, e.g. to GLES 3.0's guaranteed 2048, to
	 * check on a big desktop GL that a scene fits small devices. */
	const char *cap = getenv("RS_GLES_MAX_TEXTURE_SIZE");
	if (cap && atoi(cap) > 0 && atoi(cap) < g->max_tex)
		g->max_tex = atoi(cap);
	enum rs_status st = rs_gles_check(gl, "probing the context", err);
	if (st != RS_OK)
		return st;
	gl->GenVertexArrays(1, &g->vao);
	st = rs_gles_allocated(gl, "the vertex array object", 0, 0, 0, 0, err);
	if (st == RS_OK) {
		gl->GenFramebuffers(1, &g->fbo);
		st = rs_gles_allocated(gl, "the framebuffer object", 0, 0, 0, 0, err);
	}
	return st;
}

static const struct rs_renderer_ops gles_ops_egl = {.name = "egl",
                                                    .set_scene = gles_set_scene,
                                                    .render = gles_render,
                                                    .destroy = gles_destroy,
                                                    .describe = gles_describe};
static const struct rs_renderer_ops gles_ops_osmesa = {.name = "osmesa",
                                                       .set_scene = gles_set_scene,
                                                       .render = gles_render,
                                                       .destroy = gles_destroy,
                                                       .describe = gles_describe};

enum rs_status rs_gles_renderer_create(const struct rs_gl_context_ops *ops, void *ctx,
                                       const struct rs_render_desc *desc, struct rs_renderer **out,
                                       struct rs_error *err)
{
	RS_ASSERT(ops && out);
	*out = NULL;
	struct gles *g = calloc(1, sizeof *g);
	if (!g) {
		ops->destroy(ctx);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory");
	}
	g->cops = ops;
	g->ctx = ctx;
	enum rs_status st = ops->make_current(ctx, err);
	if (st == RS_OK) {
		st = rs_gl_load(&g->gl, ops->get_proc_address, ctx, err);
		if (st == RS_OK)
			st = probe(g, err);
		ops->release(ctx);
	}
	if (st != RS_OK) {
		gles_destroy(g);
		return st;
	}
	const struct rs_renderer_ops *table =
	    strcmp(ops->backend, "osmesa") == 0 ? &gles_ops_osmesa : &gles_ops_egl;
	return rs_renderer_create(table, g, desc, out, err);
}
