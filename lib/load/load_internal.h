/* Helpers shared by the loader's files (not installed). */
#ifndef RS_LOAD_INTERNAL_H
#define RS_LOAD_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_load.h"
#include "raystream/rs_status.h"

/*
 * Check that `path` names a readable regular file of at most `max_bytes` bytes (0: the
 * default limit); its size goes to *out_size. Errors name the file.
 */
enum rs_status rs_load_check_file(const char *path, size_t max_bytes, size_t *out_size,
                                  struct rs_error *err);

/* Read a whole file (checked as above) into a NUL-terminated buffer the caller free()s. */
enum rs_status rs_load_read_text(const char *path, size_t max_bytes, char **out_text,
                                 size_t *out_size, struct rs_error *err);

/* Map a whole file read-only (no copy: checks of large models cost no second buffer);
 * an empty file gives NULL and 0. Release with rs_load_unmap_file(). */
enum rs_status rs_load_map_file(const char *path, const unsigned char **out_bytes, size_t *out_size,
                                struct rs_error *err);
void rs_load_unmap_file(const unsigned char *bytes, size_t size);

/* ---- PLY headers (load_ply_header.c) ---------------------------------------------- */

#define RS_PLY_NAME_MAX 32
#define RS_PLY_MAX_ELEMENTS 16
#define RS_PLY_MAX_PROPERTIES 32

enum rs_ply_format { RS_PLY_ASCII, RS_PLY_BINARY_LE, RS_PLY_BINARY_BE };

/* Scalar types; RS_PLY_UNKNOWN for a type name this parser does not know. */
enum rs_ply_type {
	RS_PLY_UNKNOWN,
	RS_PLY_I8,
	RS_PLY_U8,
	RS_PLY_I16,
	RS_PLY_U16,
	RS_PLY_I32,
	RS_PLY_U32,
	RS_PLY_F32,
	RS_PLY_F64,
};

struct rs_ply_property {
	char name[RS_PLY_NAME_MAX];
	enum rs_ply_type type; /* a list's item type */
	bool is_list;
	enum rs_ply_type count_type; /* a list's count type */
};

struct rs_ply_element {
	char name[RS_PLY_NAME_MAX];
	unsigned long long count;
	size_t property_count;
	struct rs_ply_property properties[RS_PLY_MAX_PROPERTIES];
};

struct rs_ply_header {
	enum rs_ply_format format;
	size_t header_bytes; /* up to and including the end_header line */
	bool partial;        /* an element line was left out (its count did not parse) */
	size_t element_count;
	struct rs_ply_element elements[RS_PLY_MAX_ELEMENTS];
};

/* Bytes of one scalar of `type` (0 for RS_PLY_UNKNOWN). */
size_t rs_ply_type_size(enum rs_ply_type type);

/*
 * Read the header of `path` if it is a PLY file: *out_is_ply says whether it is. Elements
 * whose count does not parse are left out (assimp judges those files). RS_ERR_PARSE when
 * end_header is missing from the first 64 KiB, RS_ERR_UNSUPPORTED beyond
 * RS_PLY_MAX_ELEMENTS elements or RS_PLY_MAX_PROPERTIES properties per element.
 */
enum rs_status rs_ply_read_header(const char *path, struct rs_ply_header *out, bool *out_is_ply,
                                  struct rs_error *err);

/*
 * Refuse a PLY file whose header declares more elements than its size can hold (assimp
 * reserves memory for the declared counts up front). RS_OK for other files and for
 * headers it cannot follow; RS_ERR_PARSE naming the element otherwise.
 */
enum rs_status rs_load_check_ply_header(const struct rs_ply_header *header, const char *path,
                                        size_t file_size, struct rs_error *err);

/*
 * Everything that happens to a PLY file before assimp: header, size guard, face layout.
 * Files with strips are decoded and added here (*out_done = true); other files (not PLY
 * or faces assimp reads) are left to the caller (*out_done = false).
 */
enum rs_status rs_load_ply_front(const struct rs_load_desc *desc, const char *path,
                                 size_t file_size, struct rs_scene *scene, bool *out_done,
                                 struct rs_error *err);

/*
 * An OBJ file (by its .obj name; RS_OK for others) whose 'v' lines have fewer than three
 * coordinates or 'f' lines fewer than three vertices (a file cut off mid-line): assimp
 * drops such lines silently. RS_ERR_PARSE naming the element and the line.
 */
enum rs_status rs_obj_check_body(const char *path, struct rs_error *err);

/* ---- PLY faces (load_ply_faces.c) ----------------------------------------------------- */

/* How a PLY file's faces are stored, as far as raystream decodes them. */
enum rs_ply_faces {
	RS_PLY_FACES_ASSIMP,    /* a "face" element with a vertex_indices list (or none) */
	RS_PLY_FACES_TRISTRIPS, /* a "tristrips" element: decoded by rs_ply_load_tristrips() */
};

/*
 * Decide who decodes the faces; RS_ERR_UNSUPPORTED (naming the element) for any layout
 * neither does: index lists in other elements, both faces and strips, non-integer indices.
 */
enum rs_status rs_ply_classify_faces(const struct rs_ply_header *header, const char *path,
                                     enum rs_ply_faces *out, struct rs_error *err);

/*
 * Hold the body to the header: every declared element present in full, nothing but
 * whitespace after the last. RS_ERR_PARSE naming the element where the data ends ("after 1
 * of the 2 'face' elements its header declares") or the bytes left over. RS_OK without looking
 * for a header it could not follow (partial, unknown types): assimp judges those.
 */
enum rs_status rs_ply_check_body(const struct rs_ply_header *header, const char *path,
                                 struct rs_error *err);

/* Decode a file classified RS_PLY_FACES_TRISTRIPS and add its mesh to `scene`. */
enum rs_status rs_ply_load_tristrips(const struct rs_load_desc *desc,
                                     const struct rs_ply_header *header, const char *path,
                                     struct rs_scene *scene, struct rs_error *err);

/*
 * Exact weld of `count` vertices (float xyz at `stride` bytes; `nrm` NULL or normals at the
 * same stride): vertices with exactly equal positions (and normals, when given) share one
 * index. out_remap[v] = the vertex's new index; out_source[u] = the first input vertex of
 * new vertex u (both caller-owned, `count` entries); *out_unique = number of new vertices,
 * numbered in order of first appearance. RS_ERR_NO_MEMORY when scratch allocation fails.
 */
enum rs_status rs_load_weld(const float *pos, const float *nrm, size_t stride, size_t count,
                            uint32_t *out_remap, uint32_t *out_source, size_t *out_unique);

#endif
