/* Strict number parsing (private/rs_parse.h): a value is the whole string or nothing. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "private/rs_parse.h"

bool rs_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out)
{
	/* strtoull accepts a sign and leading blanks ("-1" wraps to a huge number). */
	if (!text || *text < '0' || *text > '9')
		return false;
	char *end = NULL;
	int saved = errno; /* the library never leaves errno changed */
	errno = 0;
	unsigned long long v = strtoull(text, &end, 10);
	bool ok = errno == 0 && *end == '\0' && v >= min && v <= max;
	errno = saved;
	if (ok)
		*out = (uint32_t)v;
	return ok;
}

bool rs_parse_size(const char *text, uint32_t max, uint32_t *out_w, uint32_t *out_h)
{
	const char *x = text ? strchr(text, 'x') : NULL;
	if (!x || x == text || x - text > 10)
		return false;
	char w[16];
	memcpy(w, text, (size_t)(x - text));
	w[x - text] = '\0';
	uint32_t a, b;
	if (!rs_parse_u32(w, 1, max, &a) || !rs_parse_u32(x + 1, 1, max, &b))
		return false;
	*out_w = a;
	*out_h = b;
	return true;
}
