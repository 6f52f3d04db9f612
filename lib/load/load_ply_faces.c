/*
 * PLY faces stored as triangle strips (an element "tristrips" with one vertex_indices
 * list, -1 restarting a strip), as several classic scanned models are distributed. assimp
 * reads only the first three indices of such a file, so they are decoded here: vertices
 * (x, y, z and, when all three are there, nx, ny, nz) and strips, ASCII or binary of
 * either byte order. Any other face layout assimp would misread is refused by name, and
 * every PLY body is walked once to hold it to its header (rs_ply_check_body): assimp
 * invents elements a truncated file lacks.
 *
 * Strip rule: within a run of indices s0 s1 s2 ... (between restarts), triangle k is
 * (s[k], s[k+1], s[k+2]) for even k and (s[k+1], s[k], s[k+2]) for odd k, so every
 * triangle keeps the first one's winding. Triangles that repeat an index are dropped:
 * strips use them only to turn or to join runs, and they have no area. They still count
 * for the parity, so the winding of the triangles after them stays right.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"

static bool lists_indices(const struct rs_ply_property *p)
{
	return p->is_list &&
	       (strcmp(p->name, "vertex_indices") == 0 || strcmp(p->name, "vertex_index") == 0);
}

static bool is_integer(enum rs_ply_type t)
{
	return t >= RS_PLY_I8 && t <= RS_PLY_U32;
}

enum rs_status rs_ply_classify_faces(const struct rs_ply_header *h, const char *path,
                                     enum rs_ply_faces *out, struct rs_error *err)
{
	RS_ASSERT(h && path && out);
	const struct rs_ply_element *faces = NULL, *strips = NULL;
	*out = RS_PLY_FACES_ASSIMP;
	for (size_t i = 0; i < h->element_count; i++) {
		const struct rs_ply_element *e = &h->elements[i];
		size_t lists = 0;
		for (size_t j = 0; j < e->property_count; j++)
			lists += lists_indices(&e->properties[j]);
		if (strcmp(e->name, "face") == 0)
			faces = e;
		else if (strcmp(e->name, "tristrips") == 0)
			strips = e;
		else if (lists > 0)
			return rs_error_set(
			    err, RS_ERR_UNSUPPORTED,
			    "%s: PLY element '%s' lists vertex indices; only 'face' "
			    "and 'tristrips' elements are read",
			    path, e->name);
		if ((e == faces || e == strips) && e->count > 0 && lists != 1)
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "%s: PLY element '%s' needs exactly one vertex_indices "
			                    "list (has %zu)",
			                    path, e->name, lists);
	}
	if (strips == NULL || strips->count == 0)
		return RS_OK;
	if (faces != NULL && faces->count > 0)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "%s: PLY file has both 'face' and 'tristrips' elements", path);
	for (size_t j = 0; j < strips->property_count; j++) {
		const struct rs_ply_property *p = &strips->properties[j];
		if (p->type == RS_PLY_UNKNOWN || (p->is_list && p->count_type == RS_PLY_UNKNOWN))
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "%s: PLY 'tristrips' property '%s' has an unknown type",
			                    path, p->name);
		if (lists_indices(p) && (!is_integer(p->type) || !is_integer(p->count_type)))
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "%s: PLY strip indices must be integers", path);
	}
	*out = RS_PLY_FACES_TRISTRIPS;
	return RS_OK;
}

/* ---- Body reader ------------------------------------------------------------------- */

struct body {
	const unsigned char *p, *end;
	enum rs_ply_format format;
};

/* One scalar as a double (exact for every integer type). false at the end of the data
 * or on a malformed ASCII token. */
static bool read_scalar(struct body *b, enum rs_ply_type type, double *out)
{
	if (b->format == RS_PLY_ASCII) {
		while (b->p < b->end && strchr(" \t\r\n", *b->p) != NULL && *b->p != '\0')
			b->p++;
		char tok[64];
		size_t n = 0;
		while (b->p < b->end && strchr(" \t\r\n", *b->p) == NULL && n + 1 < sizeof tok)
			tok[n++] = (char)*b->p++;
		tok[n] = '\0';
		char *end = NULL;
		*out = strtod(tok, &end);
		return n > 0 && *end == '\0';
	}
	size_t size = rs_ply_type_size(type);
	if (size == 0 || (size_t)(b->end - b->p) < size)
		return false;
	unsigned char raw[8];
	for (size_t i = 0; i < size; i++)
		raw[i] = b->format == RS_PLY_BINARY_LE ? b->p[i] : b->p[size - 1 - i];
	b->p += size;
	/* raw is little-endian now; assemble without assuming the host's byte order. */
	uint64_t u = 0;
	for (size_t i = size; i-- > 0;)
		u = (u << 8) | raw[i];
	switch (type) {
	case RS_PLY_I8:
		*out = (int8_t)u;
		break;
	case RS_PLY_U8:
	case RS_PLY_U16:
	case RS_PLY_U32:
		*out = (double)u;
		break;
	case RS_PLY_I16:
		*out = (int16_t)u;
		break;
	case RS_PLY_I32:
		*out = (int32_t)u;
		break;
	case RS_PLY_F32: {
		uint32_t bits = (uint32_t)u;
		float f;
		memcpy(&f, &bits, sizeof f);
		*out = f;
		break;
	}
	case RS_PLY_F64:
		memcpy(out, &u, sizeof *out);
		break;
	case RS_PLY_UNKNOWN:
		return false;
	}
	return true;
}

/* ---- Strips ------------------------------------------------------------------------- */

struct strips {
	float *positions, *normals; /* normals: NULL unless nx, ny, nz are all given */
	size_t vertex_count;
	uint32_t *indices; /* three per triangle */
	size_t triangle_count, capacity;
	uint32_t a, b; /* the last two indices of the current run */
	size_t run;    /* indices seen in the current run */
};

static enum rs_status strip_index(struct strips *s, double v, const char *path,
                                  struct rs_error *err)
{
	if (v == -1.0) {
		s->run = 0;
		return RS_OK;
	}
	if (!(v >= 0.0) || v >= (double)s->vertex_count || v != floor(v))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "%s: PLY strip index %.0f out of range (%zu vertices)", path, v,
		                    s->vertex_count);
	uint32_t c = (uint32_t)v;
	if (s->run >= 2) {
		/* Odd triangles swap their first two corners to keep the strip's winding. */
		uint32_t t[3] = {s->a, s->b, c};
		if ((s->run - 2) % 2 == 1) {
			t[0] = s->b;
			t[1] = s->a;
		}
		if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
			if (s->triangle_count == s->capacity) {
				size_t cap = s->capacity ? 2 * s->capacity : 1024;
				uint32_t *grown = realloc(s->indices, cap * 3 * sizeof *grown);
				if (grown == NULL)
					return rs_error_set(err, RS_ERR_NO_MEMORY,
					                    "%s: out of memory", path);
				s->indices = grown;
				s->capacity = cap;
			}
			memcpy(s->indices + 3 * s->triangle_count++, t, sizeof t);
		}
	}
	s->a = s->b;
	s->b = c;
	s->run++;
	return RS_OK;
}

/* Read (or skip) one element instance; vertex coordinates and strip indices are kept when
 * `s` is given (NULL: only walked, to check the body holds what the header declares). */
static enum rs_status read_instance(struct body *b, const struct rs_ply_element *e, size_t i,
                                    struct strips *s, const char *path, struct rs_error *err)
{
	static const char *const axes[6] = {"x", "y", "z", "nx", "ny", "nz"};
	bool vertex = s && strcmp(e->name, "vertex") == 0;
	bool strip = s && strcmp(e->name, "tristrips") == 0;
	double v;
	for (size_t j = 0; j < e->property_count; j++) {
		const struct rs_ply_property *p = &e->properties[j];
		if (!read_scalar(b, p->is_list ? p->count_type : p->type, &v))
			goto truncated;
		if (p->is_list) {
			if (!(v >= 0.0) || v > (double)(b->end - b->p))
				return rs_error_set(err, RS_ERR_PARSE,
				                    "%s: PLY '%s' %zu has a list of %.0f items",
				                    path, e->name, i, v);
			size_t n = (size_t)v;
			bool keep = strip && lists_indices(p);
			if (keep)
				s->run = 0; /* each list is a strip of its own */
			for (size_t k = 0; k < n; k++) {
				if (!read_scalar(b, p->type, &v))
					goto truncated;
				enum rs_status st = keep ? strip_index(s, v, path, err) : RS_OK;
				if (st != RS_OK)
					return st;
			}
			continue;
		}
		for (int a = 0; vertex && a < 6; a++) {
			if (strcmp(p->name, axes[a]) != 0)
				continue;
			float *dst = a < 3 ? s->positions : s->normals;
			if (dst != NULL)
				dst[i * 3 + (size_t)(a % 3)] = (float)v;
		}
	}
	return RS_OK;
truncated:
	return rs_error_set(err, RS_ERR_PARSE,
	                    "%s: PLY data ends after %zu of the %llu '%s' elements its header "
	                    "declares",
	                    path, i, e->count, e->name);
}

/* Walk every element the header declares: the body must hold exactly them. */
static enum rs_status walk(const struct rs_ply_header *h, const char *path, struct body *b,
                           struct strips *s, struct rs_error *err)
{
	for (size_t e = 0; e < h->element_count; e++)
		for (unsigned long long i = 0; i < h->elements[e].count; i++) {
			enum rs_status st =
			    read_instance(b, &h->elements[e], (size_t)i, s, path, err);
			if (st != RS_OK)
				return st;
		}
	/* Whitespace may follow (a final newline); anything else is data no element holds. */
	const unsigned char *rest = b->p;
	while (rest < b->end && (*rest == ' ' || *rest == '\t' || *rest == '\r' || *rest == '\n'))
		rest++;
	if (rest < b->end)
		return rs_error_set(err, RS_ERR_PARSE,
		                    "%s: PLY has %zu bytes after its last declared element ('%s')",
		                    path, (size_t)(b->end - b->p),
		                    h->element_count ? h->elements[h->element_count - 1].name : "");
	return RS_OK;
}

enum rs_status rs_ply_check_body(const struct rs_ply_header *h, const char *path,
                                 struct rs_error *err)
{
	RS_ASSERT(h && path);
	if (h->partial)
		return RS_OK; /* a header we could not follow: assimp judges the file */
	for (size_t e = 0; e < h->element_count; e++)
		for (size_t j = 0; j < h->elements[e].property_count; j++) {
			const struct rs_ply_property *p = &h->elements[e].properties[j];
			if (p->type == RS_PLY_UNKNOWN ||
			    (p->is_list && p->count_type == RS_PLY_UNKNOWN))
				return RS_OK;
		}
	const unsigned char *bytes;
	size_t size;
	enum rs_status status = rs_load_map_file(path, &bytes, &size, err);
	if (status != RS_OK)
		return status;
	size_t skip = size < h->header_bytes ? size : h->header_bytes;
	struct body b = {bytes ? bytes + skip : NULL, bytes ? bytes + size : NULL, h->format};
	status = walk(h, path, &b, NULL, err);
	rs_load_unmap_file(bytes, size);
	return status;
}

/* Which of x, y, z, nx, ny, nz the vertex element has (bit a for axes[a]). */
static unsigned vertex_axes(const struct rs_ply_element *e)
{
	static const char *const axes[6] = {"x", "y", "z", "nx", "ny", "nz"};
	unsigned bits = 0;
	for (size_t j = 0; j < e->property_count; j++)
		for (unsigned a = 0; a < 6; a++)
			if (!e->properties[j].is_list &&
			    strcmp(e->properties[j].name, axes[a]) == 0)
				bits |= 1u << a;
	return bits;
}

static enum rs_status decode(const struct rs_load_desc *desc, const struct rs_ply_header *h,
                             const char *path, struct body *b, struct strips *s,
                             struct rs_error *err)
{
	const struct rs_ply_element *vertices = NULL;
	for (size_t i = 0; i < h->element_count; i++)
		if (strcmp(h->elements[i].name, "vertex") == 0)
			vertices = &h->elements[i];
	if (vertices == NULL || (vertex_axes(vertices) & 7u) != 7u)
		return rs_error_set(err, RS_ERR_PARSE, "%s: PLY has no vertex element with x, y, z",
		                    path);
	if (vertices->count == 0 || vertices->count > UINT32_MAX)
		return rs_error_set(err, RS_ERR_BAD_DATA, "%s: PLY has %llu vertices", path,
		                    vertices->count);
	s->vertex_count = (size_t)vertices->count;
	bool want_normals = (vertex_axes(vertices) & 0x38u) == 0x38u && !desc->ignore_file_normals;
	s->positions = calloc(s->vertex_count * 3, sizeof(float));
	s->normals = want_normals ? calloc(s->vertex_count * 3, sizeof(float)) : NULL;
	if (s->positions == NULL || (want_normals && s->normals == NULL))
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	enum rs_status st = walk(h, path, b, s, err);
	if (st != RS_OK)
		return st;
	for (size_t i = 0; i < s->vertex_count * 3; i++)
		if (!isfinite(s->positions[i]) || (s->normals && !isfinite(s->normals[i])))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "%s: PLY vertex %zu has a NaN or infinite value", path,
			                    i / 3);
	if (s->triangle_count == 0)
		return rs_error_set(err, RS_ERR_BAD_DATA, "%s: no triangles in its strips", path);
	return RS_OK;
}

enum rs_status rs_ply_load_tristrips(const struct rs_load_desc *desc, const struct rs_ply_header *h,
                                     const char *path, struct rs_scene *scene, struct rs_error *err)
{
	RS_ASSERT(desc && h && path && scene);
	char *text = NULL;
	size_t size = 0;
	enum rs_status st = rs_load_read_text(path, desc->max_file_bytes, &text, &size, err);
	if (st != RS_OK)
		return st;
	struct body b = {(const unsigned char *)text +
	                     (h->header_bytes < size ? h->header_bytes : size),
	                 (const unsigned char *)text + size, h->format};
	struct strips s = {0};
	st = decode(desc, h, path, &b, &s, err);
	if (st == RS_OK) {
		struct rs_material mat;
		uint32_t id;
		if (desc->default_material != NULL)
			mat = *desc->default_material;
		else
			rs_load_default_material(&mat);
		struct rs_mesh_desc md = {.positions = s.positions,
		                          .vertex_count = s.vertex_count,
		                          .normals = s.normals,
		                          .indices = s.indices,
		                          .triangle_count = s.triangle_count};
		st = rs_scene_add_material(scene, &mat, &id, err);
		md.material = id;
		if (st == RS_OK)
			st = rs_scene_add_mesh(scene, &md, err);
		if (st != RS_OK)
			rs_error_prefix(err, st, "%s", path);
	}
	free(s.positions);
	free(s.normals);
	free(s.indices);
	free(text);
	return st;
}
