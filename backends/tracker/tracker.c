/*
 * URI dispatch over the tracker backends compiled into this build.
 */
#include <string.h>

#include "raystream/rs_tracker.h"
#ifdef RS_TRACKER_HAVE_SERIAL
#include "raystream/rs_serial.h"
#endif
#ifdef RS_TRACKER_HAVE_HID
#include "raystream/rs_hid.h"
#endif
#ifdef RS_TRACKER_HAVE_USB
#include "raystream/rs_usb.h"
#endif
#ifdef RS_TRACKER_HAVE_OPTICAL
#include "raystream/rs_optical.h"
#endif

#define PATH_CAP 512

bool rs_tracker_has_scheme(const char *scheme)
{
	if (!scheme)
		return false;
	if (!strcmp(scheme, "sim") || !strcmp(scheme, "replay"))
		return true;
#ifdef RS_TRACKER_HAVE_SERIAL
	if (!strcmp(scheme, "serial"))
		return true;
#endif
#ifdef RS_TRACKER_HAVE_HID
	if (!strcmp(scheme, "hid"))
		return true;
#endif
#ifdef RS_TRACKER_HAVE_USB
	if (!strcmp(scheme, "usb"))
		return true;
#endif
#ifdef RS_TRACKER_HAVE_OPTICAL
	if (!strcmp(scheme, "video") || !strcmp(scheme, "cam"))
		return true;
#endif
	return false;
}

/* replay:FILE[?realtime=0|1]: everything after the first '?' is options, as in serial:. */
static enum rs_status open_replay(const char *rest, struct rs_track_source **out,
                                  struct rs_error *err)
{
	char path[PATH_CAP];
	size_t n = strcspn(rest, "?");
	struct rs_track_replay_desc d = {0};
	if (n == 0)
		return rs_error_set(err, RS_ERR_PARSE, "replay: expected replay:FILE[?realtime=1]");
	if (n >= sizeof path)
		return rs_error_set(err, RS_ERR_PARSE, "replay: file name too long");
	memcpy(path, rest, n);
	path[n] = '\0';
	for (const char *q = rest + n; *q;) {
		q++; /* '?' or '&' */
		size_t len = strcspn(q, "&");
		if (len == 10 && !strncmp(q, "realtime=0", 10))
			d.realtime = 0;
		else if (len == 10 && !strncmp(q, "realtime=1", 10))
			d.realtime = 1;
		else
			return rs_error_set(err, RS_ERR_PARSE,
			                    "replay: unknown option '%.*s' (realtime=0|1)",
			                    (int)(len > 40 ? 40 : len), q);
		q += len;
	}
	return rs_track_replay_open(path, &d, out, err);
}

static enum rs_status open_sim(const char *rest, struct rs_track_source **out, struct rs_error *err)
{
	char script[PATH_CAP];
	struct rs_track_sim_source_desc d;
	enum rs_status st = rs_track_sim_parse_params(rest, &d, script, sizeof script, err);
	if (st != RS_OK)
		return st;
	st = rs_track_sim_open(&d, out, err);
	/* Every simulator option came from the URI text: a bad one is a malformed URI. */
	if (st == RS_ERR_INVALID && err)
		err->status = RS_ERR_PARSE;
	return st == RS_ERR_INVALID ? RS_ERR_PARSE : st;
}

enum rs_status rs_tracker_open(const char *uri, struct rs_track_source **out, struct rs_error *err)
{
	RS_ASSERT(uri && out);
	*out = NULL;
	size_t sl = strcspn(uri, ":");
	if (!uri[sl] || sl == 0 || sl > 16)
		return rs_error_set(
		    err, RS_ERR_PARSE,
		    "tracker: '%.60s' is not a source URI (hid:, usb:, serial:, sim:, "
		    "replay:, video:, cam:)",
		    uri);
	char scheme[17];
	memcpy(scheme, uri, sl);
	scheme[sl] = '\0';
	const char *rest = uri + sl + 1;
	if (!strcmp(scheme, "sim"))
		return open_sim(rest, out, err);
	if (!strcmp(scheme, "replay"))
		return open_replay(rest, out, err);
	if (!strcmp(scheme, "serial")) {
#ifdef RS_TRACKER_HAVE_SERIAL
		char path[PATH_CAP];
		struct rs_serial_desc d;
		enum rs_status st = rs_serial_parse_uri(rest, path, sizeof path, &d, err);
		return st != RS_OK ? st : rs_serial_open(&d, out, err);
#else
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "tracker: serial backend not built");
#endif
	}
	if (!strcmp(scheme, "hid")) {
#ifdef RS_TRACKER_HAVE_HID
		char serial[128];
		struct rs_hid_desc d;
		enum rs_status st = rs_hid_parse_uri(rest, &d, serial, sizeof serial, err);
		return st != RS_OK ? st : rs_hid_open(&d, out, err);
#else
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "tracker: hid backend not built");
#endif
	}
	if (!strcmp(scheme, "usb")) {
#ifdef RS_TRACKER_HAVE_USB
		struct rs_usb_desc d;
		enum rs_status st = rs_usb_parse_uri(rest, &d, err);
		return st != RS_OK ? st : rs_usb_open(&d, out, err);
#else
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "tracker: usb backend not built");
#endif
	}
	if (!strcmp(scheme, "video") || !strcmp(scheme, "cam")) {
#ifdef RS_TRACKER_HAVE_OPTICAL
		return rs_optical_open_uri(scheme, rest, out, err);
#else
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "tracker: opencv backend not built");
#endif
	}
	return rs_error_set(err, RS_ERR_PARSE,
	                    "tracker: unknown scheme '%s' (hid, usb, serial, sim, replay, video, "
	                    "cam)",
	                    scheme);
}
