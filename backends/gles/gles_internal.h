/* Private state of the GLES renderer, shared by its files (not installed). The files form a
 * one-way stack; a file calls only into its own layer or the ones below (docs/gles.md, "Call
 * stack"; tests/gles_layers.cmake checks it):
 *   1 renderer   gles_renderer.c                      the ops table: set_scene, render
 *   2 capture    gles_shadow.c gles_envmap.c gles_interreflect.c   shadow and cube maps
 *   3 plan       gles_plan.c (decide) gles_frame.c (run, display, read back)
 *                gles_display.c (a window context: the frame to its default framebuffer)
 *   4 programs   gles_program.c gles_prelude.c gles_uniforms.c gles_scene.c gles_storage.c
 *   5 leaf       gles_state.c gles_alloc.c gl_api.c
 */
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
	/* two levels: the instance texture (never with inter-reflection, rs_gles_two_level) */
	UNIT_INSTANCES = UNIT_OBJECTS,
	UNIT_OBJMAP, /* ... and RS_RENDER_MAX_MIRROR_OBJECTS cube maps from here on */
	UNIT_COUNT = UNIT_OBJMAP + RS_RENDER_MAX_MIRROR_OBJECTS
};

/* The program table (gles_program.c holds each one's kernel files and variant). */
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
	PROG_PRIMARY,      /* rs_render_desc.hits_only: camera ray and closest hit, nothing else */
	/* RS_KERNELS_COMPUTE: the three fused passes as compute dispatches (fused.glsl) */
	PROG_FUSED_COMPUTE,
	PROG_FUSED_FIRST_COMPUTE,
	PROG_FUSED_RASTER_COMPUTE,
	PROG_COUNT
};

/* Every uniform a kernel declares; locations are looked up once per program at link. */
enum {
	U_NODES,
	U_TRIS,
	U_NORMALS,
	U_MATERIALS,
	U_NODE_COUNT,
	U_GRID_ORIGIN,
	U_GRID_STEP,
	U_TRI_COUNT,
	U_MATERIAL_COUNT,
	U_SPAWN_SCALE,
	U_SPAWN_FLOOR,
	U_AMBIENT,
	U_LIGHT_POS,
	U_LIGHT_COLOR,
	U_ENV_CENTER,
	U_ENV_HALF,
	U_ENV_COLOR,
	U_ENV_GRID,
	U_ENV_LINE_WIDTH,
	U_ENV_LINE_SCALE,
	U_SHADOW,
	U_SHADOW_SIZE,
	U_SHADOW_FILTER,
	U_EYE,
	U_FWD,
	U_RIGHT,
	U_UP,
	U_SIZE,
	U_TAN,
	U_SHIFT,
	U_JITTER,
	U_NEAR,
	U_FAR,
	U_ORIG,
	U_DIR,
	U_ACC,
	U_CNT,
	U_HIT,
	U_VIS,
	U_ENVMAP,
	U_ENVMAP_ON,
	U_ENVMAP_AFTER,
	U_OBJECTS,
	U_OBJMAP_ON,
	U_OBJMAP0, /* ... RS_RENDER_MAX_MIRROR_OBJECTS of them */
	U_LIGHT = U_OBJMAP0 + RS_RENDER_MAX_MIRROR_OBJECTS,
	U_AXIS,
	U_SIGN,
	U_INSTANCES, /* RS_TWO_LEVEL */
	U_TOP_BASE,
	U_TOP_COUNT,
	U_INSTANCE_COUNT,
	U_PROTO_INSTANCES,
	U_DISPLAY, /* fused.glsl: target 0 takes the RGBA8 colour (rs_gles_step.display) */
	U_EXTENT,  /* fused.glsl as a compute kernel: the pixels of the pass */
	U_STORES,  /* ... and which of its four images it stores (bit k: image k) */
	U_COUNT
};

struct rs_gles_program {
	GLuint id; /* 0: not built for this scene */
	GLint loc[U_COUNT];
	bool compute; /* a compute program: dispatched, its targets bound as images */
};

/* A texture of the per-pixel state, as a plan names it: resolved at run time by
 * rs_gles_target() (0 is none). */
enum {
	REF_NONE = 0,
	REF_STATE = 1,                      /* + 3 k + s: g->state[k][s] */
	REF_HIT = REF_STATE + 2 * ST_COUNT, /* + k: g->hit[k] */
	REF_CNT = REF_HIT + 2,              /* + k: g->cnt[k] */
	REF_COLOR = REF_CNT + 2
};

/* What a step binds before its draw. */
enum {
	BIND_SCENE = 1,   /* packed textures and the frame's constants */
	BIND_CAMERA = 2,  /* the camera basis */
	BIND_NEAR = 4,    /* u_near: where primary rays start */
	BIND_STATE = 8,   /* u_orig, u_dir, u_acc (u_cnt with counters) from in[] */
	BIND_HIT = 16,    /* u_hit from in[4] */
	BIND_VIS = 32,    /* u_vis: the visibility pass's output */
	BIND_ENVMAP = 64, /* the captured cube maps (read from the second pass on, or after the
	                   * fused chain's only pass: rs_gles_step.mapped) */
};

/* One draw of a plan: program, inputs, outputs. */
struct rs_gles_step {
	const char *name; /* the kernel timing's name */
	uint8_t prog;
	bool raster;    /* the visibility pass (a triangle draw), else a fullscreen pass */
	uint8_t bind;   /* BIND_* */
	uint8_t in[5];  /* REF_* of u_orig, u_dir, u_acc, u_cnt, u_hit */
	uint8_t out[4]; /* REF_* of the colour targets (REF_NONE: not stored) */
	uint8_t n_out;
	/* The fused chain with cube maps: the rays this pass leaves read the maps at its end
	 * (the second pass, which would only read them, is not run). */
	bool mapped;
	/* The fused chain's last pass: in a displayed run (rs_gles_plan_run's `display`) it
	 * writes the RGBA8 colour itself, into the targets `shown` (target 0 the display
	 * target, the float colour not stored), and no display pass follows. */
	bool display;
	uint8_t shown[4];
	uint32_t pass;
};

/* What a plan is made for: a frame's passes, primaries, chain, counters and reflections. */
struct rs_gles_plan_desc {
	uint32_t passes;
	enum rs_primary_mode primary;
	enum rs_kernel_chain chain;
	bool counters;
	bool envmap;    /* RS_REFLECT_ENVMAP or _INTERREFLECT: later passes may read cube maps */
	bool hits_only; /* rs_render_desc.hits_only: the primary hits, nothing shaded */
	bool compute;   /* RS_KERNELS_COMPUTE: the fused passes as compute programs */
};

/* Which programs run in which order into which targets, decided once (gles_plan.c). */
#define RS_GLES_MAX_STEPS (1u + 5u * RS_TRACE_MAX_PASSES)
struct rs_gles_plan {
	struct rs_gles_step steps[RS_GLES_MAX_STEPS];
	uint32_t count; /* 0: no such plan for this scene */
	bool counters;
	/* REF_* holding the colour and counters at the end (not the colour after a displayed
	 * run: g->color holds its RGBA8 bytes only) */
	uint8_t result_acc, result_cnt;
};

/* The renderer's plans: the frame's, and the capture frames' (gles_envmap.c). */
enum {
	PLAN_FRAME = 0,
	PLAN_ENVMAP,   /* the classic cube map: 1 pass with the frame's primaries */
	PLAN_BOUNCE_1, /* inter-reflection, first bounce: 1 traced pass */
	PLAN_BOUNCE_N, /* later bounces: 2 traced passes */
	PLAN_COUNT
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
	/* Compute kernels (RS_KERNELS_COMPUTE): their version line where the context has
	 * GLES 3.1 compute shaders with 4 image units, else NULL. */
	const char *compute_glsl;
	GLuint vao, fbo;

	/* set_scene */
	const struct rs_scene *scene;
	struct rs_render_desc desc;
	struct rs_render_accel accel;
	/* Every number of the frame but the camera's, resolved once per set_scene by lib/trace
	 * (rs_trace_frame_init(), the reference's own): uniforms and prelude come from it. */
	struct rs_trace_frame frame;
	enum rs_scene_storage storage; /* resolved: 2D or BUFFER */
	GLenum scene_target;           /* GL_TEXTURE_2D or GL_TEXTURE_BUFFER */
	GLuint scene_tex[4];
	GLuint scene_buf[4]; /* BUFFER: the buffer objects behind scene_tex */
	GLuint instance_tex; /* two levels (accel.two_level): the instance texture, 2D or, with
	                      * BUFFER storage, a buffer texture over instance_buf (one
	                      * fetch is a third of a 2D one's time on llvmpipe, docs/gles.md) */
	GLuint instance_buf;
	GLuint state[2][ST_COUNT];
	GLuint cnt[2];
	GLuint hit[2];               /* [0]: pass 0 (depth), [1]: later passes */
	GLuint color;                /* RGBA8 display target */
	GLuint depth;                /* raster primary: depth renderbuffer */
	GLuint shadow, shadow_depth; /* shadow maps: R32F array (6 faces a light), depth */
	GLuint envmap;               /* RS_REFLECT_ENVMAP: RGBA16F cube map (gles_envmap.c) */
	/* Cube map captures: the face side (desc.envmap_size), and whether a face of an
	 * RGBA16F cube map is a complete colour attachment here (probed at set_scene: the
	 * faces are then copied on the GPU, else read back and uploaded). */
	uint32_t face_size;
	bool face_direct;
	bool envmap_ready; /* captured: later passes read it instead of tracing */
	/* RS_REFLECT_INTERREFLECT (gles_interreflect.c): the objects, their triangle -> object
	 * texture, two sets of cube maps (bounce k writes one set and reads the other), the set
	 * the next pass reads (-1: none yet). */
	struct rs_scene_object objects[RS_RENDER_MAX_MIRROR_OBJECTS];
	uint32_t object_count;
	GLuint object_tex, objmap[2][RS_RENDER_MAX_MIRROR_OBJECTS];
	int objmap_read;
	struct rs_gles_plan plans[PLAN_COUNT];
	struct rs_gles_program prog[PROG_COUNT];
	float *scratch; /* readback: width * height * 4 floats */
	/* the display step into a window's default framebuffer (gles_display.c), made at the
	 * first frame when the context has a display_target */
	struct rs_gles_display *display;
};

/* Largest number of lights a kernel is specialised for (uniform arrays). */
#define RS_GLES_MAX_LIGHTS 16u

/* ---- 3 plan ------------------------------------------------------------------------- */

/* gles_plan.c: the steps of a frame made for `d`: the one place that decides the chain
 * (fused only without counters and cube maps), the passes run (with cube maps at most 2)
 * and the ping-pong targets. */
void rs_gles_plan_make(const struct rs_gles_plan_desc *d, struct rs_gles_plan *out);
/* gles_plan.c: whether `plan`'s last step can write the RGBA8 colour itself (the fused
 * chain's last pass, rs_gles_step.display): then a run with `display` needs no display
 * pass. */
bool rs_gles_plan_displays(const struct rs_gles_plan *plan);

/* gles_plan.c: whether `scene` is walked in two levels under `desc` (rs_render_two_level()
 * and this backend's limits: traced primaries, shadow rays and reflections only);
 * RS_ERR_UNSUPPORTED naming why when instances=two-level cannot be done. `moving`: asked
 * by an instance update (auto then takes two levels); `max_texels`: the most texels one
 * scene texture of this GL may hold (auto flattens a still scene that fits). */
enum rs_status rs_gles_two_level(const struct rs_render_desc *desc, const struct rs_scene *scene,
                                 bool moving, uint64_t max_texels, bool *out_two_level,
                                 struct rs_error *err);

/* gles_frame.c. Run `plan` from `camera` over the viewport w x h (primary rays start `near`
 * from the eye), kernel times into stats. `display` (only where rs_gles_plan_displays()):
 * the last step writes the RGBA8 colour into g->color and leaves no float colour. */
enum rs_status rs_gles_plan_run(struct gles *g, const struct rs_gles_plan *plan,
                                const struct rs_camera *camera, float near, GLsizei w, GLsizei h,
                                bool display, struct rs_render_stats *stats, struct rs_error *err);
/* The display pass, a step apart from the plan: the plan's colour to RGBA8 in g->color
 * (after a run without `display`). */
enum rs_status rs_gles_display(struct gles *g, const struct rs_gles_plan *plan,
                               struct rs_render_stats *stats, struct rs_error *err);
/* Read the plan's results into `frame` (colour, RGBA8, depth, triangle ids) and, with
 * counters, the hit numbers into stats. */
enum rs_status rs_gles_readback(struct gles *g, const struct rs_gles_plan *plan,
                                const struct rs_frame *frame, struct rs_render_stats *stats,
                                struct rs_error *err);

/* Cube map faces (the captures, gles_envmap.c): rs_gles_face_probe() says whether face 0 of
 * RGBA16F cube map `cube` is a complete colour attachment of the renderer's framebuffer;
 * then
 * rs_gles_to_face() copies the plan's colour, n x n texels from the origin, into face `face`
 * on the GPU (columns reversed with `mirror`), and otherwise rs_gles_read_face() reads them
 * (RGBA floats) into g->scratch for an upload. The frame's framebuffer is bound after each. */
bool rs_gles_face_probe(struct gles *g, GLuint cube);
enum rs_status rs_gles_to_face(struct gles *g, const struct rs_gles_plan *plan, GLuint cube,
                               int face, GLsizei n, bool mirror, struct rs_error *err);
enum rs_status rs_gles_read_face(struct gles *g, const struct rs_gles_plan *plan, GLsizei n,
                                 struct rs_error *err);

/* ---- 4 programs and scene storage ---------------------------------------------------- */

/* gles_program.c: the programs every plan in g->plans uses (and the display and shadow
 * programs), compiled under `prelude` (three variants: every program, the fused first pass,
 * it over raster hits), uniform locations looked up once. */
enum rs_status rs_gles_programs_build(struct gles *g, const char *const prelude[3],
                                      struct rs_error *err);
void rs_gles_programs_delete(struct gles *g);

/* What a kernel program is specialised for (gles_prelude.c writes it as #defines). */
struct rs_gles_spec {
	uint32_t row_items;   /* items per texture row of the packed layout */
	int row_shift;        /* log2 of row_items, -1 if it is no power of two */
	uint32_t lights;      /* lights the kernels loop over */
	uint32_t node_orders; /* direction-ordered node copies */
	bool watertight, counters, optics, geometry, shadow_map, envmap, interreflect;
	bool unshadowed; /* lights counted visible: no feelers (rs_trace_frame.unshadowed) */
	bool compact_nodes, wide_nodes, scene_buffers;
	bool two_level;                /* an instanced scene walked in two levels */
	uint32_t instance_row_items;   /* two levels: instances per row of the instance texture */
	bool first_pass, raster_first; /* the fused chain's first pass (over raster hits) */
};

/* The #define lines of `spec` and the rules' constants into out (cap bytes, NUL included);
 * RS_ERR_LIMIT when they do not fit. */
enum rs_status rs_gles_prelude(const struct rs_gles_spec *spec, const struct rs_trace_rules *rules,
                               char *out, size_t cap, struct rs_error *err);

/* A program outside the table (the window's display step, gles_display.c): the fullscreen
 * triangle and fragment `files`, no #define prelude. */
enum rs_status rs_gles_program_compile(const struct rs_gl *gl, const char *version,
                                       const char *const *files, size_t count, GLuint *out,
                                       struct rs_error *err);

/* gles_uniforms.c: inputs of a program, through its cached locations. */
void rs_gles_bind(const struct rs_gl *gl, const struct rs_gles_program *p, int unit, int u,
                  GLenum target, GLuint tex);
void rs_gles_uniform_i(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLint v);
void rs_gles_uniform_f(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLfloat v);
void rs_gles_uniform_3fv(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLsizei n,
                         const GLfloat *v);
/* The packed textures and the frame description's constants (rs_trace_frame), in fp32. */
void rs_gles_scene_uniforms(const struct gles *g, const struct rs_gles_program *p);
/* Camera basis for a w x h image (rs_trace_view: eye in the packed frame, R1), size, fov,
 * lens shift. */
void rs_gles_camera_uniforms(const struct gles *g, const struct rs_gles_program *p,
                             const struct rs_camera *c, uint32_t w, uint32_t h);
/* The cube maps, whether pass `pass` reads them for its own rays (RS_REFLECT_ENVMAP,
 * _INTERREFLECT), and whether for the rays it leaves (`after`, rs_gles_step.mapped). */
void rs_gles_envmap_uniforms(const struct gles *g, const struct rs_gles_program *p, uint32_t pass,
                             bool after);
/* Light i of the frame in the packed frame (R1), rounded to fp32. */
void rs_gles_light_position(const struct gles *g, uint32_t i, GLfloat out[3]);

/* gles_scene.c: the packed textures, the per-pixel targets the plans use and the display
 * target (each allocation checked, rs_gles_allocated); rs_gles_scene_delete() frees
 * everything set_scene made. */
enum rs_status rs_gles_scene_upload(struct gles *g, struct rs_error *err);
void rs_gles_scene_delete(struct gles *g);
/* The scene textures from g->accel.packed (what they hold now) to `next` (the same layout:
 * sizes and formats): only runs of texel rows that differ are sent (glTexSubImage2D, or
 * glBufferSubData for buffer storage); *out_bytes counts what was. */
enum rs_status rs_gles_scene_update(struct gles *g, const struct rs_packed *next,
                                    uint64_t *out_bytes, struct rs_error *err);
/* Two levels, after rs_render_accel_update_instances(): send the TLAS's rows of the node
 * and triangle textures and the instance texture, nothing of the BLASes; bytes sent. */
enum rs_status rs_gles_scene_update_top(struct gles *g, uint64_t *out_bytes, struct rs_error *err);
/* The texture a plan's REF_* names. */
GLuint rs_gles_target(const struct gles *g, uint8_t ref);

/* gles_storage.c: at creation, whether the context has buffer textures (g->buffer_glsl, the
 * kernels' version line for them, and g->max_tex_buffer; `version` is GL_VERSION); per scene,
 * the storage (g->storage, g->scene_target; RS_ERR_UNSUPPORTED or RS_ERR_LIMIT when BUFFER
 * cannot be had; `instances`, a two-level scene's instance texture or NULL, must fit too),
 * and a packed texture as a buffer texture (*buf, *tex: g->scene_buf[i] and scene_tex[i],
 * or g->instance_buf and instance_tex). */
void rs_gles_probe_buffers(struct gles *g, const char *version);
enum rs_status rs_gles_choose_storage(struct gles *g, const struct rs_packed *p,
                                      const struct rs_texture *instances,
                                      enum rs_scene_storage want, struct rs_error *err);
enum rs_status rs_gles_buffer_texture(struct gles *g, GLuint *buf, GLuint *tex, GLenum format,
                                      const struct rs_texture *t, const char *what,
                                      struct rs_error *err);

/* ---- 5 leaf: GL state, allocation, the GL table -------------------------------------- */

/* gles_state.c. The renderer's draw state for a w x h viewport (its framebuffer and vertex
 * array bound, the fixed-function state that would change results off). */
void rs_gles_frame_state(const struct gles *g, GLsizei w, GLsizei h);
/* Attach `n` colour targets (a 0 drops that output), draw the fullscreen triangle with the
 * bound program, finish and add the time since `t0` to kernel `name` of `stats`. */
enum rs_status rs_gles_draw(const struct gles *g, const char *name, const GLuint *targets, int n,
                            struct rs_render_stats *stats, double t0, struct rs_error *err);
/* The same with the bound compute program over a w x h grid: target k bound to image unit k
 * as RGBA32F (a 0 is not stored: u_stores), then a barrier for every later read of them. */
enum rs_status rs_gles_dispatch(const struct gles *g, const struct rs_gles_program *p,
                                const char *name, const GLuint *targets, int n, GLsizei w,
                                GLsizei h, struct rs_render_stats *stats, double t0,
                                struct rs_error *err);
/* Add `ms` to the kernel timing `name` of `stats` (a new entry while there is room). */
void rs_gles_kernel_time(struct rs_render_stats *stats, const char *name, double ms);

/* gles_alloc.c. Check glGetError after `what`; RS_ERR_NO_MEMORY for GL_OUT_OF_MEMORY, else
 * RS_ERR_DEVICE. */
enum rs_status rs_gles_check(const struct rs_gl *gl, const char *what, struct rs_error *err);
/* Read glGetError right after allocating `what` (internal `format`, w x h x layers texels;
 * format 0: an object without storage): RS_ERR_NO_MEMORY "gles: out of GPU memory for
 * <what> (<size> <format>, <KiB or MiB>)" for GL_OUT_OF_MEMORY, RS_ERR_DEVICE for another error.
 * What was made before stays in the renderer for rs_gles_scene_delete(). */
enum rs_status rs_gles_allocated(const struct rs_gl *gl, const char *what, GLenum format, GLsizei w,
                                 GLsizei h, GLsizei layers, struct rs_error *err);

/* ---- 2 capture ------------------------------------------------------------------------ */

/* gles_display.c (layer 3): show float colour texture `tex` (width x height texels, row 0 =
 * top) in the context's window (cops->display_target) and swap, through the still-pose
 * refinement mean of the camera's `sample` (0 restarts it); its time is kernel "present".
 * rs_gles_display_free releases the step (context current). */
enum rs_status rs_gles_present(struct gles *g, GLuint tex, uint32_t width, uint32_t height,
                               uint32_t sample, struct rs_render_stats *stats,
                               struct rs_error *err);
void rs_gles_display_free(struct gles *g);

/* gles_shadow.c: the cube shadow maps of every light (set_scene: lights and geometry are
 * fixed). */
enum rs_status rs_gles_shadow_maps(struct gles *g, struct rs_error *err);

/* gles_envmap.c. RS_REFLECT_ENVMAP (and _INTERREFLECT, for rays leaving no mirror): the
 * classic cube map captured from the centre of the scene's bounds (PLAN_ENVMAP). */
enum rs_status rs_gles_envmap(struct gles *g, struct rs_error *err);
/* Make `tex` an RGBA16F cube map of g->face_size texels a side (`what` names it in an
 * out-of-memory error). */
enum rs_status rs_gles_cube_alloc(struct gles *g, GLuint tex, const char *what,
                                  struct rs_error *err);
/* Render the 6 faces of cube map `tex` (rs_gles_cube_alloc) from `eye` with `plan` (90
 * degrees, g->face_size texels a side; primary rays start `near` from the eye). */
enum rs_status rs_gles_capture_cube(struct gles *g, const struct rs_gles_plan *plan,
                                    const double eye[3], float near, GLuint tex,
                                    struct rs_error *err);

/* gles_interreflect.c. RS_REFLECT_INTERREFLECT, set_scene: group the mirrors, upload the
 * triangle -> object texture, make the cube maps; every frame: capture the objects' maps,
 * bounce by bounce (PLAN_BOUNCE_1, PLAN_BOUNCE_N). */
enum rs_status rs_gles_interreflect_setup(struct gles *g, struct rs_error *err);
enum rs_status rs_gles_interreflect_capture(struct gles *g, struct rs_error *err);

#endif
