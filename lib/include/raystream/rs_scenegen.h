/**
 * @file rs_scenegen.h
 * The seed paper's benchmark scenes, built exactly to shared/SCENES.md: Box (153
 * triangles) and CowN (N copies of the 5,804-triangle cow plus a 33-triangle stage), the
 * Mirrors scene of Table 3 (25,254 triangles, defined here: the paper only sizes it), and
 * the exporter that writes any scene as OBJ + MTL + JSON view file for other tools.
 * docs/scenes.md describes every part and how it maps to the spec.
 */
#ifndef RS_SCENEGEN_H
#define RS_SCENEGEN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest N accepted for CowN (1024 copies: about 5.9 M triangles). */
#define RS_SCENEGEN_MAX_COWS 1024u

/** Triangles of the stage added to every CowN herd. */
#define RS_SCENEGEN_STAGE_TRIANGLES 33u

/** Triangles of the mirrors scene (the size of the paper's Table 3 scene). */
#define RS_SCENEGEN_MIRRORS_TRIANGLES 25254u

/** Which scene to build. */
enum rs_scenegen_kind {
	RS_SCENEGEN_COW = 0,
	RS_SCENEGEN_BOX = 1,
	/** Table 3's scene: mirror spheres and a mirror torus that reflect each other and
	 * themselves, 25,254 triangles (docs/scenes.md) */
	RS_SCENEGEN_MIRRORS = 2,
	/** Things that move (docs/scenes.md): two cows walking a circle, one turning in the
	 * middle, a mirror orbiting them; 17,484 triangles; rs_scenegen_desc.frame and fps
	 * place them */
	RS_SCENEGEN_ANIMATED = 3,
};

/** Frames per second when rs_scenegen_desc.fps is 0. */
#define RS_SCENEGEN_DEFAULT_FPS 30u

/** What to build; zero-initialised means Cow1 with the shipped cow. */
struct rs_scenegen_desc {
	enum rs_scenegen_kind kind;
	uint32_t cows; /**< N for CowN; 0 means 1 */
	/** Path of the cow model for RS_SCENEGEN_COW; NULL: the shipped cow.obj, found by
	 * rs_scenegen_data_path(). */
	const char *cow_path;
	/** Scenes that move (ANIMATED, and COW, whose cow N / 2 sways): the frame shown, at
	 * time frame / fps seconds, a pure function of the two (no clock); frame 0 of a COW
	 * scene is the still one. Other kinds refuse a frame > 0. Every frame of one scene has
	 * the same topology (rs_renderer_update_vertices() takes any after any; an instanced
	 * herd's, rs_renderer_update_instances()). */
	uint32_t frame;
	uint32_t fps; /**< 0 -> RS_SCENEGEN_DEFAULT_FPS */
	/** CowN as N instances of one prototype cow (rs_scene_add_instance) instead of N copies:
	 * the same triangles in the same order (name "cowNi"), for two-level packing. It moves
	 * as CowN does: at frame > 0 cow N / 2 has CowN's sway as its instance transform, and
	 * every other triangle (the stage) is the same to the bit in every frame, so
	 * rs_renderer_update_instances() takes any frame after any. */
	bool instanced;
};

/**
 * Parse a scene name: "box", "mirrors", "animated" or "cowN" with N = 1..RS_SCENEGEN_MAX_COWS
 * written without leading zeros (lower case), optionally followed by "i" (instanced). Fills
 * *out (cow_path NULL); on failure returns RS_ERR_INVALID with a message naming the bad name.
 */
enum rs_status rs_scenegen_parse(const char *name, struct rs_scenegen_desc *out,
                                 struct rs_error *err);

/**
 * Canonical name of a scene ("box", "mirrors", "cow17") into out (at most size bytes, NUL
 * included).
 * @return RS_OK, RS_ERR_INVALID (bad desc) or RS_ERR_LIMIT (does not fit).
 */
enum rs_status rs_scenegen_name(const struct rs_scenegen_desc *desc, char *out, size_t size,
                                struct rs_error *err);

/**
 * Build a scene. Always adds all four lights L1..L4 (renderers use the first N). For COW
 * the cow file is read with rs_load_mesh_file() (normals computed unless the file has some).
 * On success *out is a new scene the caller frees with rs_scene_destroy(); on failure
 * *out is NULL and err names the problem.
 */
enum rs_status rs_scenegen_build(const struct rs_scenegen_desc *desc, struct rs_scene **out,
                                 struct rs_error *err);

/**
 * Find a file shipped with raystream (the models in data/, e.g. "cow.obj") into `out`
 * (size bytes), looking in this order:
 *   1. $RS_DATA_DIR, when set: the only place then (RS_ERR_NOT_FOUND when the file is not
 *      there, rather than a quiet fallback to another copy);
 *   2. PREFIX/share/raystream for the running program at PREFIX/bin (any folder name), so
 *      an installed program finds its install's data wherever the prefix was moved;
 *   3. the source tree's data/ the library was built from;
 *   4. the configured install prefix's share/raystream.
 * RS_ERR_NOT_FOUND names the places looked in.
 */
enum rs_status rs_scenegen_data_path(const char *file, char *out, size_t size,
                                     struct rs_error *err);

/**
 * A scene by the name a command line gives: "box", "mirrors", "cowN" (the shipped cow,
 * rs_scenegen_data_path()) or the path of an OBJ/PLY file with an optional view file
 * beside it (rs_load_scene()). RS_ERR_NOT_FOUND names a name that is none of these.
 */
enum rs_status rs_scenegen_load(const char *name, struct rs_scene **out, struct rs_error *err);

/** rs_scenegen_load() of frame `frame` at `fps` (0: RS_SCENEGEN_DEFAULT_FPS) of a scene that
 * moves ("animated", "cowN", "cowNi"); frame 0 of any scene is rs_scenegen_load()'s; RS_ERR_INVALID
 * for frame > 0 of one that does not move. */
enum rs_status rs_scenegen_load_frame(const char *name, uint32_t frame, uint32_t fps,
                                      struct rs_scene **out, struct rs_error *err);

/** Whether the scene named `name` moves with its frame ("animated", "cowN", "cowNi"). */
bool rs_scenegen_moves(const char *name);

/**
 * Export a scene: an OBJ with positions, normals and one object per run of triangles
 * sharing a material; an MTL beside it (obj_path with the extension replaced by ".mtl",
 * named by `mtllib`); and the JSON view file at view_path (camera, lights, environment,
 * ambient; see rs_load_view_format()). view_path may be NULL to skip it. Each file is
 * written to a temporary file in its directory, and all are renamed into place only once
 * every one is complete, so a reader never sees a half-written file or half a set; on
 * failure no temporary file is left behind. RS_ERR_INVALID when two of the three paths
 * coincide; RS_ERR_IO when a target exists and is not a regular file (a device or FIFO
 * would otherwise be replaced by the rename).
 * rs_load_scene() on obj_path reads the scene back when view_path is the sidecar path.
 */
enum rs_status rs_scene_export(const struct rs_scene *scene, const char *obj_path,
                               const char *view_path, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
