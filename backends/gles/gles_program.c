/* The program table: each kernel program's files and variant, compiled per scene for the
 * programs the scene's plans use (no program is built that no plan runs), with the version
 * line, the precision prelude and the #define prelude (gles_prelude.c); each program's
 * uniform locations looked up once at link. Compile errors are translated into one line
 * naming file, line and text. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"
#include "gles_seams.h"
#include "kernels.h"

#define LINE_BASE 1000

/* Every kernel runs at full precision (ray tracing in mediump would be meaningless). */
static const char precision[] = "precision highp float;\n"
                                "precision highp int;\n"
                                "precision highp sampler2D;\n"
                                "precision highp sampler2DArray;\n";

/* Which #define prelude a program takes (rs_gles_programs_build()'s three). */
enum { ALL_PASSES, FIRST_PASS, RASTER_FIRST_PASS };

/* The fragment stage of a tracing kernel: the library files in dependency order, then
 * the kernel's own (and camera.glsl, visibility.glsl where it makes primaries). */
#define PATH_FILES                                                                                 \
	"common.glsl", "surface.glsl", "envcube.glsl", "lighting.glsl", "optics.glsl",             \
	    "cubemaps.glsl", "path.glsl"
#define PATH_COUNT 7
enum { MAX_FILES = 12 };

static const struct {
	const char *files[MAX_FILES]; /* fragment stage, in order */
	size_t count;
	const char *vertex[3]; /* NULL: the fullscreen triangle */
	size_t vcount;
	int variant;
	bool compute; /* the files as one compute stage (no vertex stage) */
} programs[PROG_COUNT] = {
    [PROG_RAYGEN] = {{"camera.glsl", "raygen.glsl"}, 2, {NULL}, 0, ALL_PASSES},
    [PROG_INTERSECT] =
        {{"common.glsl", "cubemaps.glsl", "intersect.glsl"}, 3, {NULL}, 0, ALL_PASSES},
    [PROG_SHADE] = {{PATH_FILES, "shade.glsl"}, PATH_COUNT + 1, {NULL}, 0, ALL_PASSES},
    [PROG_FUSED] =
        {{PATH_FILES, "quantize.glsl", "fused.glsl"}, PATH_COUNT + 2, {NULL}, 0, ALL_PASSES},
    [PROG_DISPLAY] = {{"quantize.glsl", "display.glsl"}, 2, {NULL}, 0, ALL_PASSES},
    [PROG_RASTER] =
        {{"raster.glsl"}, 1, {"common.glsl", "camera.glsl", "raster_vertex.glsl"}, 3, ALL_PASSES},
    [PROG_SHADOW] = {{"shadow.glsl"}, 1, {"common.glsl", "shadow_vertex.glsl"}, 2, ALL_PASSES},
    [PROG_FUSED_FIRST] = {{PATH_FILES, "camera.glsl", "quantize.glsl", "fused.glsl"},
                          PATH_COUNT + 3,
                          {NULL},
                          0,
                          FIRST_PASS},
    [PROG_ENVIRONMENT] = {{PATH_FILES, "environment.glsl"}, PATH_COUNT + 1, {NULL}, 0, ALL_PASSES},
    [PROG_SHADING] = {{PATH_FILES, "shading.glsl"}, PATH_COUNT + 1, {NULL}, 0, ALL_PASSES},
    [PROG_NEXTRAY] = {{PATH_FILES, "nextray.glsl"}, PATH_COUNT + 1, {NULL}, 0, ALL_PASSES},
    [PROG_RESOLVE] = {{"common.glsl", "camera.glsl", "visibility.glsl", "resolve.glsl"},
                      4,
                      {NULL},
                      0,
                      ALL_PASSES},
    [PROG_FUSED_RASTER] = {{PATH_FILES, "camera.glsl", "visibility.glsl", "quantize.glsl",
                            "fused.glsl"},
                           PATH_COUNT + 4,
                           {NULL},
                           0,
                           RASTER_FIRST_PASS},
    [PROG_PRIMARY] = {{"common.glsl", "camera.glsl", "primary.glsl"}, 3, {NULL}, 0, ALL_PASSES},
    [PROG_FUSED_COMPUTE] =
        {{PATH_FILES, "quantize.glsl", "fused.glsl"}, PATH_COUNT + 2, {NULL}, 0, ALL_PASSES, true},
    [PROG_FUSED_FIRST_COMPUTE] = {{PATH_FILES, "camera.glsl", "quantize.glsl", "fused.glsl"},
                                  PATH_COUNT + 3,
                                  {NULL},
                                  0,
                                  FIRST_PASS,
                                  true},
    [PROG_FUSED_RASTER_COMPUTE] = {{PATH_FILES, "camera.glsl", "visibility.glsl", "quantize.glsl",
                                    "fused.glsl"},
                                   PATH_COUNT + 4,
                                   {NULL},
                                   0,
                                   RASTER_FIRST_PASS,
                                   true},
};

/* The uniforms' names, in the order of the U_* enum. */
static const char *const uniform_names[U_COUNT] = {
    [U_NODES] = "u_nodes",
    [U_TRIS] = "u_tris",
    [U_NORMALS] = "u_normals",
    [U_MATERIALS] = "u_materials",
    [U_NODE_COUNT] = "u_node_count",
    [U_GRID_ORIGIN] = "u_grid_origin",
    [U_GRID_STEP] = "u_grid_step",
    [U_TRI_COUNT] = "u_tri_count",
    [U_MATERIAL_COUNT] = "u_material_count",
    [U_SPAWN_SCALE] = "u_spawn_scale",
    [U_SPAWN_FLOOR] = "u_spawn_floor",
    [U_AMBIENT] = "u_ambient",
    [U_LIGHT_POS] = "u_light_pos",
    [U_LIGHT_COLOR] = "u_light_color",
    [U_ENV_CENTER] = "u_env_center",
    [U_ENV_HALF] = "u_env_half",
    [U_ENV_COLOR] = "u_env_color",
    [U_ENV_GRID] = "u_env_grid",
    [U_ENV_LINE_WIDTH] = "u_env_line_width",
    [U_ENV_LINE_SCALE] = "u_env_line_scale",
    [U_SHADOW] = "u_shadow",
    [U_SHADOW_SIZE] = "u_shadow_size",
    [U_SHADOW_FILTER] = "u_shadow_filter",
    [U_EYE] = "u_eye",
    [U_FWD] = "u_fwd",
    [U_RIGHT] = "u_right",
    [U_UP] = "u_up",
    [U_SIZE] = "u_size",
    [U_TAN] = "u_tan",
    [U_SHIFT] = "u_shift",
    [U_JITTER] = "u_jitter",
    [U_NEAR] = "u_near",
    [U_FAR] = "u_far",
    [U_ORIG] = "u_orig",
    [U_DIR] = "u_dir",
    [U_ACC] = "u_acc",
    [U_CNT] = "u_cnt",
    [U_HIT] = "u_hit",
    [U_VIS] = "u_vis",
    [U_ENVMAP] = "u_envmap",
    [U_ENVMAP_ON] = "u_envmap_on",
    [U_ENVMAP_AFTER] = "u_envmap_after",
    [U_OBJECTS] = "u_objects",
    [U_OBJMAP_ON] = "u_objmap_on",
    [U_OBJMAP0] = "u_objmap0",
    [U_OBJMAP0 + 1] = "u_objmap1",
    [U_OBJMAP0 + 2] = "u_objmap2",
    [U_OBJMAP0 + 3] = "u_objmap3",
    [U_LIGHT] = "u_light",
    [U_AXIS] = "u_axis",
    [U_SIGN] = "u_sign",
    [U_INSTANCES] = "u_instances",
    [U_TOP_BASE] = "u_top_base",
    [U_TOP_COUNT] = "u_top_count",
    [U_INSTANCE_COUNT] = "u_instance_count",
    [U_PROTO_INSTANCES] = "u_proto_instances",
    [U_DISPLAY] = "u_display",
    [U_EXTENT] = "u_extent",
    [U_STORES] = "u_stores",
};
_Static_assert(RS_RENDER_MAX_MIRROR_OBJECTS == 4, "one u_objmapN name per mirror object");

static const char *kernel_source(const char *name)
{
	/* test builds only (gles_seams.h): a kernel's source replaced */
	const char *override = rs__gles_kernel_override ? rs__gles_kernel_override(name) : NULL;
	if (override)
		return override;
	for (const struct rs_gles_kernel *k = rs_gles_kernels; k->name; ++k)
		if (strcmp(k->name, name) == 0)
			return k->source;
	return NULL;
}

/* Line `line` (1-based) of `src` into out, trimmed. */
static void source_line(const char *src, int line, char *out, size_t cap)
{
	out[0] = '\0';
	for (int l = 1; src && *src && l < line; ++src)
		if (*src == '\n')
			++l;
	if (!src)
		return;
	while (*src == ' ' || *src == '\t')
		++src;
	size_t n = strcspn(src, "\n");
	if (n >= cap)
		n = cap - 1;
	memcpy(out, src, n);
	out[n] = '\0';
}

/* Drivers print "<string>:<line>" (Mesa "0:12(5): error: ...", others "ERROR: 0:12: ...").
 * Not every driver reports #line's source number, so file k starts at line 1000 (k + 1)
 * (LINE_BASE) and the line alone says which file it is. */
static enum rs_status compile_error(const char *log, const char *const *files, size_t count,
                                    struct rs_error *err)
{
	char first[160];
	size_t n = strcspn(log, "\n");
	snprintf(first, sizeof first, "%.*s", (int)(n < 159 ? n : 159), log);
	for (const char *p = log; *p; ++p) {
		int string, line;
		if ((p == log || p[-1] < '0' || p[-1] > '9') &&
		    sscanf(p, "%d:%d", &string, &line) == 2 && line >= LINE_BASE &&
		    (size_t)(line / LINE_BASE) <= count) {
			const char *file = files[line / LINE_BASE - 1];
			line %= LINE_BASE;
			char text[96];
			source_line(kernel_source(file), line, text, sizeof text);
			return rs_error_set(err, RS_ERR_DEVICE,
			                    "gles: kernel %s line %d does not compile: %s [%s]",
			                    file, line, first, text);
		}
	}
	return rs_error_set(err, RS_ERR_DEVICE, "gles: a kernel does not compile: %s", first);
}

static enum rs_status compile(const struct rs_gl *gl, GLenum type, const char **parts, GLsizei n,
                              const char *const *files, size_t count, GLuint *out,
                              struct rs_error *err)
{
	GLuint sh = gl->CreateShader(type);
	gl->ShaderSource(sh, n, parts, NULL);
	gl->CompileShader(sh);
	GLint ok = 0;
	gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		char log[1024] = "";
		gl->GetShaderInfoLog(sh, sizeof log, NULL, log);
		gl->DeleteShader(sh);
		return compile_error(log, files, count, err);
	}
	*out = sh;
	return RS_OK;
}

/* Sources of one stage: prelude, defines (RS_COMPUTE: 1 in a compute stage, which the files
 * test for their entry point), then each file at line LINE_BASE * (k + 1). */
static enum rs_status stage(const struct rs_gl *gl, GLenum type, const char *version,
                            const char *const *files, size_t count, const char *defines,
                            GLuint *out, struct rs_error *err)
{
	RS_ASSERT(count > 0 && count <= MAX_FILES);
	const char *parts[4 + 2 * MAX_FILES];
	char lines[MAX_FILES][32];
	GLsizei n = 0;
	parts[n++] = version;
	parts[n++] = precision;
	parts[n++] = defines;
	parts[n++] =
	    type == GL_COMPUTE_SHADER ? "#define RS_COMPUTE 1\n" : "#define RS_COMPUTE 0\n";
	for (size_t i = 0; i < count; ++i) {
		const char *src = kernel_source(files[i]);
		if (!src)
			return rs_error_set(err, RS_ERR_INVALID, "gles: no kernel named %s",
			                    files[i]);
		snprintf(lines[i], sizeof lines[i], "\n#line %zu\n", (i + 1) * LINE_BASE + 1);
		parts[n++] = lines[i];
		parts[n++] = src;
	}
	return compile(gl, type, parts, n, files, count, out, err);
}

/* A program of the vertex files (NULL: the fullscreen triangle) and fragment files, or with
 * `compute` of the files as one compute stage. */
static enum rs_status program(const struct rs_gl *gl, const char *version,
                              const char *const *vfiles, size_t vcount, const char *const *files,
                              size_t count, const char *defines, bool compute, GLuint *out,
                              struct rs_error *err)
{
	static const char *const fullscreen[1] = {"fullscreen.glsl"};
	*out = 0;
	GLuint vs = 0, fs = 0;
	enum rs_status st = RS_OK;
	if (!compute)
		st = stage(gl, GL_VERTEX_SHADER, version, vfiles ? vfiles : fullscreen,
		           vfiles ? vcount : 1, defines, &vs, err);
	if (st == RS_OK)
		st = stage(gl, compute ? GL_COMPUTE_SHADER : GL_FRAGMENT_SHADER, version, files,
		           count, defines, &fs, err);
	if (st != RS_OK) {
		if (vs)
			gl->DeleteShader(vs);
		return st;
	}
	GLuint prog = gl->CreateProgram();
	if (vs)
		gl->AttachShader(prog, vs);
	gl->AttachShader(prog, fs);
	gl->LinkProgram(prog);
	if (vs)
		gl->DeleteShader(vs);
	gl->DeleteShader(fs);
	GLint ok = 0;
	gl->GetProgramiv(prog, GL_LINK_STATUS, &ok);
	if (!ok) {
		char log[512] = "";
		gl->GetProgramInfoLog(prog, sizeof log, NULL, log);
		gl->DeleteProgram(prog);
		log[strcspn(log, "\n")] = '\0';
		return rs_error_set(err, RS_ERR_DEVICE, "gles: kernel %s does not link: %s",
		                    files[count - 1], log);
	}
	*out = prog;
	return RS_OK;
}

enum rs_status rs_gles_programs_build(struct gles *g, const char *const prelude[3],
                                      struct rs_error *err)
{
	bool used[PROG_COUNT] = {false};
	used[PROG_DISPLAY] = true;
	used[PROG_SHADOW] = g->desc.shadows == RS_SHADOW_MAP;
	for (int k = 0; k < PLAN_COUNT; ++k)
		for (uint32_t i = 0; i < g->plans[k].count; ++i)
			used[g->plans[k].steps[i].prog] = true;
	bool buffers = g->storage == RS_SCENE_STORAGE_BUFFER;
	const char *version = buffers ? g->buffer_glsl : "#version 300 es\n";
	/* compute needs GLES 3.1; a buffer-texture line is 3.1 or later already */
	const char *cs_version = buffers ? g->buffer_glsl : g->compute_glsl;
	for (int i = 0; i < PROG_COUNT; ++i) {
		struct rs_gles_program *p = &g->prog[i];
		if (!used[i])
			continue;
		bool cs = programs[i].compute;
		RS_ASSERT(!cs || g->compute_glsl); /* set_scene refused compute without it */
		const char *const *vs = programs[i].vcount ? programs[i].vertex : NULL;
		enum rs_status st = program(
		    &g->gl, cs ? cs_version : version, vs, programs[i].vcount, programs[i].files,
		    programs[i].count, prelude[programs[i].variant], cs, &p->id, err);
		if (st != RS_OK)
			return st;
		p->compute = cs;
		for (int u = 0; u < U_COUNT; ++u)
			p->loc[u] = g->gl.GetUniformLocation(p->id, uniform_names[u]);
	}
	return RS_OK;
}

void rs_gles_programs_delete(struct gles *g)
{
	for (int i = 0; i < PROG_COUNT; ++i)
		if (g->prog[i].id)
			g->gl.DeleteProgram(g->prog[i].id);
	memset(g->prog, 0, sizeof g->prog);
}

enum rs_status rs_gles_program_compile(const struct rs_gl *gl, const char *version,
                                       const char *const *files, size_t count, GLuint *out,
                                       struct rs_error *err)
{
	return program(gl, version, NULL, 0, files, count, "", false, out, err);
}
