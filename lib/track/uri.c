/* Shared pieces of device URI parsing (the hid: and usb: backends both take VID:PID). */
#include <string.h>

#include "raystream/rs_track.h"

static int hex16(const char *s, size_t n, uint16_t *out)
{
	if (n == 0 || n > 4)
		return 0;
	unsigned v = 0;
	for (size_t i = 0; i < n; i++) {
		char c = s[i];
		unsigned d = c >= '0' && c <= '9'   ? (unsigned)(c - '0')
		             : c >= 'a' && c <= 'f' ? (unsigned)(c - 'a' + 10)
		             : c >= 'A' && c <= 'F' ? (unsigned)(c - 'A' + 10)
		                                    : 16u;
		if (d > 15)
			return 0;
		v = v * 16 + d;
	}
	*out = (uint16_t)v;
	return 1;
}

enum rs_status rs_track_parse_vid_pid(const char *text, uint16_t *out_vid, uint16_t *out_pid,
                                      const char **out_tail, struct rs_error *err)
{
	RS_ASSERT(text && out_vid && out_pid && out_tail);
	size_t a = strcspn(text, ":");
	const char *pid = text + a + 1;
	size_t b = text[a] == ':' ? strcspn(pid, ":") : 0;
	uint16_t vid_value, pid_value;
	if (text[a] != ':' || !hex16(text, a, &vid_value) || !hex16(pid, b, &pid_value))
		return rs_error_set(err, RS_ERR_PARSE, "expected VID:PID in hex, got '%.60s'",
		                    text);
	*out_vid = vid_value;
	*out_pid = pid_value;
	*out_tail = pid + b;
	return RS_OK;
}
