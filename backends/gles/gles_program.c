/* Kernel programs: sources assembled from the embedded files with a version line and the
 * scene's #defines; compile errors translated into one line naming file, line and text. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"
#include "kernels.h"

#define LINE_BASE 1000

/* Every kernel runs at full precision (ray tracing in mediump would be meaningless). */
static const char prelude[] = "precision highp float;\n"
                              "precision highp int;\n"
                              "precision highp sampler2D;\n"
                              "precision highp sampler2DArray;\n";

/* Test seam (gles_internal.h): one kernel's source replaced, to check compile errors. */
static const char *override_name, *override_source;

void rs__gles_override_kernel(const char *name, const char *source)
{
	override_name = name;
	override_source = source;
}

static const char *kernel_source(const char *name)
{
	if (override_name && strcmp(override_name, name) == 0)
		return override_source;
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

/* Sources of one stage: prelude, defines, then each file at line LINE_BASE * (k + 1). */
static enum rs_status stage(const struct rs_gl *gl, GLenum type, const char *version,
                            const char *const *files, size_t count, const char *defines,
                            GLuint *out, struct rs_error *err)
{
	enum { MAX_FILES = 6 };
	RS_ASSERT(count > 0 && count <= MAX_FILES);
	const char *parts[3 + 2 * MAX_FILES];
	char lines[MAX_FILES][32];
	GLsizei n = 0;
	parts[n++] = version;
	parts[n++] = prelude;
	parts[n++] = defines;
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

enum rs_status rs_gles_program(const struct rs_gl *gl, const char *version,
                               const char *const *vfiles, size_t vcount, const char *const *files,
                               size_t count, const char *defines, GLuint *out, struct rs_error *err)
{
	static const char *const fullscreen[1] = {"fullscreen.glsl"};
	*out = 0;
	GLuint vs = 0, fs = 0;
	enum rs_status st = stage(gl, GL_VERTEX_SHADER, version, vfiles ? vfiles : fullscreen,
	                          vfiles ? vcount : 1, defines, &vs, err);
	if (st == RS_OK)
		st = stage(gl, GL_FRAGMENT_SHADER, version, files, count, defines, &fs, err);
	if (st != RS_OK) {
		if (vs)
			gl->DeleteShader(vs);
		return st;
	}
	GLuint prog = gl->CreateProgram();
	gl->AttachShader(prog, vs);
	gl->AttachShader(prog, fs);
	gl->LinkProgram(prog);
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

enum rs_status rs_gles_check(const struct rs_gl *gl, const char *what, struct rs_error *err)
{
	GLenum e = gl->GetError();
	if (e == GL_NO_ERROR)
		return RS_OK;
	while (gl->GetError() != GL_NO_ERROR) {
	}
	if (e == GL_OUT_OF_MEMORY)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of GPU memory (%s)", what);
	return rs_error_set(err, RS_ERR_DEVICE, "gles: GL error 0x%04x after %s", (unsigned)e,
	                    what);
}
