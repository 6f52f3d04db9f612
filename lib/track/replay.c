/*
 * Replay files: the recorder writes a header and (host time, protocol frame) records;
 * the replay source reads them back through the parser, so a damaged file is counted
 * like a noisy line. Files without the header are read as raw frame dumps.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "raystream/rs_track.h"
#include "private/rs_atomic_file.h"
#include "private/rs_le.h"

#define MAGIC "RSTRKREC"
#define HEADER_SIZE 16
#define RECORD_SIZE (8 + RS_PROTO_FRAME_SIZE)
#define RAW_CHUNK 4096
/* Recorded host times beyond this (about 3000 years) are not CLOCK_MONOTONIC readings. */
#define MAX_TIME_S 1e11
/* Longest single sleep of realtime pacing; keeps the timespec conversion in range. */
#define MAX_SLEEP_S 1e6
/* Bytes one read may examine without finding a frame (see replay_next()). */
#define MAX_SCAN (1 << 20)

static void sleep_s(double s)
{
	if (!(s > 0))
		return;
	if (s > MAX_SLEEP_S)
		s = MAX_SLEEP_S;
	struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
	nanosleep(&ts, NULL);
}

/* The recording goes to a temporary file next to `path` and is renamed over it only when
 * the recorder is finished without a write error, so a failed run never leaves a partial
 * or half-overwritten file under the real name. */
struct rs_track_recorder {
	struct rs_atomic_file af;
};

enum rs_status rs_track_recorder_create(const char *path, struct rs_track_recorder **out,
                                        struct rs_error *err)
{
	RS_ASSERT(path && out);
	*out = NULL;
	if (!path[0])
		return rs_error_set(err, RS_ERR_INVALID, "record: empty file name");
	/* The finished file is renamed over `path`, which would replace a device node (as
	 * root, --record /dev/null), FIFO or symlink itself with a regular file: only a
	 * regular file (or nothing) is replaced. lstat, so a symlink is not followed. */
	struct stat sb;
	if (lstat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
		return rs_error_set(err, RS_ERR_IO, "record: cannot create %s: Is a directory",
		                    path);
	if (lstat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
		return rs_error_set(err, RS_ERR_IO, "record: cannot write %s: not a regular file",
		                    path);
	struct rs_track_recorder *r = calloc(1, sizeof *r);
	if (!r)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "record: out of memory");
	enum rs_status st = rs_atomic_open(&r->af, path, err);
	if (st != RS_OK) {
		free(r);
		return rs_error_prefix(err, st, "record");
	}
	uint8_t h[HEADER_SIZE];
	memcpy(h, MAGIC, 8);
	rs_le_put32(h + 8, 1);                    /* file format version */
	rs_le_put32(h + 12, RS_PROTO_FRAME_SIZE); /* record payload size */
	if (fwrite(h, 1, sizeof h, r->af.f) != sizeof h) {
		st = rs_error_set(err, RS_ERR_IO, "record: cannot write %s", path);
		rs_atomic_commit(&r->af, false, NULL);
		free(r);
		return st;
	}
	*out = r;
	return RS_OK;
}

enum rs_status rs_track_recorder_write(struct rs_track_recorder *r,
                                       const struct rs_marker_sample *sample, struct rs_error *err)
{
	RS_ASSERT(r && sample);
	uint8_t rec[RECORD_SIZE];
	enum rs_status st = rs_proto_encode(sample, rec + 8, err);
	if (st != RS_OK)
		return st;
	uint64_t bits;
	memcpy(&bits, &sample->host_time_s, sizeof bits);
	rs_le_put64(rec, bits);
	if (fwrite(rec, 1, sizeof rec, r->af.f) != sizeof rec)
		return rs_error_set(err, RS_ERR_IO, "record: cannot write %s", r->af.path);
	return RS_OK;
}

enum rs_status rs_track_recorder_destroy(struct rs_track_recorder **rec, struct rs_error *err)
{
	if (!rec || !*rec)
		return RS_OK;
	/* A write that failed earlier left ferror() set: the file is incomplete, dropped. */
	enum rs_status st = rs_atomic_commit(&(*rec)->af, true, err);
	free(*rec);
	*rec = NULL;
	return st == RS_OK ? RS_OK : rs_error_prefix(err, st, "record");
}

/* ---- Replay source ----------------------------------------------------------------------- */

struct replay {
	FILE *f;
	char path[256];
	int raw; /* no header: a plain dump of frames */
	int realtime;
	struct rs_proto_parser parser;
	uint8_t chunk[RAW_CHUNK];
	size_t pos, len;
	double chunk_time;
	int time_ok;      /* chunk_time is finite and sane */
	int have_pending; /* realtime: a parsed sample waiting for its time */
	struct rs_marker_sample pending;
	int have_origin;
	double rec_origin, host_origin;
};

static enum rs_status replay_rewind(struct replay *r, struct rs_error *err)
{
	uint8_t h[HEADER_SIZE];
	rewind(r->f);
	size_t n = fread(h, 1, sizeof h, r->f);
	r->raw = !(n == sizeof h && memcmp(h, MAGIC, 8) == 0);
	if (!r->raw && (rs_le_get32(h + 8) != 1 || rs_le_get32(h + 12) != RS_PROTO_FRAME_SIZE))
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "replay: %s: unsupported recording version", r->path);
	if (r->raw)
		rewind(r->f);
	rs_proto_parser_reset(&r->parser);
	r->pos = r->len = 0;
	r->have_pending = 0;
	r->have_origin = 0;
	return RS_OK;
}

/* Next sample in file order, ignoring pacing. At most MAX_SCAN bytes are examined per
 * call: an endless frameless input (replay:/dev/zero, a FIFO of noise) then reads as
 * RS_TIMEOUT, so callers keep control (timeouts, signals) instead of spinning inside. */
static enum rs_status replay_next(struct replay *r, struct rs_marker_sample *out,
                                  struct rs_error *err)
{
	size_t scanned = 0;
	for (;;) {
		const uint8_t *p = r->chunk + r->pos;
		size_t n = r->len - r->pos;
		int got = rs_proto_parser_feed(&r->parser, &p, &n, out);
		r->pos = r->len - n;
		if (got) {
			/* A damaged or hand-made file may hold a NaN/Inf/absurd host time: such a
			 * record falls back to its device time, as a raw dump does, so no
			 * non-finite time reaches the caller or the realtime pacing. */
			out->host_time_s = r->raw || !r->time_ok
			                       ? (double)out->device_time_us * 1e-6
			                       : r->chunk_time;
			return RS_OK;
		}
		r->pos = r->len = 0;
		if (scanned >= MAX_SCAN)
			return rs_error_set(err, RS_TIMEOUT, "replay: %s: no frame in %d bytes",
			                    r->path, MAX_SCAN);
		if (r->raw) {
			r->len = fread(r->chunk, 1, sizeof r->chunk, r->f);
		} else {
			uint8_t rec[RECORD_SIZE];
			size_t got_n = fread(rec, 1, sizeof rec, r->f);
			if (got_n == sizeof rec) {
				uint64_t bits = rs_le_get64(rec);
				memcpy(&r->chunk_time, &bits, sizeof bits);
				memcpy(r->chunk, rec + 8, RS_PROTO_FRAME_SIZE);
				r->len = RS_PROTO_FRAME_SIZE;
			}
			r->time_ok = isfinite(r->chunk_time) && fabs(r->chunk_time) <= MAX_TIME_S;
		}
		scanned += r->len;
		if (r->len == 0) {
			if (ferror(r->f))
				return rs_error_set(err, RS_ERR_IO, "replay: %s: read error",
				                    r->path);
			return rs_error_set(err, RS_END, "replay: end of %s", r->path);
		}
	}
}

/* A file without the recorder's header is read as a raw frame dump, so any file at all
 * would "replay" as zero samples and a clean end (replay:data/cow.obj). A regular file
 * must therefore show a frame within its first MAX_SCAN bytes; streams (a FIFO, a
 * device) cannot be looked at without consuming them and are taken as they come. */
static enum rs_status probe_raw_dump(struct replay *r, struct rs_error *err)
{
	struct stat sb;
	if (!r->raw || fstat(fileno(r->f), &sb) != 0 || !S_ISREG(sb.st_mode))
		return RS_OK;
	struct rs_marker_sample s;
	enum rs_status st = replay_next(r, &s, NULL);
	if (st == RS_ERR_IO)
		return rs_error_set(err, RS_ERR_IO, "replay: %s: read error", r->path);
	if (st != RS_OK)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "replay: %s is not a recording (no " MAGIC
		                    " header, no tracker frame in its first %d bytes)",
		                    r->path, MAX_SCAN);
	return replay_rewind(r, err);
}

static enum rs_status replay_read(void *impl, struct rs_marker_sample *out, int timeout_ms,
                                  struct rs_error *err)
{
	struct replay *r = impl;
	if (!r->realtime)
		return replay_next(r, out, err);
	if (!r->have_pending) {
		enum rs_status st = replay_next(r, &r->pending, err);
		if (st != RS_OK)
			return st;
		r->have_pending = 1;
	}
	double now = rs_track_now_s();
	if (!r->have_origin) {
		r->have_origin = 1;
		r->rec_origin = r->pending.host_time_s;
		r->host_origin = now;
	}
	double wait = r->host_origin + (r->pending.host_time_s - r->rec_origin) - now;
	if (wait > 0) {
		if (timeout_ms >= 0 && wait > timeout_ms * 1e-3) {
			sleep_s(timeout_ms * 1e-3);
			return rs_error_set(err, RS_TIMEOUT, "replay: next sample not due yet");
		}
		sleep_s(wait);
	}
	*out = r->pending;
	r->have_pending = 0;
	return RS_OK;
}

static enum rs_status replay_reopen(void *impl, struct rs_error *err)
{
	return replay_rewind(impl, err);
}

static void replay_stats(const void *impl, struct rs_proto_stats *out)
{
	const struct replay *r = impl;
	*out = *rs_proto_parser_stats(&r->parser);
}

static void replay_destroy(void *impl)
{
	struct replay *r = impl;
	if (!r)
		return;
	if (r->f)
		fclose(r->f);
	free(r);
}

static const struct rs_track_source_ops replay_ops = {
    .read = replay_read,
    .reopen = replay_reopen,
    .get_proto_stats = replay_stats,
    .destroy = replay_destroy,
};

enum rs_status rs_track_replay_open(const char *path, const struct rs_track_replay_desc *desc,
                                    struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(path && out_source);
	*out_source = NULL;
	if (!path[0])
		return rs_error_set(err, RS_ERR_INVALID, "replay: empty file name");
	struct replay *r = calloc(1, sizeof *r);
	if (!r)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "replay: out of memory");
	snprintf(r->path, sizeof r->path, "%s", path);
	r->realtime = desc ? desc->realtime : 0;
	rs_proto_parser_init(&r->parser);
	r->f = fopen(path, "rb");
	if (!r->f) {
		enum rs_status st =
		    rs_error_set(err, errno == ENOENT ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                 "replay: cannot open %s: %s", path, strerror(errno));
		free(r);
		return st;
	}
	enum rs_status st = replay_rewind(r, err);
	if (st == RS_OK)
		st = probe_raw_dump(r, err);
	if (st != RS_OK) {
		replay_destroy(r);
		return st;
	}
	return rs_track_source_create(&replay_ops, r, out_source, err);
}
