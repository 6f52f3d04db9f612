/*
 * The PLY header, parsed once before assimp or our own decoder sees the body: the guard
 * (load_ply_guard.c) holds the declared counts against the file size and the face
 * classifier (load_ply_faces.c) decides who can decode the faces.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"

#define PLY_HEADER_MAX 65536

static const struct {
	const char *name;
	enum rs_ply_type type;
} k_types[] = {{"char", RS_PLY_I8},    {"uchar", RS_PLY_U8},    {"int8", RS_PLY_I8},
               {"uint8", RS_PLY_U8},   {"short", RS_PLY_I16},   {"ushort", RS_PLY_U16},
               {"int16", RS_PLY_I16},  {"uint16", RS_PLY_U16},  {"int", RS_PLY_I32},
               {"uint", RS_PLY_U32},   {"int32", RS_PLY_I32},   {"uint32", RS_PLY_U32},
               {"float", RS_PLY_F32},  {"float32", RS_PLY_F32}, {"double", RS_PLY_F64},
               {"float64", RS_PLY_F64}};

static enum rs_ply_type type_named(const char *name)
{
	for (size_t i = 0; name && i < sizeof k_types / sizeof k_types[0]; i++)
		if (strcmp(name, k_types[i].name) == 0)
			return k_types[i].type;
	return RS_PLY_UNKNOWN;
}

size_t rs_ply_type_size(enum rs_ply_type type)
{
	static const size_t sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
	return (unsigned)type < sizeof sizes / sizeof sizes[0] ? sizes[type] : 0;
}

/* The end of the end_header line within buf, or NULL. assimp's PLY reader loops forever on
 * a header without it (a 200-byte file hung the tools), so it must be in the bytes read. */
static char *find_end_header(char *buf)
{
	for (char *p = buf; *p != '\0';) {
		char *nl = strchr(p, '\n');
		char *q = p + strspn(p, " \t");

		if (strncmp(q, "end_header", 10) == 0 && strchr(" \t\r\n", q[10]) != NULL)
			return nl != NULL ? nl + 1 : q + strlen(q);
		if (nl == NULL)
			return NULL;
		p = nl + 1;
	}
	return NULL;
}

static enum rs_status parse_line(char *line, struct rs_ply_header *h, bool *in_element,
                                 const char *path, struct rs_error *err)
{
	char *save = NULL;
	const char *word = strtok_r(line, " \t", &save);

	if (word == NULL)
		return RS_OK;
	if (strcmp(word, "format") == 0) {
		const char *fmt = strtok_r(NULL, " \t", &save);
		h->format = fmt == NULL                                ? RS_PLY_ASCII
		            : strcmp(fmt, "binary_little_endian") == 0 ? RS_PLY_BINARY_LE
		            : strcmp(fmt, "binary_big_endian") == 0    ? RS_PLY_BINARY_BE
		                                                       : RS_PLY_ASCII;
	} else if (strcmp(word, "element") == 0) {
		const char *name = strtok_r(NULL, " \t", &save);
		const char *num = strtok_r(NULL, " \t", &save);
		char *num_end = NULL;

		*in_element = false;
		/* An element left out makes the header partial: assimp's to judge. */
		if (name == NULL || num == NULL || num[0] == '-') {
			h->partial = true;
			return RS_OK;
		}
		errno = 0;
		unsigned long long count = strtoull(num, &num_end, 10);
		if (errno != 0 || *num_end != '\0') {
			h->partial = true;
			return RS_OK;
		}
		if (h->element_count == RS_PLY_MAX_ELEMENTS)
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "%s: PLY header has more than %d elements", path,
			                    RS_PLY_MAX_ELEMENTS);
		struct rs_ply_element *e = &h->elements[h->element_count++];
		snprintf(e->name, sizeof e->name, "%s", name);
		e->count = count;
		*in_element = true;
	} else if (strcmp(word, "property") == 0 && *in_element) {
		struct rs_ply_element *e = &h->elements[h->element_count - 1];
		const char *type = strtok_r(NULL, " \t", &save);
		struct rs_ply_property p = {{0}, RS_PLY_UNKNOWN, false, RS_PLY_UNKNOWN};

		if (type != NULL && strcmp(type, "list") == 0) {
			p.is_list = true;
			p.count_type = type_named(strtok_r(NULL, " \t", &save));
			type = strtok_r(NULL, " \t", &save);
		}
		p.type = type_named(type);
		const char *name = strtok_r(NULL, " \t", &save);
		snprintf(p.name, sizeof p.name, "%s", name ? name : "");
		if (e->property_count == RS_PLY_MAX_PROPERTIES)
			return rs_error_set(err, RS_ERR_UNSUPPORTED,
			                    "%s: PLY element '%s' has more than %d properties",
			                    path, e->name, RS_PLY_MAX_PROPERTIES);
		e->properties[e->property_count++] = p;
	}
	return RS_OK;
}

enum rs_status rs_ply_read_header(const char *path, struct rs_ply_header *out, bool *out_is_ply,
                                  struct rs_error *err)
{
	RS_ASSERT(path && out && out_is_ply);
	memset(out, 0, sizeof *out);
	*out_is_ply = false;
	FILE *f = fopen(path, "rb");
	if (f == NULL)
		return rs_error_set(err, RS_ERR_IO, "%s: %s", path, strerror(errno));
	char *buf = malloc(PLY_HEADER_MAX + 1);
	if (buf == NULL) {
		fclose(f);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	}
	size_t got = fread(buf, 1, PLY_HEADER_MAX, f);
	fclose(f);
	buf[got] = '\0';
	enum rs_status st = RS_OK;
	if (strncmp(buf, "ply", 3) != 0 && strncmp(buf, "PLY", 3) != 0)
		goto done;
	*out_is_ply = true;
	char *end = find_end_header(buf);
	if (end == NULL) {
		st = rs_error_set(err, RS_ERR_PARSE,
		                  "%s: PLY header has no end_header line in its first %d bytes",
		                  path, PLY_HEADER_MAX);
		goto done;
	}
	out->header_bytes = (size_t)(end - buf);
	*end = '\0';
	bool in_element = false;
	char *save = NULL;
	for (char *line = strtok_r(buf, "\r\n", &save); line != NULL && st == RS_OK;
	     line = strtok_r(NULL, "\r\n", &save))
		st = parse_line(line, out, &in_element, path, err);
done:
	free(buf);
	return st;
}
