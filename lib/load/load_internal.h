/* Helpers shared by the loader's files (not installed). */
#ifndef RS_LOAD_INTERNAL_H
#define RS_LOAD_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

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

/*
 * Refuse a PLY file whose header declares more elements than its size can hold (assimp
 * reserves memory for the declared counts up front). RS_OK for other files and for
 * headers it cannot follow; RS_ERR_PARSE naming the element otherwise.
 */
enum rs_status rs_load_check_ply_header(const char *path, size_t file_size, struct rs_error *err);

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
