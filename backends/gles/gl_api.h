/* The GL entry points the GLES module calls, loaded through the context's
 * get_proc_address: never linked directly, so one module serves an EGL GLES context and an
 * OSMesa desktop context (libOSMesa and libGLESv2 both export gl* symbols; linking one of
 * them would bind every call to it). Types and enums come from the GLES 3.2 header; every
 * entry point of the table is GLES 3.0 except the optional TexBuffer and compute calls. */
#ifndef RS_GLES_GL_API_H
#define RS_GLES_GL_API_H

#define GL_GLES_PROTOTYPES 0
#include <GLES3/gl32.h>
#include <stdbool.h>

#include "raystream/rs_status.h"

/* X(return type, name, parameter list) for every entry point used. */
#define RS_GL_FUNCS(X)                                                                             \
	X(void, ActiveTexture, (GLenum texture))                                                   \
	X(void, AttachShader, (GLuint program, GLuint shader))                                     \
	X(void, BindBuffer, (GLenum target, GLuint buffer))                                        \
	X(void, BindFramebuffer, (GLenum target, GLuint framebuffer))                              \
	X(void, BindTexture, (GLenum target, GLuint texture))                                      \
	X(void, BlitFramebuffer,                                                                   \
	  (GLint srcX0, GLint srcY0, GLint srcX1, GLint srcY1, GLint dstX0, GLint dstY0,           \
	   GLint dstX1, GLint dstY1, GLbitfield mask, GLenum filter))                              \
	X(void, BindRenderbuffer, (GLenum target, GLuint renderbuffer))                            \
	X(void, BindVertexArray, (GLuint array))                                                   \
	X(void, BufferData, (GLenum target, GLsizeiptr size, const void *data, GLenum usage))      \
	X(void, BufferSubData,                                                                     \
	  (GLenum target, GLintptr offset, GLsizeiptr size, const void *data))                     \
	X(GLenum, CheckFramebufferStatus, (GLenum target))                                         \
	X(void, ClearBufferfv, (GLenum buffer, GLint drawbuffer, const GLfloat *value))            \
	X(void, CompileShader, (GLuint shader))                                                    \
	X(GLuint, CreateProgram, (void))                                                           \
	X(GLuint, CreateShader, (GLenum type))                                                     \
	X(void, DeleteBuffers, (GLsizei n, const GLuint *buffers))                                 \
	X(void, DeleteFramebuffers, (GLsizei n, const GLuint *framebuffers))                       \
	X(void, DeleteProgram, (GLuint program))                                                   \
	X(void, DeleteRenderbuffers, (GLsizei n, const GLuint *renderbuffers))                     \
	X(void, DeleteShader, (GLuint shader))                                                     \
	X(void, DeleteTextures, (GLsizei n, const GLuint *textures))                               \
	X(void, DeleteVertexArrays, (GLsizei n, const GLuint *arrays))                             \
	X(void, DepthFunc, (GLenum func))                                                          \
	X(void, DepthMask, (GLboolean flag))                                                       \
	X(void, Disable, (GLenum cap))                                                             \
	X(void, DrawArrays, (GLenum mode, GLint first, GLsizei count))                             \
	X(void, DrawBuffers, (GLsizei n, const GLenum *bufs))                                      \
	X(void, Enable, (GLenum cap))                                                              \
	X(void, Finish, (void))                                                                    \
	X(void, FramebufferTexture2D,                                                              \
	  (GLenum target, GLenum attachment, GLenum textarget, GLuint texture, GLint level))       \
	X(void, GenBuffers, (GLsizei n, GLuint * buffers))                                         \
	X(void, GenFramebuffers, (GLsizei n, GLuint * framebuffers))                               \
	X(void, FramebufferRenderbuffer,                                                           \
	  (GLenum target, GLenum attachment, GLenum renderbuffertarget, GLuint renderbuffer))      \
	X(void, FramebufferTextureLayer,                                                           \
	  (GLenum target, GLenum attachment, GLuint texture, GLint level, GLint layer))            \
	X(void, GenRenderbuffers, (GLsizei n, GLuint * renderbuffers))                             \
	X(void, GenTextures, (GLsizei n, GLuint * textures))                                       \
	X(void, GenVertexArrays, (GLsizei n, GLuint * arrays))                                     \
	X(GLenum, GetError, (void))                                                                \
	X(void, GetIntegerv, (GLenum pname, GLint * data))                                         \
	X(void, GetProgramInfoLog,                                                                 \
	  (GLuint program, GLsizei bufSize, GLsizei * length, GLchar * infoLog))                   \
	X(void, GetProgramiv, (GLuint program, GLenum pname, GLint * params))                      \
	X(void, GetShaderInfoLog,                                                                  \
	  (GLuint shader, GLsizei bufSize, GLsizei * length, GLchar * infoLog))                    \
	X(void, GetShaderiv, (GLuint shader, GLenum pname, GLint * params))                        \
	X(const GLubyte *, GetString, (GLenum name))                                               \
	X(const GLubyte *, GetStringi, (GLenum name, GLuint index))                                \
	X(GLint, GetUniformLocation, (GLuint program, const GLchar *name))                         \
	X(GLboolean, IsEnabled, (GLenum cap))                                                      \
	X(void, LinkProgram, (GLuint program))                                                     \
	X(void, PixelStorei, (GLenum pname, GLint param))                                          \
	X(void, ReadBuffer, (GLenum src))                                                          \
	X(void, RenderbufferStorage,                                                               \
	  (GLenum target, GLenum internalformat, GLsizei width, GLsizei height))                   \
	X(void, ReadPixels,                                                                        \
	  (GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type,            \
	   void *pixels))                                                                          \
	X(void, ShaderSource,                                                                      \
	  (GLuint shader, GLsizei count, const GLchar *const *string, const GLint *length))        \
	X(void, TexImage2D,                                                                        \
	  (GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,        \
	   GLint border, GLenum format, GLenum type, const void *pixels))                          \
	X(void, TexImage3D,                                                                        \
	  (GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,        \
	   GLsizei depth, GLint border, GLenum format, GLenum type, const void *pixels))           \
	X(void, TexParameteri, (GLenum target, GLenum pname, GLint param))                         \
	X(void, TexStorage2D,                                                                      \
	  (GLenum target, GLsizei levels, GLenum internalformat, GLsizei width, GLsizei height))   \
	X(void, TexSubImage2D,                                                                     \
	  (GLenum target, GLint level, GLint xoffset, GLint yoffset, GLsizei width,                \
	   GLsizei height, GLenum format, GLenum type, const void *pixels))                        \
	X(void, Uniform1f, (GLint location, GLfloat v0))                                           \
	X(void, Uniform1i, (GLint location, GLint v0))                                             \
	X(void, Uniform2f, (GLint location, GLfloat v0, GLfloat v1))                               \
	X(void, Uniform3f, (GLint location, GLfloat v0, GLfloat v1, GLfloat v2))                   \
	X(void, Uniform3fv, (GLint location, GLsizei count, const GLfloat *value))                 \
	X(void, UseProgram, (GLuint program))                                                      \
	X(void, Viewport, (GLint x, GLint y, GLsizei width, GLsizei height))

#define RS_GL_MEMBER(ret, name, params) ret(GL_APIENTRY *name) params;
struct rs_gl {
	RS_GL_FUNCS(RS_GL_MEMBER)
	/* Optional (GLES 3.2 glTexBuffer, or the OES/EXT entry point of GLES 3.1; desktop GL
	 * 3.1): NULL where the context has none. */
	void(GL_APIENTRY *TexBuffer)(GLenum target, GLenum internalformat, GLuint buffer);
	/* Optional (GLES 3.1, desktop GL 4.3): compute dispatches writing images
	 * (rs_render_desc.kernels); all three or NULL where the context has none. */
	void(GL_APIENTRY *DispatchCompute)(GLuint groups_x, GLuint groups_y, GLuint groups_z);
	void(GL_APIENTRY *BindImageTexture)(GLuint unit, GLuint texture, GLint level,
	                                    GLboolean layered, GLint layer, GLenum access,
	                                    GLenum format);
	void(GL_APIENTRY *MemoryBarrier)(GLbitfield barriers);
};
#undef RS_GL_MEMBER

/* Fill *gl through `get`; RS_ERR_UNSUPPORTED naming the first entry point missing. */
enum rs_status rs_gl_load(struct rs_gl *gl, void *(*get)(void *ctx, const char *name), void *ctx,
                          struct rs_error *err);

#endif
