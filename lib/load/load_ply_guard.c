/*
 * A guard in front of assimp's PLY reader: it reserves memory for every element a header
 * declares before reading a single one, so a 200-byte file declaring 10^9 faces makes it
 * allocate (and touch) gigabytes. Here the header is read first and each declared count is
 * held against the bytes the file actually has after the header: an element needs at
 * least its scalar sizes (binary) or one character plus a separator per property (ASCII).
 * A header without its end_header line is refused too (assimp never returns from it).
 * Other headers this parser does not understand are left to assimp to judge.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"

#define PLY_HEADER_MAX 65536

static size_t scalar_size(const char *type)
{
	static const struct {
		const char *name;
		size_t size;
	} types[] = {{"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},
	             {"short", 2}, {"ushort", 2},  {"int16", 2},  {"uint16", 2},
	             {"int", 4},   {"uint", 4},    {"int32", 4},  {"uint32", 4},
	             {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};

	for (size_t i = 0; i < sizeof(types) / sizeof(types[0]); i++)
		if (strcmp(type, types[i].name) == 0)
			return types[i].size;
	return 0;
}

struct element {
	char name[32];
	unsigned long long count;
	size_t min_bytes; /* smallest possible encoding of one element */
};

/* The element being declared is complete: add its smallest size to *need (saturating)
 * and check the total against the bytes after the header. One byte of slack: the last
 * ASCII line may lack its newline. */
static enum rs_status check_element(const char *path, const struct element *e,
                                    unsigned long long body, unsigned long long *need,
                                    struct rs_error *err)
{
	unsigned long long min = e->min_bytes ? e->min_bytes : 1;

	if (e->name[0] == '\0')
		return RS_OK;
	*need = e->count > (ULLONG_MAX - *need) / min ? ULLONG_MAX : *need + e->count * min;
	if (*need > body + 1)
		return rs_error_set(err, RS_ERR_PARSE,
		                    "%s: PLY header declares %llu '%s' elements, more than the "
		                    "file's %llu bytes can hold",
		                    path, e->count, e->name, body);
	return RS_OK;
}

enum rs_status rs_load_check_ply_header(const char *path, size_t file_size, struct rs_error *err)
{
	char *buf = NULL, *line, *save = NULL, *end;
	size_t got, header_len;
	unsigned long long body, need = 0;
	int binary = 0;
	struct element e = {{0}, 0, 0};
	enum rs_status st = RS_OK;
	FILE *f = fopen(path, "rb");

	if (f == NULL)
		return rs_error_set(err, RS_ERR_IO, "%s: %s", path, strerror(errno));
	buf = malloc(PLY_HEADER_MAX + 1);
	if (buf == NULL) {
		fclose(f);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	}
	got = fread(buf, 1, PLY_HEADER_MAX, f);
	fclose(f);
	buf[got] = '\0';
	if (strncmp(buf, "ply", 3) != 0 && strncmp(buf, "PLY", 3) != 0)
		goto done; /* not PLY */
	/* assimp's PLY reader loops forever on a header without its end_header line (a
	 * 200-byte file hung the tools), so the line must be there, within the bytes read. */
	end = NULL;
	for (char *p = buf; *p != '\0';) {
		char *nl = strchr(p, '\n');
		char *q = p + strspn(p, " \t");

		if (strncmp(q, "end_header", 10) == 0 && strchr(" \t\r\n", q[10]) != NULL) {
			end = nl != NULL ? nl + 1 : q + strlen(q);
			break;
		}
		if (nl == NULL)
			break;
		p = nl + 1;
	}
	if (end == NULL) {
		st = rs_error_set(err, RS_ERR_PARSE,
		                  "%s: PLY header has no end_header line in its first %d bytes",
		                  path, PLY_HEADER_MAX);
		goto done;
	}
	header_len = (size_t)(end - buf);
	*end = '\0';
	body = file_size > header_len ? file_size - header_len : 0;

	for (line = strtok_r(buf, "\r\n", &save); line != NULL && st == RS_OK;
	     line = strtok_r(NULL, "\r\n", &save)) {
		char *tok_save = NULL;
		char *word = strtok_r(line, " \t", &tok_save);

		if (word == NULL)
			continue;
		if (strcmp(word, "format") == 0) {
			const char *fmt = strtok_r(NULL, " \t", &tok_save);

			binary = fmt != NULL && strncmp(fmt, "binary", 6) == 0;
		} else if (strcmp(word, "element") == 0) {
			const char *name = strtok_r(NULL, " \t", &tok_save);
			const char *num = strtok_r(NULL, " \t", &tok_save);
			char *num_end = NULL;

			st = check_element(path, &e, body, &need, err);
			memset(&e, 0, sizeof(e));
			if (name == NULL || num == NULL || num[0] == '-')
				continue; /* assimp's to judge */
			errno = 0;
			e.count = strtoull(num, &num_end, 10);
			if (errno != 0 || *num_end != '\0')
				continue;
			snprintf(e.name, sizeof(e.name), "%s", name);
		} else if (strcmp(word, "property") == 0 && e.name[0] != '\0') {
			const char *type = strtok_r(NULL, " \t", &tok_save);

			if (type != NULL && strcmp(type, "list") == 0)
				type = strtok_r(NULL, " \t", &tok_save); /* the count's type */
			/* A list may be empty: only its count is certain to be there. */
			e.min_bytes += binary ? scalar_size(type != NULL ? type : "") : 2;
		}
	}
	if (st == RS_OK)
		st = check_element(path, &e, body, &need, err);
done:
	free(buf);
	return st;
}
