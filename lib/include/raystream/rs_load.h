/**
 * @file rs_load.h
 * Scene loading: triangle meshes from OBJ (+MTL) and PLY files through assimp, and the
 * small JSON "view" file (camera, lights, environment, ambient) that travels beside an
 * exported mesh. The core (rs_scene) does not depend on this module.
 *
 * MTL mapping (both ways, see docs/scenes.md): Kd = diffuse, Ks = specular weight (mean of
 * the three channels), Ns = shininess, Ni = index of refraction, d = 1 - transmittance,
 * Pm = mirror reflectance (when absent: mean Ks if illum is 3, 5 or 7, else 0),
 * illum 5 or 7 = Fresnel weighting.
 */
#ifndef RS_LOAD_H
#define RS_LOAD_H

#include <stddef.h>

#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default size limit for mesh and view files (1 GiB). */
#define RS_LOAD_DEFAULT_MAX_FILE_BYTES ((size_t)1 << 30)

/** Loader options; zero-initialised means defaults. */
struct rs_load_desc {
	/** Nonzero: compute angle-weighted normals even if the file has some. */
	int ignore_file_normals;
	/** Refuse larger files with RS_ERR_LIMIT; 0 means RS_LOAD_DEFAULT_MAX_FILE_BYTES. */
	size_t max_file_bytes;
	/** Material for meshes the file gives none; NULL means diffuse 0.8 grey. Copied. */
	const struct rs_material *default_material;
};

/** The material used where a file names none and desc->default_material is NULL. */
void rs_load_default_material(struct rs_material *out);

/**
 * Add the triangle meshes of an OBJ (+MTL) or PLY file, and the materials they use, to an
 * existing scene. Polygons are triangulated; points and lines are skipped. File normals are
 * kept unless desc->ignore_file_normals; otherwise rs_scene computes angle-weighted ones.
 * Every mesh is checked (finite positions and normals, indices in range) before anything
 * is added, so bad data leaves the scene unchanged; only a failure inside rs_scene (its
 * triangle limit, memory) can leave part of the file added.
 * @param desc  options, or NULL for defaults
 * @param path  file to read (format from its content/extension, as assimp detects it)
 * @param scene scene to extend (caller-owned)
 * @param err   optional; on failure gets a one-line message naming the file and problem
 * @return RS_OK, RS_ERR_NOT_FOUND, RS_ERR_IO, RS_ERR_LIMIT (file too large), RS_ERR_PARSE
 *         (malformed file), RS_ERR_BAD_DATA (NaN/inf, bad index, no triangles), or the
 *         status of the failing rs_scene call.
 */
enum rs_status rs_load_mesh_file(const struct rs_load_desc *desc, const char *path,
                                 struct rs_scene *scene, struct rs_error *err);

/**
 * Read a view file (JSON) and apply it to `scene`: every member is optional; "camera"
 * replaces the camera, "lights" are appended, "environment" and "ambient" replace theirs.
 * The whole file is parsed and checked before the scene is touched.
 * Format: see docs/scenes.md ("format": "raystream-view", "version": 1).
 * @return RS_OK, RS_ERR_NOT_FOUND, RS_ERR_IO, RS_ERR_LIMIT, RS_ERR_PARSE (malformed JSON or
 *         a member of the wrong type/shape, named in the message), or the status of the
 *         rs_scene call that rejected a value.
 */
enum rs_status rs_load_view_file(const char *path, struct rs_scene *scene, struct rs_error *err);

/**
 * Format the scene's camera (resolved), lights, environment (resolved) and ambient as view
 * file text. On success *out_text is a NUL-terminated string the caller frees with
 * rs_free(); doubles are written so they read back bit-exactly.
 */
enum rs_status rs_load_view_format(const struct rs_scene *scene, char **out_text,
                                   struct rs_error *err);

/**
 * Path of the sidecar view file of a mesh file: `path` with its extension (if any, after
 * the last '/') replaced by ".json". Writes at most `size` bytes including the NUL.
 * @return RS_OK, or RS_ERR_LIMIT if it does not fit.
 */
enum rs_status rs_load_sidecar_path(const char *path, char *out, size_t size, struct rs_error *err);

/**
 * A whole scene from a mesh file: its meshes plus the sidecar view file if that exists;
 * without one, the camera is rs_camera_frame(bounds, 30 degrees) (45 degrees, 512x512) and
 * one white light sits at the bounds centre + (-10, 25, 20) (SCENES.md's L1), that offset
 * stretched where needed to keep the light at least one bounds diagonal from the centre.
 * On success *out is a new scene the caller frees with rs_scene_destroy(); on failure
 * *out is NULL.
 */
enum rs_status rs_load_scene(const struct rs_load_desc *desc, const char *path,
                             struct rs_scene **out, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
