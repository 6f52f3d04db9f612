/* raystream-peer-tmb's GL side (peer_gl.h): EGL context, the peer's textures, its program.
 * The fragment shader is three-mesh-bvh's chunks verbatim (DIR/bvh.glsl, as the package
 * exports them) after a GLSL ES 3.00 header, then a main that makes the primary ray exactly
 * as rs_trace_view_ray() does (centre of the pixel, row 0 at the top, unit direction) and
 * writes the first hit's triangle slot and distance into an RGBA32UI target (core GLES 3.0:
 * no float-target extension needed, and RGBA_INTEGER is the readback every context allows). */
#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "peer_gl.h"

#define PEER_MAX_TEXTURES 4

struct peer_gl {
	EGLDisplay display;
	EGLContext context;
	GLuint textures[PEER_MAX_TEXTURES];
	GLuint program, fbo, target, vao;
	GLint u_eye, u_fwd, u_right, u_up, u_view;
	uint32_t width, height;
	uint32_t *texels; /* readback, 4 words per pixel */
	char renderer[128];
};

static const char vertex_src[] = "#version 300 es\n"
                                 "void main() {\n"
                                 "  vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1),\n"
                                 "                float((gl_VertexID & 2) * 2 - 1));\n"
                                 "  gl_Position = vec4(p, 0.0, 1.0);\n"
                                 "}\n";

static const char fragment_head[] = "#version 300 es\n"
                                    "precision highp float;\n"
                                    "precision highp int;\n"
                                    "precision highp sampler2D;\n"
                                    "precision highp usampler2D;\n"
                                    "precision highp isampler2D;\n";

/* u_view: tan(fov_y / 2), width, height; rs_trace_view_ray() with no shift or offset. */
static const char fragment_main[] =
    "uniform BVH bvh;\n"
    "uniform vec3 u_eye, u_fwd, u_right, u_up;\n"
    "uniform vec3 u_view;\n"
    "layout(location = 0) out uvec4 o_hit;\n"
    "void main() {\n"
    "  float px = gl_FragCoord.x, py = u_view.z - gl_FragCoord.y;\n"
    "  float sx = (2.0 * px / u_view.y - 1.0) * (u_view.y / u_view.z) * u_view.x;\n"
    "  float sy = (1.0 - 2.0 * py / u_view.z) * u_view.x;\n"
    "  vec3 dir = normalize(u_fwd + sx * u_right + sy * u_up);\n"
    "  uvec4 faceIndices = uvec4(0u);\n"
    "  vec3 faceNormal = vec3(0.0), barycoord = vec3(0.0);\n"
    "  float side = 1.0, dist = 0.0;\n"
    "  bool hit = bvhIntersectFirstHit(bvh, u_eye, dir, faceIndices, faceNormal, barycoord,\n"
    "                                  side, dist);\n"
    "  o_hit = hit ? uvec4(faceIndices.w, floatBitsToUint(dist), 0u, 0u)\n"
    "              : uvec4(0xffffffffu, floatBitsToUint(-1.0), 0u, 0u);\n"
    "}\n";

static const char *const sampler_names[PEER_MAX_TEXTURES] = {"index", "position", "bvhBounds",
                                                             "bvhContents"};

static enum rs_status open_context(struct peer_gl *gl, struct rs_error *err)
{
	static const EGLint config_attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
	                                      EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
	static const EGLint context_attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
	EGLDeviceEXT devices[8];
	EGLint device_count = 0;
	PFNEGLQUERYDEVICESEXTPROC query =
	    (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
	if (query && !query(8, devices, &device_count))
		device_count = 0;
	/* the platforms rs_egl tries, device then surfaceless, or the one RS_EGL_PLATFORM names
	 * as rs_egl reads it (gbm is not offered here: name device for a GPU) */
	const char *only = getenv("RS_EGL_PLATFORM");
	bool devices_too = !only || !*only || !strcmp(only, "device");
	bool surfaceless = !only || !*only || !strcmp(only, "surfaceless");
	if (!devices_too && !surfaceless)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "RS_EGL_PLATFORM=%s: the peer opens device or surfaceless",
		                    only);
	if (!devices_too)
		device_count = 0;
	for (EGLint i = 0; i < device_count + (surfaceless ? 1 : 0); ++i) {
		gl->display = i < device_count
		                  ? eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL)
		                  : eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA,
		                                          EGL_DEFAULT_DISPLAY, NULL);
		EGLConfig config;
		EGLint n = 0;
		if (gl->display == EGL_NO_DISPLAY || !eglInitialize(gl->display, NULL, NULL) ||
		    !eglBindAPI(EGL_OPENGL_ES_API) ||
		    !eglChooseConfig(gl->display, config_attrs, &config, 1, &n))
			continue;
		gl->context = eglCreateContext(gl->display, n ? config : EGL_NO_CONFIG_KHR,
		                               EGL_NO_CONTEXT, context_attrs);
		if (gl->context != EGL_NO_CONTEXT &&
		    eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context))
			return RS_OK;
	}
	return rs_error_set(err, RS_ERR_DEVICE,
	                    "no GLES 3 context on EGL (device or surfaceless platform, 0x%04x)",
	                    (unsigned)eglGetError());
}

/* DIR/NAME's bytes, NUL-terminated; NULL with `err` set when it cannot be read. */
static char *read_in(const char *dir, const char *name, size_t *out_size, struct rs_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "rb");
	char *data = NULL;
	long size = -1;
	if (f && fseek(f, 0, SEEK_END) == 0 && (size = ftell(f)) >= 0 &&
	    fseek(f, 0, SEEK_SET) == 0 && (data = malloc((size_t)size + 1)) &&
	    fread(data, 1, (size_t)size, f) == (size_t)size) {
		data[size] = '\0';
		*out_size = (size_t)size;
		fclose(f);
		return data;
	}
	if (f)
		fclose(f);
	free(data);
	rs_error_set(err, RS_ERR_IO, "%s: cannot read", path);
	return NULL;
}

/* One texture of textures.txt: the formats three-mesh-bvh's MeshBVHUniformStruct makes. */
static enum rs_status load_texture(struct peer_gl *gl, const char *dir, const char *name,
                                   const char *format, uint32_t w, uint32_t h, struct rs_error *err)
{
	static const struct {
		const char *name;
		GLenum internal, format, type;
		size_t bytes;
	} formats[] = {{"RGBA32F", GL_RGBA32F, GL_RGBA, GL_FLOAT, 16},
	               {"RGBA32UI", GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT, 16},
	               {"RG32UI", GL_RG32UI, GL_RG_INTEGER, GL_UNSIGNED_INT, 8}};
	int slot = -1, f = -1;
	for (int i = 0; i < PEER_MAX_TEXTURES; ++i)
		slot = strcmp(name, sampler_names[i]) ? slot : i;
	for (int i = 0; i < 3; ++i)
		f = strcmp(format, formats[i].name) ? f : i;
	if (slot < 0 || f < 0 || w == 0 || h == 0 || w > 16384 || h > 16384)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "%s/textures.txt: '%s %s %ux%u' is not a texture of BVH", dir,
		                    name, format, w, h);
	char file[48];
	snprintf(file, sizeof file, "%s.bin", name);
	size_t size = 0;
	char *data = read_in(dir, file, &size, err);
	if (!data)
		return err->status;
	if (size != (size_t)w * h * formats[f].bytes) {
		free(data);
		return rs_error_set(err, RS_ERR_INVALID, "%s/%s: %zu bytes, %ux%u %s needs %zu",
		                    dir, file, size, w, h, format,
		                    (size_t)w * h * formats[f].bytes);
	}
	glGenTextures(1, &gl->textures[slot]);
	glActiveTexture(GL_TEXTURE0 + (GLenum)slot);
	glBindTexture(GL_TEXTURE_2D, gl->textures[slot]);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	glTexImage2D(GL_TEXTURE_2D, 0, (GLint)formats[f].internal, (GLsizei)w, (GLsizei)h, 0,
	             formats[f].format, formats[f].type, data);
	free(data);
	return glGetError() == GL_NO_ERROR
	           ? RS_OK
	           : rs_error_set(err, RS_ERR_DEVICE, "%s/%s: glTexImage2D failed", dir, file);
}

static enum rs_status load_textures(struct peer_gl *gl, const char *dir, struct rs_error *err)
{
	size_t size;
	char *text = read_in(dir, "textures.txt", &size, err);
	if (!text)
		return err->status;
	char *save = NULL;
	enum rs_status st = RS_OK;
	for (char *line = strtok_r(text, "\n", &save); line && st == RS_OK;
	     line = strtok_r(NULL, "\n", &save)) {
		char name[32], format[16];
		unsigned w, h;
		if (sscanf(line, "%31s %15s %u %u", name, format, &w, &h) != 4)
			st =
			    rs_error_set(err, RS_ERR_INVALID,
			                 "%s/textures.txt: '%s' is not NAME FORMAT W H", dir, line);
		else
			st = load_texture(gl, dir, name, format, w, h, err);
	}
	free(text);
	for (int i = 0; i < PEER_MAX_TEXTURES && st == RS_OK; ++i)
		if (!gl->textures[i])
			st = rs_error_set(err, RS_ERR_INVALID, "%s/textures.txt: no texture '%s'",
			                  dir, sampler_names[i]);
	return st;
}

static GLuint compile(GLenum kind, const char *const *parts, GLsizei count, struct rs_error *err)
{
	GLuint s = glCreateShader(kind);
	glShaderSource(s, count, parts, NULL);
	glCompileShader(s);
	GLint ok = 0;
	glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		char log[512] = "";
		glGetShaderInfoLog(s, sizeof log, NULL, log);
		for (char *c = log; *c; ++c)
			*c = *c == '\n' ? ' ' : *c;
		rs_error_set(err, RS_ERR_DEVICE, "the peer's shader does not compile: %s", log);
		glDeleteShader(s);
		return 0;
	}
	return s;
}

static enum rs_status make_program(struct peer_gl *gl, const char *dir, struct rs_error *err)
{
	size_t size;
	char *chunks = read_in(dir, "bvh.glsl", &size, err);
	if (!chunks)
		return err->status;
	const char *vs[] = {vertex_src}, *fs[] = {fragment_head, chunks, fragment_main};
	GLuint v = compile(GL_VERTEX_SHADER, vs, 1, err);
	GLuint f = v ? compile(GL_FRAGMENT_SHADER, fs, 3, err) : 0;
	free(chunks);
	if (!f) {
		glDeleteShader(v);
		return err->status;
	}
	gl->program = glCreateProgram();
	glAttachShader(gl->program, v);
	glAttachShader(gl->program, f);
	glLinkProgram(gl->program);
	glDeleteShader(v);
	glDeleteShader(f);
	GLint ok = 0;
	glGetProgramiv(gl->program, GL_LINK_STATUS, &ok);
	if (!ok)
		return rs_error_set(err, RS_ERR_DEVICE, "the peer's program does not link");
	glUseProgram(gl->program);
	for (int i = 0; i < PEER_MAX_TEXTURES; ++i) {
		char name[32];
		snprintf(name, sizeof name, "bvh.%s", sampler_names[i]);
		glUniform1i(glGetUniformLocation(gl->program, name), i);
	}
	gl->u_eye = glGetUniformLocation(gl->program, "u_eye");
	gl->u_fwd = glGetUniformLocation(gl->program, "u_fwd");
	gl->u_right = glGetUniformLocation(gl->program, "u_right");
	gl->u_up = glGetUniformLocation(gl->program, "u_up");
	gl->u_view = glGetUniformLocation(gl->program, "u_view");
	return RS_OK;
}

static enum rs_status make_target(struct peer_gl *gl, struct rs_error *err)
{
	glGenTextures(1, &gl->target);
	glActiveTexture(GL_TEXTURE0 + PEER_MAX_TEXTURES);
	glBindTexture(GL_TEXTURE_2D, gl->target);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32UI, (GLsizei)gl->width, (GLsizei)gl->height);
	glGenFramebuffers(1, &gl->fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, gl->fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, gl->target, 0);
	glGenVertexArrays(1, &gl->vao);
	glBindVertexArray(gl->vao);
	glViewport(0, 0, (GLsizei)gl->width, (GLsizei)gl->height);
	if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		return rs_error_set(err, RS_ERR_DEVICE, "the peer's RGBA32UI target is incomplete");
	gl->texels = malloc((size_t)gl->width * gl->height * 4 * sizeof *gl->texels);
	return gl->texels ? RS_OK : rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
}

enum rs_status peer_gl_create(const char *dir, uint32_t width, uint32_t height,
                              struct peer_gl **out, struct rs_error *err)
{
	RS_ASSERT(dir && out && width && height);
	*out = NULL;
	struct peer_gl *gl = calloc(1, sizeof *gl);
	if (!gl)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
	gl->display = EGL_NO_DISPLAY;
	gl->context = EGL_NO_CONTEXT;
	gl->width = width;
	gl->height = height;
	enum rs_status st = open_context(gl, err);
	if (st == RS_OK) {
		snprintf(gl->renderer, sizeof gl->renderer, "%s",
		         (const char *)glGetString(GL_RENDERER));
		st = load_textures(gl, dir, err);
	}
	if (st == RS_OK)
		st = make_program(gl, dir, err);
	if (st == RS_OK)
		st = make_target(gl, err);
	if (gl->context != EGL_NO_CONTEXT)
		eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	if (st != RS_OK) {
		peer_gl_destroy(&gl);
		return st;
	}
	*out = gl;
	return RS_OK;
}

void peer_gl_destroy(struct peer_gl **glp)
{
	struct peer_gl *gl = glp ? *glp : NULL;
	if (!gl)
		return;
	if (gl->context != EGL_NO_CONTEXT &&
	    eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context)) {
		glDeleteTextures(PEER_MAX_TEXTURES, gl->textures);
		glDeleteTextures(1, &gl->target);
		glDeleteFramebuffers(1, &gl->fbo);
		glDeleteVertexArrays(1, &gl->vao);
		glDeleteProgram(gl->program);
		eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	}
	if (gl->context != EGL_NO_CONTEXT)
		eglDestroyContext(gl->display, gl->context);
	free(gl->texels);
	free(gl);
	*glp = NULL;
}

const char *peer_gl_renderer(const struct peer_gl *gl)
{
	return gl->renderer;
}

enum rs_status peer_gl_trace(struct peer_gl *gl, const struct rs_trace_view *view, double *out_ms,
                             struct rs_error *err)
{
	if (!eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context))
		return rs_error_set(err, RS_ERR_DEVICE, "eglMakeCurrent failed (0x%04x)",
		                    (unsigned)eglGetError());
	const double *v3[4] = {view->eye, view->fwd, view->right, view->up};
	GLint loc[4] = {gl->u_eye, gl->u_fwd, gl->u_right, gl->u_up};
	for (int i = 0; i < 4; ++i)
		glUniform3f(loc[i], (float)v3[i][0], (float)v3[i][1], (float)v3[i][2]);
	glUniform3f(gl->u_view, (float)view->tan_half_fov, (float)view->width, (float)view->height);
	glFinish();
	double t0 = rs_now_ms();
	glDrawArrays(GL_TRIANGLES, 0, 3);
	glFinish();
	*out_ms = rs_now_ms() - t0;
	GLenum e = glGetError();
	eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	return e == GL_NO_ERROR ? RS_OK
	                        : rs_error_set(err, RS_ERR_DEVICE,
	                                       "the peer's draw failed (0x%04x)", (unsigned)e);
}

enum rs_status peer_gl_read(struct peer_gl *gl, uint32_t *out_slot, float *out_dist,
                            struct rs_error *err)
{
	if (!eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context))
		return rs_error_set(err, RS_ERR_DEVICE, "eglMakeCurrent failed (0x%04x)",
		                    (unsigned)eglGetError());
	glReadPixels(0, 0, (GLsizei)gl->width, (GLsizei)gl->height, GL_RGBA_INTEGER,
	             GL_UNSIGNED_INT, gl->texels);
	GLenum e = glGetError();
	eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	if (e != GL_NO_ERROR)
		return rs_error_set(err, RS_ERR_DEVICE, "the peer's readback failed (0x%04x)",
		                    (unsigned)e);
	for (uint32_t y = 0; y < gl->height; ++y)
		for (uint32_t x = 0; x < gl->width; ++x) {
			const uint32_t *t =
			    gl->texels + 4 * ((size_t)(gl->height - 1 - y) * gl->width + x);
			size_t i = (size_t)y * gl->width + x;
			if (out_slot)
				out_slot[i] = t[0];
			if (out_dist)
				memcpy(&out_dist[i], &t[1], sizeof(float));
		}
	return RS_OK;
}
