/* Test seam (gles_seams.h; test builds only): GPU out-of-memory on demand. When armed before a
 * renderer loads its GL table, the allocating entry points (texture and renderbuffer
 * storage: glTexImage2D/3D, glTexStorage2D, glRenderbufferStorage; buffer storage,
 * glBufferData; framebuffer and vertex array objects) are wrapped: allocation number N is not made
 * and glGetError reports GL_OUT_OF_MEMORY for it, as a driver that ran out would. The wrappers also
 * keep the set of live GL object names, so a test can see that a failed call deletes what it made.
 * One renderer at a time (the state is static). */
#include <string.h>

#include "gles_seams.h"

enum { KIND_TEXTURE, KIND_RENDERBUFFER, KIND_BUFFER, KIND_FRAMEBUFFER, KIND_VERTEX_ARRAY, KINDS };
#define MAX_LIVE 512

static bool armed;
static struct rs_gl real;
static long fail_at, seen;
static bool fired;
static GLenum pending;
static GLuint live[KINDS][MAX_LIVE];
static long live_count[KINDS];
static bool overflow;

void rs__gl_fault_wrap(bool on)
{
	armed = on;
	memset(live_count, 0, sizeof live_count);
	overflow = false;
	rs__gl_fault_fail_at(0);
}

void rs__gl_fault_fail_at(long n)
{
	fail_at = n;
	seen = 0;
	fired = false;
	pending = GL_NO_ERROR;
}

void rs__gl_fault_counts(struct rs__gl_fault_counts *out)
{
	out->allocations = seen;
	out->fired = fired;
	out->textures = live_count[KIND_TEXTURE];
	out->renderbuffers = live_count[KIND_RENDERBUFFER];
	out->buffers = live_count[KIND_BUFFER];
	out->framebuffers = live_count[KIND_FRAMEBUFFER];
	out->vertex_arrays = live_count[KIND_VERTEX_ARRAY];
	out->overflow = overflow;
}

/* Count one allocation; false when this one fails. */
static bool allocate(void)
{
	if (++seen != fail_at)
		return true;
	fired = true;
	pending = GL_OUT_OF_MEMORY;
	return false;
}

static void add(int kind, GLsizei n, const GLuint *names)
{
	for (GLsizei i = 0; i < n; ++i) {
		if (!names[i])
			continue;
		if (live_count[kind] == MAX_LIVE) {
			overflow = true;
			return;
		}
		live[kind][live_count[kind]++] = names[i];
	}
}

/* GL ignores names that are 0 or not live, and so does this. */
static void drop(int kind, GLsizei n, const GLuint *names)
{
	for (GLsizei i = 0; i < n; ++i)
		for (long k = 0; names[i] && k < live_count[kind]; ++k)
			if (live[kind][k] == names[i]) {
				live[kind][k] = live[kind][--live_count[kind]];
				break;
			}
}

static GLenum GL_APIENTRY get_error(void)
{
	GLenum e = pending;
	pending = GL_NO_ERROR;
	return e != GL_NO_ERROR ? e : real.GetError();
}

static void GL_APIENTRY tex_image_2d(GLenum target, GLint level, GLint internal, GLsizei w,
                                     GLsizei h, GLint border, GLenum format, GLenum type,
                                     const void *pixels)
{
	if (allocate())
		real.TexImage2D(target, level, internal, w, h, border, format, type, pixels);
}

static void GL_APIENTRY tex_image_3d(GLenum target, GLint level, GLint internal, GLsizei w,
                                     GLsizei h, GLsizei d, GLint border, GLenum format, GLenum type,
                                     const void *pixels)
{
	if (allocate())
		real.TexImage3D(target, level, internal, w, h, d, border, format, type, pixels);
}

static void GL_APIENTRY tex_storage_2d(GLenum target, GLsizei levels, GLenum internal, GLsizei w,
                                       GLsizei h)
{
	if (allocate())
		real.TexStorage2D(target, levels, internal, w, h);
}

static void GL_APIENTRY renderbuffer_storage(GLenum target, GLenum internal, GLsizei w, GLsizei h)
{
	if (allocate())
		real.RenderbufferStorage(target, internal, w, h);
}

static void GL_APIENTRY buffer_data(GLenum target, GLsizeiptr size, const void *data, GLenum usage)
{
	if (allocate())
		real.BufferData(target, size, data, usage);
}

/* glGen<X> and glDelete<X> tracking the live names of `kind`; with `counted`, creating
 * the objects is an allocation, and a failed one leaves the names 0. */
#define RS_TRACKED(kind, X, counted)                                                               \
	static void GL_APIENTRY gen_##X(GLsizei n, GLuint *names)                                  \
	{                                                                                          \
		if ((counted) && !allocate()) {                                                    \
			memset(names, 0, (size_t)n * sizeof *names);                               \
			return;                                                                    \
		}                                                                                  \
		real.Gen##X(n, names);                                                             \
		add(kind, n, names);                                                               \
	}                                                                                          \
	static void GL_APIENTRY delete_##X(GLsizei n, const GLuint *names)                         \
	{                                                                                          \
		drop(kind, n, names);                                                              \
		real.Delete##X(n, names);                                                          \
	}
RS_TRACKED(KIND_TEXTURE, Textures, false)
RS_TRACKED(KIND_RENDERBUFFER, Renderbuffers, false)
RS_TRACKED(KIND_BUFFER, Buffers, false)
RS_TRACKED(KIND_FRAMEBUFFER, Framebuffers, true)
RS_TRACKED(KIND_VERTEX_ARRAY, VertexArrays, true)
#undef RS_TRACKED

void rs__gl_fault_hook(struct rs_gl *gl)
{
	if (!armed)
		return;
	real = *gl;
	gl->GetError = get_error;
	gl->TexImage2D = tex_image_2d;
	gl->TexImage3D = tex_image_3d;
	gl->TexStorage2D = tex_storage_2d;
	gl->RenderbufferStorage = renderbuffer_storage;
	gl->BufferData = buffer_data;
	gl->GenTextures = gen_Textures;
	gl->DeleteTextures = delete_Textures;
	gl->GenRenderbuffers = gen_Renderbuffers;
	gl->DeleteRenderbuffers = delete_Renderbuffers;
	gl->GenBuffers = gen_Buffers;
	gl->DeleteBuffers = delete_Buffers;
	gl->GenFramebuffers = gen_Framebuffers;
	gl->DeleteFramebuffers = delete_Framebuffers;
	gl->GenVertexArrays = gen_VertexArrays;
	gl->DeleteVertexArrays = delete_VertexArrays;
}
