/*
 * A check in front of assimp's OBJ reader: it drops a face line with fewer than three
 * vertices (a file cut off mid-line) and a vertex line with fewer than three coordinates
 * without a word, so a truncated file renders as less than it is. Here such a line is
 * refused by element and line number. Only 'v' and 'f' lines are judged; the rest is
 * assimp's.
 */
#include <stdbool.h>
#include <string.h>
#include <strings.h>

#include "load_internal.h"

static bool blank(unsigned char c)
{
	return c == ' ' || c == '\t' || c == '\r';
}

/* Whitespace-separated words from p to the end of its line (a '\' before the newline
 * continues the line, as OBJ allows); *p is left after the newline. */
static unsigned count_words(const unsigned char **p, const unsigned char *end, size_t *line)
{
	unsigned n = 0;
	const unsigned char *q = *p;
	while (q < end && *q != '\n') {
		if (*q == '\\' && q + 1 < end && (q[1] == '\n' || q[1] == '\r')) {
			q += q[1] == '\r' && q + 2 < end && q[2] == '\n' ? 3 : 2;
			++*line;
			continue;
		}
		if (blank(*q)) {
			q++;
			continue;
		}
		n++;
		while (q < end && !blank(*q) && *q != '\n')
			q++;
	}
	*p = q < end ? q + 1 : q;
	return n;
}

static enum rs_status check_text(const unsigned char *p, const unsigned char *end, const char *path,
                                 struct rs_error *err)
{
	for (size_t line = 1; p < end; ++line) {
		while (p < end && blank(*p))
			p++;
		size_t at = line;
		bool vertex = end - p > 1 && p[0] == 'v' && blank(p[1]);
		bool face = end - p > 1 && p[0] == 'f' && blank(p[1]);
		unsigned words = count_words(&p, end, &line);
		if (vertex && words < 4)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "%s: line %zu: vertex with %u coordinates (needs 3)",
			                    path, at, words - 1);
		if (face && words < 4)
			return rs_error_set(
			    err, RS_ERR_PARSE,
			    "%s: line %zu: face with %u vertices (needs at least 3)", path, at,
			    words - 1);
	}
	return RS_OK;
}

enum rs_status rs_obj_check_body(const char *path, struct rs_error *err)
{
	RS_ASSERT(path);
	const char *dot = strrchr(path, '.');
	if (!dot || strcasecmp(dot, ".obj") != 0)
		return RS_OK;
	const unsigned char *bytes;
	size_t size;
	enum rs_status status = rs_load_map_file(path, &bytes, &size, err);
	if (status == RS_OK && bytes)
		status = check_text(bytes, bytes + size, path, err);
	rs_load_unmap_file(bytes, size);
	return status;
}
