/*
 * A guard in front of assimp's PLY reader: it reserves memory for every element a header
 * declares before reading a single one, so a 200-byte file declaring 10^9 faces makes it
 * allocate (and touch) gigabytes. Each declared count is held against the bytes the file
 * actually has after the header: an element needs at least its scalar sizes (binary) or
 * one character plus a separator per property (ASCII). The header itself is parsed by
 * load_ply_header.c, which also refuses a header without its end_header line.
 */
#include <limits.h>
#include <stdlib.h>

#include "load_internal.h"

/* Smallest possible encoding of one element. A list may be empty: only its count is
 * certain to be there. */
static unsigned long long min_bytes(const struct rs_ply_element *e, enum rs_ply_format format)
{
	unsigned long long n = 0;
	for (size_t i = 0; i < e->property_count; i++) {
		const struct rs_ply_property *p = &e->properties[i];
		n += format == RS_PLY_ASCII
		         ? 2
		         : rs_ply_type_size(p->is_list ? p->count_type : p->type);
	}
	return n ? n : 1;
}

enum rs_status rs_load_ply_front(const struct rs_load_desc *desc, const char *path,
                                 size_t file_size, struct rs_scene *scene, bool *out_done,
                                 struct rs_error *err)
{
	struct rs_ply_header *h = malloc(sizeof *h);
	bool is_ply = false;
	enum rs_ply_faces faces = RS_PLY_FACES_ASSIMP;
	*out_done = false;
	if (h == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	enum rs_status st = rs_ply_read_header(path, h, &is_ply, err);
	if (st == RS_OK && is_ply)
		st = rs_load_check_ply_header(h, path, file_size, err);
	if (st == RS_OK && is_ply)
		st = rs_ply_check_body(h, path, err);
	if (st == RS_OK && is_ply)
		st = rs_ply_classify_faces(h, path, &faces, err);
	if (st == RS_OK && faces == RS_PLY_FACES_TRISTRIPS) {
		st = rs_ply_load_tristrips(desc, h, path, scene, err);
		*out_done = true;
	}
	free(h);
	return st;
}

enum rs_status rs_load_check_ply_header(const struct rs_ply_header *header, const char *path,
                                        size_t file_size, struct rs_error *err)
{
	unsigned long long body =
	    file_size > header->header_bytes ? file_size - header->header_bytes : 0;
	unsigned long long need = 0;

	for (size_t i = 0; i < header->element_count; i++) {
		const struct rs_ply_element *e = &header->elements[i];
		unsigned long long min = min_bytes(e, header->format);
		need = e->count > (ULLONG_MAX - need) / min ? ULLONG_MAX : need + e->count * min;
		/* One byte of slack: the last ASCII line may lack its newline. */
		if (need > body + 1)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "%s: PLY header declares %llu '%s' elements, more than "
			                    "the file's %llu bytes can hold",
			                    path, e->count, e->name, body);
	}
	return RS_OK;
}
