/**
 * @file rs_render.h
 * One render interface for every backend: a descriptor, one stats struct, and an opaque
 * renderer object behind a small table of operations. The CPU double-precision reference
 * (rs_trace.h, threaded) is one backend, built into this module; the GLES backends (EGL,
 * OSMesa) plug in through the same table from backends/ and are opened by name with
 * rs_renderer_open() (rs_renderers.h, module rs_renderers).
 *
 * Life cycle: create -> set_scene (builds the BVH, packs and uploads once) -> render any
 * number of frames, each with an optional camera (the tracked viewer changes only the
 * camera every frame; nothing else is uploaded) -> destroy. Between frames,
 * rs_renderer_update_vertices() moves the scene's vertices (same topology): the BVH is
 * refitted (or rebuilt past rs_render_desc.rebuild_ratio) and only what changed is uploaded;
 * rs_renderer_update_instances() moves its instances (new transforms only).
 *
 * Threading: a renderer is used by one thread at a time. GL backends make their context
 * current in set_scene and render and release it before returning.
 */
#ifndef RS_RENDER_H
#define RS_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"
#include "raystream/rs_trace.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where primary hits come from. */
enum rs_primary_mode {
	RS_PRIMARY_TRACE = 0,  /**< primary rays traced through the BVH (default) */
	RS_PRIMARY_RASTER = 1, /**< a raster pass writes triangle id, barycentrics, depth */
};

/** How lights are tested for occlusion. */
enum rs_shadow_mode {
	RS_SHADOW_RAYS = 0, /**< exact shadow feelers through the BVH (default) */
	RS_SHADOW_MAP = 1,  /**< cube shadow maps, box-filtered (GL backends only) */
	/** Unshadowed: every light in front of a surface counts as visible; no feelers, no
	 * maps (every backend). For scenes whose look needs no shadows: the paper's classic
	 * environment mapping (its Table 3) had none. rs_render_trace_desc() hands it to the
	 * frame (rs_trace_desc.unshadowed), which every backend shades from. */
	RS_SHADOW_NONE = 2,
};

/** How the GL backends chain their kernels. */
enum rs_kernel_chain {
	/** One trace pass per ray segment (intersection, environment, shading and next ray);
	 * with counters or environment maps the separate chain (render targets). */
	RS_CHAIN_FUSED = 0,
	/** Two passes per segment: intersection, then environment, shading and next ray. */
	RS_CHAIN_SEPARATE = 1,
	/** The paper's chain: ray generation, then intersection, environment, shading and next
	 * ray, each its own pass, per segment (kernel times named apart in the stats). */
	RS_CHAIN_PAPER = 2,
};

/** How the GL backends run the fused chain's trace passes. */
enum rs_kernel_stage {
	/** Full-screen fragment passes into render targets: GLES 3.0, the paper's way, and
	 * what handheld GPUs run best (default). */
	RS_KERNELS_FRAGMENT = 0,
	/** GLES 3.1 compute dispatches writing the same targets as images: the same kernels
	 * and images bit for bit. For GPUs whose fragment stage gets only part of the chip
	 * (NVIDIA's Hopper data-centre GPUs shade fragments on 2 of their 66 TPCs:
	 * docs/gles.md "Compute kernels"). The fused chain only (chain fused; a counting frame,
	 * which runs the separate chain, and a hits_only frame's one kernel stay fragment
	 * passes), and its last pass does not write the RGBA8 colour itself (the display pass
	 * does). Refused at set_scene for the other chains and where the context has no
	 * compute shaders. */
	RS_KERNELS_COMPUTE = 1,
};

/** How a scene with instances (rs_scene_add_instance) is traced. */
enum rs_instances_mode {
	/** Two levels where the scene has instances and the renderer can walk them, else
	 * flattened (rs_render_two_level() decides, and the GL plan for its own limits: on GL
	 * a still scene is flattened where it fits the texture limit, its walk being the
	 * faster there, and the first update_instances sets it again in two levels). */
	RS_INSTANCES_AUTO = 0,
	/** The instances' baked world-space triangles in one BVH, as a scene without any. */
	RS_INSTANCES_FLATTEN = 1,
	/** A BLAS per prototype and a TLAS over the instances, merged into the same textures
	 * (rs_pack_two_level(), docs/bvh.md); refused where it cannot be walked. */
	RS_INSTANCES_TWO_LEVEL = 2,
};

/** Where reflected and refracted rays (passes after the first) find their colour. */
enum rs_reflection_mode {
	RS_REFLECT_TRACE = 0, /**< traced through the BVH (default) */
	/** Classic environment mapping (GL backends only): one cube map captured once at
	 * set_scene from the scene's centre (the traced image of 1 pass, 90-degree faces of
	 * rs_render_desc.envmap_size texels); later rays read it by direction and stop.
	 * No inter- or self-reflection, parallax error away from the centre. */
	RS_REFLECT_ENVMAP = 1,
	/** Inter-reflection environment mapping (GL backends only): a cube map per reflective
	 * object (rs_scene_reflective_objects, at most RS_RENDER_MAX_MIRROR_OBJECTS), captured
	 * from its bounding-sphere centre every frame with capture rays starting on that sphere
	 * (the object does not see itself), rs_render_desc.reflection_bounces times: bounce k
	 * sees the scene and the maps of bounce k-1. Rays leaving an object read its own map by
	 * direction; rays leaving other surfaces read the classic map. */
	RS_REFLECT_INTERREFLECT = 2,
};

/** How the GL backends hold the packed scene (nodes, triangles, normals, materials). The
 * data and the layout are the same either way (rs_pack.h: dense rows), and so are the
 * images, bit for bit; only the fetch differs. */
enum rs_scene_storage {
	/** Buffer textures where the context has them (GLES 3.2, GLES 3.1 with
	 * OES/EXT_texture_buffer, desktop GL with ARB_ES3_2_compatibility) and the scene fits
	 * GL_MAX_TEXTURE_BUFFER_SIZE, else 2D textures. */
	RS_SCENE_STORAGE_AUTO = 0,
	/** 2D textures, rows of rs_packed.row_items: GLES 3.0, the paper's layout. */
	RS_SCENE_STORAGE_2D = 1,
	/** Buffer textures, one texel index per texel (texelFetch without levels or rows:
	 * cheaper on llvmpipe, docs/gles.md); refused where the context has none. */
	RS_SCENE_STORAGE_BUFFER = 2,
};

/** Most reflective objects RS_REFLECT_INTERREFLECT maps (GLES 3.0 has 16 texture units). */
#define RS_RENDER_MAX_MIRROR_OBJECTS 4u
/** Default and largest rs_render_desc.envmap_size (face side in texels). */
#define RS_RENDER_ENVMAP_SIZE 128u
#define RS_RENDER_MAX_ENVMAP_SIZE 16384u
/** Largest rs_render_desc.reflection_bounces. */
#define RS_RENDER_MAX_BOUNCES 8u

/** Largest rs_render_desc.threads. */
#define RS_RENDER_MAX_THREADS 256u

/** Renderer options; zero-initialised means defaults (resolved by rs_render_desc_resolve). */
struct rs_render_desc {
	uint32_t width, height; /**< image size; 0: the scene camera's (at set_scene) */
	uint32_t passes;        /**< ray segments per path; 0 -> 2 */
	/** The scene's first N lights; 0 -> all of them. The command-line tools and apps
	 * default to all as well (--lights N restricts), so a zero descriptor and a tool run
	 * without options render the same image. */
	uint32_t lights;
	enum rs_triangle_test triangle_test;
	double ray_epsilon; /**< as rs_trace_desc.ray_epsilon; 0 -> the tracer's default */
	enum rs_primary_mode primary;
	enum rs_shadow_mode shadows;
	uint32_t shadow_map_size; /**< cube face side in texels; 0 -> 512 */
	uint32_t shadow_filter;   /**< box filter side in texels (1 = none); 0 -> 3 */
	bool counters;            /**< count box and triangle tests (costs time on GPUs) */
	struct rs_bvh_desc bvh;   /**< the BVH builder and its options */
	/** Texture layout. pack.max_texture_size 0: the device's limit, GL_MAX_TEXTURE_SIZE on
	 * the GL backends and RS_PACK_DEFAULT_MAX_TEXTURE_SIZE (2048, GLES 3.0's minimum) on
	 * the CPU; GL backends refuse a value above their device's. A scene that does not fit
	 * is refused at set_scene with RS_ERR_LIMIT naming the limit. */
	struct rs_pack_desc pack;
	/** CPU backend threads, and every backend's BVH build threads (rs_render_bvh_desc());
	 * 0 -> the machine's cores. */
	uint32_t threads;
	enum rs_kernel_chain chain;
	/** GL backends: fragment passes or compute dispatches (rs_kernel_stage); the CPU
	 * backend ignores it. */
	enum rs_kernel_stage kernels;
	enum rs_reflection_mode reflections;
	/** RS_REFLECT_INTERREFLECT: cube-map captures per frame, 1..8; 0 -> 1. */
	uint32_t reflection_bounces;
	/** GL backends: EGL platform to use ("device", "gbm", "surfaceless"); NULL: the
	 * RS_EGL_PLATFORM environment variable, else the first that works in that order
	 * (rs_egl.h).
	 * Read only while the renderer is created. */
	const char *egl_platform;
	/** GL backends: where the packed scene lives; the CPU backend ignores it. */
	enum rs_scene_storage scene_storage;
	/** rs_renderer_update_vertices(): rebuild the BVH instead of refitting it once the
	 * refitted tree's SAH cost exceeds this many times the cost at its last build; 0 ->
	 * RS_BVH_REBUILD_RATIO; +INFINITY: always refit. NaN or negative is refused. */
	double rebuild_ratio;
	/** The backend rs_renderer_open() opens when it is given no name: "auto", "cpu",
	 * "egl", "osmesa" (rs_renderers.h); NULL -> "auto". The backends themselves ignore it;
	 * rs_render_desc_set() points it at a static string. */
	const char *backend;
	/** RS_REFLECT_ENVMAP and _INTERREFLECT: the cube maps' face side in texels, rendered by
	 * the kernels straight into the cube faces (docs/gles.md); 0 -> RS_RENDER_ENVMAP_SIZE,
	 * at most RS_RENDER_MAX_ENVMAP_SIZE (and the GL context's viewport and texture
	 * limits, checked at set_scene). */
	uint32_t envmap_size;
	/** Instanced scenes: two levels or flattened; 0 -> RS_INSTANCES_AUTO. */
	enum rs_instances_mode instances;
	/** The primary hits only (picking, and timing the closest-hit walk on its own): a frame
	 * gives rs_frame.depth and .triangle, and asking it for rgb or rgba8 is refused (nothing
	 * is shaded). rs_renderer_open() then sets passes to 1, shadows to RS_SHADOW_RAYS and
	 * reflections to RS_REFLECT_TRACE (nothing to capture); counters are refused. GL
	 * backends: one kernel per frame, the camera ray made in it (docs/gles.md); the CPU
	 * backend traces its usual frame and returns its hits. */
	bool hits_only;
};

/** Kernel timing, GL backends (summed over the passes of one frame). */
struct rs_render_kernel_time {
	char name[24];
	uint32_t calls;
	double ms;
};

/** Largest number of kernel timings a stats struct carries. */
#define RS_RENDER_MAX_KERNELS 16u

/** What a frame cost and counted; the same struct for every backend. */
struct rs_render_stats {
	char backend[16];   /**< "cpu", "egl", "osmesa" */
	char renderer[128]; /**< GL_RENDERER (or the CPU's description) */
	uint32_t width, height;
	uint64_t pixels;
	uint64_t primary_rays;   /**< one per pixel (rasterized ones included) */
	uint64_t secondary_rays; /**< reflected and refracted segments */
	uint64_t shadow_rays;    /**< shadow feelers (0 with shadow maps or none) */
	bool counters_valid;     /**< box/triangle counts below were measured */
	uint64_t box_tests;
	uint64_t triangle_tests;
	double box_per_pixel; /**< the paper's hit numbers: means per pixel */
	double triangle_per_pixel;
	double total_per_pixel;
	double build_ms;    /**< BVH build (set_scene) */
	double pack_ms;     /**< packing into textures (set_scene) */
	double upload_ms;   /**< texture upload and shader compile (set_scene) */
	double render_ms;   /**< the last frame, up to the image being ready on the device */
	double readback_ms; /**< copying the last frame to host memory */
	uint32_t kernel_count;
	struct rs_render_kernel_time kernels[RS_RENDER_MAX_KERNELS];
	/** GL backends: the storage set_scene chose (never AUTO); CPU: AUTO. */
	enum rs_scene_storage scene_storage;
	/** Vertex updates (rs_renderer_update_vertices) since set_scene, and how many of them
	 * rebuilt the BVH rather than refitting it. */
	uint32_t updates, update_rebuilds;
	bool update_rebuilt;     /**< the last update rebuilt (false: refitted) */
	double update_sah_ratio; /**< the last refit's SAH cost over the cost at the last build */
	double refit_ms;         /**< the last update's refit (a rebuild is in build_ms) */
	/** Bytes of scene textures the last set_scene or update uploaded (CPU: 0); pack_ms and
	 * upload_ms are the last update's too. */
	uint64_t upload_bytes;
	/** Instance updates (rs_renderer_update_instances) since set_scene; each is counted in
	 * `updates` too. */
	uint32_t instance_updates;
	/** The last instance update went through the backend's update_vertices (it has no
	 * update_instances op): the baked triangles refitted or rebuilt, as `update_rebuilt`
	 * says; false when the backend rebuilt only its top-level tree. */
	bool instance_update_baked;
	/** The last instance update's top-level (TLAS) build; its packing is in pack_ms (0 when
	 * instance_update_baked). */
	double tlas_build_ms;
};

/** Where a frame goes; caller-owned buffers of the renderer's width * height pixels. */
struct rs_frame {
	float *rgb;     /**< 3 linear floats per pixel, row 0 = top, or NULL */
	uint8_t *rgba8; /**< 4 bytes per pixel as rs_image_quantize() rounds, alpha 255, or NULL */
	float *depth;   /**< primary-hit distance, +INFINITY on a miss, or NULL */
	/** Scene triangle id of the primary hit (traced or rasterized), RS_NO_SLOT on a miss,
	 * or NULL: for picking, and for comparing primary modes. */
	uint32_t *triangle;
};

struct rs_renderer;

/**
 * A backend's operations. `impl` is the backend's own state. Every call fills `err` on
 * failure. Ops other than destroy are never called with a NULL impl.
 */
struct rs_renderer_ops {
	const char *name;
	/** Upload a scene (after any earlier one). `scene` stays valid until the next
	 * set_scene or destroy; the BVH and packed textures are owned by the renderer. */
	enum rs_status (*set_scene)(void *impl, const struct rs_scene *scene,
	                            const struct rs_render_desc *desc,
	                            struct rs_render_stats *stats, struct rs_error *err);
	/** Render one frame from `camera` (already resolved, never NULL). */
	enum rs_status (*render)(void *impl, const struct rs_camera *camera,
	                         const struct rs_frame *frame, struct rs_render_stats *stats,
	                         struct rs_error *err);
	/** Release everything, `impl` included. */
	void (*destroy)(void *impl);
	/** Optional: describe the device (GL_RENDERER) into `out` for stats.renderer. */
	void (*describe)(const void *impl, char *out, size_t cap);
	/** Optional (NULL: RS_ERR_UNSUPPORTED): move to `scene`, whose topology the caller
	 * checked against the current one (rs_render_scene_same_topology()); refit or rebuild,
	 * repack and upload what changed; fill the update fields of `stats`. On failure the
	 * backend keeps no scene (the renderer then refuses to render), except for
	 * RS_ERR_UNSUPPORTED, which it returns before changing anything. */
	enum rs_status (*update_vertices)(void *impl, const struct rs_scene *scene,
	                                  struct rs_render_stats *stats, struct rs_error *err);
	/** Optional (NULL: the renderer calls update_vertices instead, as the baked triangles
	 * moved): move to `scene`, which the caller checked has the current scene's topology,
	 * prototypes and instances (only instance transforms differ; it may be the same object,
	 * changed by rs_scene_set_instance_transform()); rebuild the top-level tree
	 * (rs_pack_instances_update()) and upload it and the transforms; fill tlas_build_ms,
	 * pack_ms, upload_ms and upload_bytes. Failure rules as update_vertices. */
	enum rs_status (*update_instances)(void *impl, const struct rs_scene *scene,
	                                   struct rs_render_stats *stats, struct rs_error *err);
};

/**
 * Wrap a backend: on success the renderer owns `impl` (ops->destroy runs in
 * rs_renderer_destroy()); on failure ops->destroy(impl) has already run. `ops` must outlive
 * the renderer (a static const table). `desc` is copied and resolved; NULL means defaults.
 */
enum rs_status rs_renderer_create(const struct rs_renderer_ops *ops, void *impl,
                                  const struct rs_render_desc *desc, struct rs_renderer **out,
                                  struct rs_error *err);

/** The CPU reference backend (rs_trace_render over threads). Trace-only: RS_PRIMARY_RASTER,
 * RS_SHADOW_MAP and RS_REFLECT_ENVMAP are refused with RS_ERR_UNSUPPORTED. */
enum rs_status rs_renderer_create_cpu(const struct rs_render_desc *desc, struct rs_renderer **out,
                                      struct rs_error *err);

/** The CPU backend with `intersector`'s ray queries in place of its BVH walk (NULL: as
 * rs_renderer_create_cpu()): the reference's rays, paths, shading and threads over a peer's
 * intersection code. The intersector must outlive the renderer; its prepare() runs at each
 * set_scene. Box and triangle counts stay 0 (counters_valid false) under an intersector. */
enum rs_status rs_renderer_create_cpu_with(const struct rs_render_desc *desc,
                                           const struct rs_trace_intersector *intersector,
                                           struct rs_renderer **out, struct rs_error *err);

/** Destroy and set *renderer to NULL; NULL and *renderer == NULL are allowed. */
void rs_renderer_destroy(struct rs_renderer **renderer);

/**
 * Build the BVH, pack and upload `scene`, which must stay alive and unchanged until the
 * next set_scene or destroy. The image size is fixed here when the descriptor leaves it 0.
 */
enum rs_status rs_renderer_set_scene(struct rs_renderer *renderer, const struct rs_scene *scene,
                                     struct rs_error *err);

/**
 * Move the current scene's vertices for the next frame: `scene` replaces the scene of the
 * last set_scene (or update) and must stay alive and unchanged as that one; it must have
 * the same topology (vertex and triangle counts, indices, per-triangle materials and the
 * materials); positions and normals may differ, and so may lights, ambient and environment
 * (every backend reads them from the new scene, as set_scene would).
 * The BVH is refitted, or rebuilt when the refitted tree's SAH cost passes
 * rs_render_desc.rebuild_ratio times its cost at the last build; the scene is repacked
 * and GL backends upload only the texel rows that changed. The images are those a
 * set_scene of `scene` gives (same hits; the tree decides only the order of box tests).
 * RS_ERR_INVALID before set_scene or for a topology change (one line naming what
 * changed; the current scene stays); RS_ERR_UNSUPPORTED where the backend cannot update
 * (GL shadow or environment maps, captured at set_scene). Stats: updates,
 * update_rebuilds, update_rebuilt, update_sah_ratio, refit_ms, build_ms, pack_ms,
 * upload_ms, upload_bytes.
 */
enum rs_status rs_renderer_update_vertices(struct rs_renderer *renderer,
                                           const struct rs_scene *scene, struct rs_error *err);

/**
 * Move the current scene's instances for the next frame: `scene` has the current scene's
 * topology (as update_vertices), prototypes and instances (the same count, each with the
 * same prototype, material and triangles) and its plain triangles (rs_scene_add_mesh: their
 * vertices and normals, compared by a hash kept at set_scene); only instance transforms
 * differ, so `scene` may be the current scene itself after rs_scene_set_instance_transform()
 * calls, or another scene built the same way (a frame of "cowNi"). It replaces the current scene as
 * update_vertices' does. A backend with an update_instances op rebuilds and uploads only its
 * top-level tree and the transforms; the others (every backend today) take the update_vertices
 * path, as the baked triangles moved, so every backend shows the image a set_scene of `scene`
 * shows. RS_ERR_INVALID before set_scene, for a scene with no instances, and for any other
 * change (one line naming it; the current scene stays); RS_ERR_UNSUPPORTED as
 * update_vertices. Stats: instance_updates, instance_update_baked, tlas_build_ms, and the
 * fields update_vertices fills.
 */
enum rs_status rs_renderer_update_instances(struct rs_renderer *renderer,
                                            const struct rs_scene *scene, struct rs_error *err);

/** RS_OK when `next` has the topology of `current` (update_vertices' condition), else
 * RS_ERR_INVALID with one line naming the first difference. */
enum rs_status rs_render_scene_same_topology(const struct rs_scene *current,
                                             const struct rs_scene *next, struct rs_error *err);

/**
 * Render a frame. `camera` NULL: the scene's camera; else its eye, target, up, fov, shift
 * and sub-pixel sample are used (its width/height are ignored: the size was fixed at
 * set_scene). RS_ERR_INVALID
 * before set_scene or for a camera rs_scene_set_camera() would refuse.
 */
enum rs_status rs_renderer_render(struct rs_renderer *renderer, const struct rs_camera *camera,
                                  const struct rs_frame *frame, struct rs_error *err);

/** The resolved descriptor (defaults filled in, size known after set_scene). */
const struct rs_render_desc *rs_renderer_desc(const struct rs_renderer *renderer);

/** Stats of the last set_scene and frame; owned by the renderer. */
const struct rs_render_stats *rs_renderer_stats(const struct rs_renderer *renderer);

/** Last error message of this renderer (empty if none); owned by the renderer. */
const char *rs_renderer_last_error(const struct rs_renderer *renderer);

/** Backend name ("cpu", "egl", "osmesa"). */
const char *rs_renderer_backend(const struct rs_renderer *renderer);

/** Fill the zero fields of `desc` with defaults (size stays 0 until a scene is known;
 * pack.max_texture_size stays 0, the backend's own limit). RS_ERR_INVALID for out-of-range
 * values (unknown enums, passes > RS_TRACE_MAX_PASSES, negative or non-finite epsilon,
 * filter larger than the map, more threads than RS_RENDER_MAX_THREADS, a texture limit
 * under 3 texels or a row wider than it). */
enum rs_status rs_render_desc_resolve(const struct rs_render_desc *desc, struct rs_render_desc *out,
                                      struct rs_error *err);

/** One render option as the command line and config strings spell it. */
struct rs_render_option {
	const char *key;      /**< "passes"; on a command line "--passes" */
	const char *values;   /**< the valid values, e.g. "1..64" or "trace|raster" */
	const char *fallback; /**< what a zero descriptor means, e.g. "2" */
	const char *help;     /**< one line */
};

/** Every render option (static table, `*out_count` entries), in --help order: backend, size,
 * passes, lights, shadows, primary, reflections, envmap-size, bvh, nodes, scene-storage,
 * threads, triangle-test, chain, kernels, instances. */
const struct rs_render_option *rs_render_options(size_t *out_count);

/** The option named `key`, or NULL. */
const struct rs_render_option *rs_render_option_find(const char *key);

/**
 * Set one option of `desc` from text, as a command line spells it: key "passes", value "2"
 * (keys and values as rs_render_options() lists them). RS_ERR_INVALID with a message naming
 * the key, the value and the valid values ("passes: '0' is not 1..64") for an unknown key
 * or a bad value; `desc` is unchanged then. Ranges that depend on the scene or device (more
 * lights than the scene has, a backend this build lacks) are checked when used.
 */
enum rs_status rs_render_desc_set(struct rs_render_desc *desc, const char *key, const char *value,
                                  struct rs_error *err);

/** rs_render_desc_set() for each item of a comma-separated "key=value" list
 * ("passes=2,lights=4,shadows=map:1024"); all or nothing: `desc` is unchanged on failure. */
enum rs_status rs_render_desc_parse(struct rs_render_desc *desc, const char *config,
                                    struct rs_error *err);

/** Spell one option of `desc` as rs_render_desc_set() takes it (a zero field as its default:
 * "all", "camera", "cores") into `out` (cap bytes). RS_ERR_INVALID for an unknown key,
 * RS_ERR_LIMIT when it does not fit. */
enum rs_status rs_render_desc_get(const struct rs_render_desc *desc, const char *key, char *out,
                                  size_t cap, struct rs_error *err);

/** A scene's BVH and its packed textures, owned together: what every backend uploads. */
struct rs_render_accel {
	/** Two levels (rs_render_accel_build_two_level()): the merged packing, whose `all` is
	 * also `packed` (shared, freed once); instance_count 0 for a one-level build. */
	struct rs_packed_two_level two_level;
	/** Two levels: the per-tree packing two_level was merged from (its TLAS is what an
	 * instance update rebuilds, rs_render_accel_update_instances()). */
	struct rs_packed_instances instances;
	double tlas_build_ms; /**< rs_render_accel_update_instances(): the TLAS build */
	struct rs_bvh_node *nodes;
	size_t node_count;
	uint32_t *triangle_order;
	struct rs_packed packed;
	double build_ms; /**< rs_bvh_build() only */
	double pack_ms;
	double build_sah; /**< the tree's SAH cost when it was last built (refits compare) */
	double refit_ms;  /**< rs_render_accel_update(): the refit, 0 when it rebuilt */
	double sah_ratio; /**< rs_render_accel_update(): refitted cost / build_sah */
	bool rebuilt;     /**< rs_render_accel_update() rebuilt rather than refitted */
};

/** Build the BVH of `scene` with `bvh` and pack it with `pack` (either NULL: defaults;
 * pack->max_texture_size 0: 2048). RS_ERR_LIMIT when the scene does not fit the texture
 * limit. Free with rs_render_accel_free(), also after a failure (which leaves *out zeroed). */
enum rs_status rs_render_accel_build(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                     const struct rs_pack_desc *pack, struct rs_render_accel *out,
                                     struct rs_error *err);

/** As rs_render_accel_build() but in two levels (rs_pack_instances() merged by
 * rs_pack_two_level()): `packed` is then the merged textures and `nodes` is NULL. The scene
 * must have instances. Free with rs_render_accel_free(). */
enum rs_status rs_render_accel_build_two_level(const struct rs_scene *scene,
                                               const struct rs_bvh_desc *bvh,
                                               const struct rs_pack_desc *pack,
                                               struct rs_render_accel *out, struct rs_error *err);

/** Two levels, `scene` the accel's scene with new instance transforms (the renderer checked
 * its instances): the TLAS rebuilt with `bvh` (rs_pack_instances_update()) and merged in
 * place (rs_pack_two_level_update()), the BLASes untouched; tlas_build_ms and pack_ms say
 * what it took. RS_ERR_INVALID for an accel that is not two levels. */
enum rs_status rs_render_accel_update_instances(struct rs_render_accel *accel,
                                                const struct rs_scene *scene,
                                                const struct rs_bvh_desc *bvh,
                                                struct rs_error *err);

/**
 * Whether `scene` is rendered in two levels under `desc` (desc->instances; the one
 * decision every backend starts from, the GL plan adding its own limits): AUTO and
 * TWO_LEVEL where the scene has instances and the node format is threaded (not wide4).
 * RS_ERR_UNSUPPORTED, naming the reason, when TWO_LEVEL is asked and cannot be done.
 */
enum rs_status rs_render_two_level(const struct rs_render_desc *desc, const struct rs_scene *scene,
                                   bool *out_two_level, struct rs_error *err);

/**
 * The BVH and textures of `scene`, which has the topology of the scene `accel` was built
 * for (rs_render_scene_same_topology()), into `out`: accel's tree refitted to the new
 * positions, or rebuilt with `bvh` when the refitted SAH cost passes `rebuild_ratio` (0:
 * RS_BVH_REBUILD_RATIO) times accel->build_sah; then packed with `pack` into new textures
 * of the same layout when the node count is unchanged. `accel` is left as it was (a GL
 * backend compares the two to upload only the changed rows). Free `out` with
 * rs_render_accel_free(), also after a failure.
 */
enum rs_status rs_render_accel_update(const struct rs_render_accel *accel,
                                      const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                      const struct rs_pack_desc *pack, double rebuild_ratio,
                                      struct rs_render_accel *out, struct rs_error *err);

/** Free what rs_render_accel_build() allocated and zero the struct; NULL is allowed. */
void rs_render_accel_free(struct rs_render_accel *accel);

/** The reference tracer's descriptor of `desc`: size, passes, lights, triangle test,
 * spawn scale and unshadowed (shadows RS_SHADOW_NONE) (camera, rows and intersector 0).
 * Every backend resolves its frame from it (rs_trace_frame_init()), so the kernels and the
 * reference read the same numbers. */
struct rs_trace_desc rs_render_trace_desc(const struct rs_render_desc *desc);

/** The BVH builder's descriptor of `desc`: desc->bvh, with bvh.threads 0 taken from
 * desc->threads (0 there: the machine's cores), so a renderer's set_scene builds on the
 * threads it was given. The tree does not depend on the thread count (docs/bvh.md). */
struct rs_bvh_desc rs_render_bvh_desc(const struct rs_render_desc *desc);

/** Recompute the per-pixel means of `stats` from its counts. */
void rs_render_stats_finish(struct rs_render_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
