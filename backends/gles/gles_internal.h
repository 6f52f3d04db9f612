/* Private state of the GLES renderer, shared by its files (not installed). */
#ifndef RS_GLES_INTERNAL_H
#define RS_GLES_INTERNAL_H

#include <stdbool.h>

#include "gl_api.h"
#include "raystream/rs_gles.h"
#include "raystream/rs_scene.h"

/* Per-pixel state textures (ping-pong pairs). */
enum { ST_ORIG = 0, ST_DIR = 1, ST_ACC = 2, ST_COUNT = 3 };

/* Texture units: the scene's four packed textures first, then the per-pixel inputs. */
enum {
	UNIT_NODES = 0,
	UNIT_TRIS,
	UNIT_NORMALS,
	UNIT_MATERIALS,
	UNIT_ORIG,
	UNIT_DIR,
	UNIT_ACC,
	UNIT_HIT,
	UNIT_CNT,
	UNIT_SHADOW,
	UNIT_ENVMAP,
	UNIT_OBJECTS, /* RS_REFLECT_INTERREFLECT: scene triangle -> object (R32F) */
	UNIT_OBJMAP,  /* ... and RS_RENDER_MAX_MIRROR_OBJECTS cube maps from here on */
	UNIT_COUNT = UNIT_OBJMAP + RS_RENDER_MAX_MIRROR_OBJECTS
};

enum {
	PROG_RAYGEN = 0,
	PROG_INTERSECT,
	PROG_SHADE,
	PROG_FUSED,
	PROG_DISPLAY,
	PROG_RASTER,
	PROG_SHADOW,
	PROG_FUSED_FIRST, /* the fused pass that makes its own primary rays (no raygen pass) */
	PROG_ENVIRONMENT, /* RS_CHAIN_PAPER: environment, shading, next ray apart */
	PROG_SHADING,
	PROG_NEXTRAY,
	PROG_RESOLVE,      /* rasterized primaries: exact hits from the visibility pass */
	PROG_FUSED_RASTER, /* the fused chain's first pass over rasterized primaries */
	PROG_COUNT
};

struct gles {
	const struct rs_gl_context_ops *cops;
	void *ctx;
	struct rs_gl gl;
	char renderer[128];
	bool es;        /* a GLES context (else desktop GL running the ES kernels) */
	GLint max_tex;  /* GL_MAX_TEXTURE_SIZE */
	GLint max_view; /* smaller side of GL_MAX_VIEWPORT_DIMS */
	GLint max_draw; /* GL_MAX_DRAW_BUFFERS */
	/* Buffer textures: the kernels' version line (and extension) where the context has
	 * them, else NULL; GL_MAX_TEXTURE_BUFFER_SIZE. */
	const char *buffer_glsl;
	GLint max_tex_buffer;
	GLuint vao, fbo;

	/* set_scene */
	const struct rs_scene *scene;
	struct rs_render_desc desc;
	struct rs_render_accel accel;
	enum rs_scene_storage storage; /* resolved: 2D or BUFFER */
	GLenum scene_target;           /* GL_TEXTURE_2D or GL_TEXTURE_BUFFER */
	GLuint scene_tex[4];
	GLuint scene_buf[4]; /* BUFFER: the buffer objects behind scene_tex */
	GLuint state[2][ST_COUNT];
	GLuint cnt[2];
	GLuint hit[2];               /* [0]: pass 0 (depth), [1]: later passes */
	GLuint color;                /* RGBA8 display target */
	GLuint depth;                /* raster primary: depth renderbuffer */
	GLuint shadow, shadow_depth; /* shadow maps: R32F array (6 faces a light), depth */
	GLuint envmap;               /* RS_REFLECT_ENVMAP: RGB16F cube map (gles_envmap.c) */
	bool envmap_ready;           /* captured: later passes read it instead of tracing */
	/* RS_REFLECT_INTERREFLECT (gles_interreflect.c): the objects, their triangle -> object
	 * texture, two sets of cube maps (bounce k writes one set and reads the other), the set
	 * the next pass reads (-1: none yet), and the capture rays' start distance. */
	struct rs_scene_object objects[RS_RENDER_MAX_MIRROR_OBJECTS];
	uint32_t object_count;
	GLuint object_tex, objmap[2][RS_RENDER_MAX_MIRROR_OBJECTS];
	int objmap_read;
	float capture_near;
	double bounds_center[3], bounds_radius; /* raster primary: clip planes per camera */
	GLuint prog[PROG_COUNT];
	uint32_t light_count;
	float light_pos[16 * 3], light_color[16 * 3];
	float spawn_scale, ambient;
	float env_center[3], env_half, env_color[18], env_grid, env_line_width, env_line_scale;
	float *scratch; /* readback: width * height * 4 floats */
};

/* Largest number of lights a kernel is specialised for (uniform arrays). */
#define RS_GLES_MAX_LIGHTS 16u

/* Compile and link vertex kernel files `vfiles` (NULL: the fullscreen triangle) with
 * fragment kernel files `files` (common first), under `version` (the #version line and any
 * #extension lines) and `defines` (#define lines). A compile error names the file and line
 * with the driver's first log line and the source line. */
enum rs_status rs_gles_program(const struct rs_gl *gl, const char *version,
                               const char *const *vfiles, size_t vcount, const char *const *files,
                               size_t count, const char *defines, GLuint *out,
                               struct rs_error *err);

/* Tests only: compile `source` in place of kernel file `name` (NULL name: none). */
void rs__gles_override_kernel(const char *name, const char *source);

/* Check glGetError after `what`; RS_ERR_NO_MEMORY for GL_OUT_OF_MEMORY, else RS_ERR_DEVICE. */
enum rs_status rs_gles_check(const struct rs_gl *gl, const char *what, struct rs_error *err);

/* Read glGetError right after allocating `what` (internal `format`, w x h x layers texels;
 * format 0: an object without storage): RS_ERR_NO_MEMORY "gles: out of GPU memory for
 * <what> (<size> <format>, <KiB or MiB>)" for GL_OUT_OF_MEMORY, RS_ERR_DEVICE for another error
 * (gles_alloc.c). What was made before stays in the renderer for delete_scene(). */
enum rs_status rs_gles_allocated(const struct rs_gl *gl, const char *what, GLenum format, GLsizei w,
                                 GLsizei h, GLsizei layers, struct rs_error *err);

/* gles_storage.c: at creation, whether the context has buffer textures (g->buffer_glsl, the
 * kernels' version line for them, and g->max_tex_buffer; `version` is GL_VERSION); per scene,
 * the storage (g->storage, g->scene_target; RS_ERR_UNSUPPORTED or RS_ERR_LIMIT when BUFFER
 * cannot be had), and packed texture i as a buffer texture (g->scene_buf[i], scene_tex[i]). */
void rs_gles_probe_buffers(struct gles *g, const char *version);
enum rs_status rs_gles_choose_storage(struct gles *g, const struct rs_packed *p,
                                      enum rs_scene_storage want, struct rs_error *err);
enum rs_status rs_gles_buffer_texture(struct gles *g, int i, GLenum format,
                                      const struct rs_texture *t, const char *what,
                                      struct rs_error *err);

/* Add `ms` to the kernel timing `name` of `stats` (a new entry while there is room). */
void rs_gles_kernel_time(struct rs_render_stats *stats, const char *name, double ms);

/* Which texture of each ping-pong pair holds the current per-pixel state: g->state[st[s]][s]
 * and g->cnt[cnt] (a kernel that writes a texture writes the other one of its pair). */
struct rs_gles_cursor {
	int st[ST_COUNT];
	int cnt;
};

/* Attach `n` colour targets (a 0 drops that output), draw the fullscreen triangle with the
 * bound program, finish and add the time since `t0` to kernel `name` of `stats`
 * (gles_frame.c). */
enum rs_status rs_gles_draw(struct gles *g, const char *name, const GLuint *targets, int n,
                            struct rs_render_stats *stats, double t0, struct rs_error *err);
/* Bind the per-pixel state `c` points at as u_orig, u_dir, u_acc (and u_cnt). */
void rs_gles_state_inputs(const struct gles *g, GLuint prog, const struct rs_gles_cursor *c);

/* RS_CHAIN_PAPER: the environment, shading and next-ray passes of segment `pass` after its
 * hits are in `hit`; advances `c` (gles_paper.c). */
enum rs_status rs_gles_paper_segment(struct gles *g, uint32_t pass, GLuint hit,
                                     struct rs_gles_cursor *c, struct rs_render_stats *stats,
                                     struct rs_error *err);

/* One frame: passes, display, readback (gles_frame.c). */
enum rs_status rs_gles_frame(struct gles *g, const struct rs_camera *camera,
                             const struct rs_frame *frame, struct rs_render_stats *stats,
                             struct rs_error *err);

/* Render the cube shadow maps of every light (set_scene: lights and geometry are fixed). */
enum rs_status rs_gles_shadow_maps(struct gles *g, struct rs_error *err);

/* RS_REFLECT_ENVMAP: capture the cube map from the centre of `scene` (6 traced frames of
 * 1 pass, 90 degrees, the frame's square size). */
enum rs_status rs_gles_envmap(struct gles *g, const struct rs_scene *scene, struct rs_error *err);

/* RS_REFLECT_ENVMAP and _INTERREFLECT: the cube maps and whether pass `pass` reads them. */
void rs_gles_envmap_uniforms(const struct gles *g, GLuint prog, uint32_t pass);

/* Render the 6 faces of cube map `tex` from `eye` (traced frames of `passes` passes, 90
 * degrees, the frame's square size; primary rays start `near` from the eye). */
enum rs_status rs_gles_capture_cube(struct gles *g, const double eye[3], float near,
                                    uint32_t passes, GLuint tex, struct rs_error *err);

/* RS_REFLECT_INTERREFLECT, set_scene: group the mirrors, upload the triangle -> object
 * texture, make the cube maps (gles_interreflect.c). */
enum rs_status rs_gles_interreflect_setup(struct gles *g, const struct rs_scene *scene,
                                          struct rs_error *err);
/* RS_REFLECT_INTERREFLECT, every frame: capture the objects' maps, bounce by bounce. */
enum rs_status rs_gles_interreflect_capture(struct gles *g, struct rs_error *err);

/* Bind `tex` (target GL_TEXTURE_2D or GL_TEXTURE_2D_ARRAY) to `unit` as sampler `name`. */
void rs_gles_bind(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLenum target,
                  GLuint tex);
void rs_gles_bind_2d(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLuint tex);
/* Uniforms by name; a name the compiler dropped (unused in this specialisation) is skipped. */
void rs_gles_uniform_i(const struct rs_gl *gl, GLuint prog, const char *name, GLint v);
void rs_gles_uniform_f(const struct rs_gl *gl, GLuint prog, const char *name, GLfloat v);
void rs_gles_uniform_3fv(const struct rs_gl *gl, GLuint prog, const char *name, GLsizei n,
                         const GLfloat *v);
/* The packed textures and scene constants of the tracing kernels (gles_uniforms.c). */
void rs_gles_scene_uniforms(const struct gles *g, GLuint prog);
/* Camera basis, eye moved into the packed frame (R1), size, fov, lens shift. */
void rs_gles_camera_uniforms(const struct gles *g, GLuint prog, const struct rs_camera *c);

/* The whole chain once on a 1x1 viewport, results unused: drivers (llvmpipe) compile a
 * kernel at its first draw, which would otherwise land in the first frame's timings. */
enum rs_status rs_gles_warm_up(struct gles *g, const struct rs_camera *camera,
                               struct rs_error *err);

#endif
