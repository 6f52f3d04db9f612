/*
 * Replay files: the recorder writes a header and (host time, protocol frame) records;
 * the replay source reads them back through the parser, so a damaged file is counted
 * like a noisy line. Files without the header are read as raw frame dumps.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "raystream/rs_track.h"

#define MAGIC "RSTRKREC"
#define HEADER_SIZE 16
#define RECORD_SIZE (8 + RS_PROTO_FRAME_SIZE)
#define RAW_CHUNK 4096

struct rs_track_recorder {
	FILE *f;
	char path[256];
};

static void put_le(uint8_t *p, uint64_t v, int n)
{
	for (int i = 0; i < n; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

static uint64_t get_le(const uint8_t *p, int n)
{
	uint64_t v = 0;
	for (int i = n - 1; i >= 0; i--)
		v = v << 8 | p[i];
	return v;
}

enum rs_status rs_track_recorder_create(const char *path, struct rs_track_recorder **out,
                                        struct rs_error *err)
{
	RS_ASSERT(path && out);
	*out = NULL;
	struct rs_track_recorder *r = calloc(1, sizeof *r);
	if (!r)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "record: out of memory");
	r->f = fopen(path, "wb");
	if (!r->f) {
		enum rs_status st = rs_error_set(err, RS_ERR_IO, "record: cannot create %s: %s",
		                                 path, strerror(errno));
		free(r);
		return st;
	}
	snprintf(r->path, sizeof r->path, "%s", path);
	uint8_t h[HEADER_SIZE];
	memcpy(h, MAGIC, 8);
	put_le(h + 8, 1, 4);                    /* file format version */
	put_le(h + 12, RS_PROTO_FRAME_SIZE, 4); /* record payload size */
	if (fwrite(h, 1, sizeof h, r->f) != sizeof h) {
		fclose(r->f);
		free(r);
		return rs_error_set(err, RS_ERR_IO, "record: cannot write %s", path);
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
	put_le(rec, bits, 8);
	if (fwrite(rec, 1, sizeof rec, r->f) != sizeof rec)
		return rs_error_set(err, RS_ERR_IO, "record: cannot write %s", r->path);
	return RS_OK;
}

enum rs_status rs_track_recorder_destroy(struct rs_track_recorder **rec, struct rs_error *err)
{
	if (!rec || !*rec)
		return RS_OK;
	struct rs_track_recorder *r = *rec;
	enum rs_status st = RS_OK;
	if (fclose(r->f) != 0)
		st = rs_error_set(err, RS_ERR_IO, "record: cannot finish %s", r->path);
	free(r);
	*rec = NULL;
	return st;
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
	if (!r->raw && (get_le(h + 8, 4) != 1 || get_le(h + 12, 4) != RS_PROTO_FRAME_SIZE))
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

/* Next sample in file order, ignoring pacing. */
static enum rs_status replay_next(struct replay *r, struct rs_marker_sample *out,
                                  struct rs_error *err)
{
	for (;;) {
		const uint8_t *p = r->chunk + r->pos;
		size_t n = r->len - r->pos;
		int got = rs_proto_parser_feed(&r->parser, &p, &n, out);
		r->pos = r->len - n;
		if (got) {
			out->host_time_s =
			    r->raw ? (double)out->device_time_us * 1e-6 : r->chunk_time;
			return RS_OK;
		}
		r->pos = r->len = 0;
		if (r->raw) {
			r->len = fread(r->chunk, 1, sizeof r->chunk, r->f);
		} else {
			uint8_t rec[RECORD_SIZE];
			size_t got_n = fread(rec, 1, sizeof rec, r->f);
			if (got_n == sizeof rec) {
				uint64_t bits = get_le(rec, 8);
				memcpy(&r->chunk_time, &bits, sizeof bits);
				memcpy(r->chunk, rec + 8, RS_PROTO_FRAME_SIZE);
				r->len = RS_PROTO_FRAME_SIZE;
			}
		}
		if (r->len == 0) {
			if (ferror(r->f))
				return rs_error_set(err, RS_ERR_IO, "replay: %s: read error",
				                    r->path);
			return rs_error_set(err, RS_END, "replay: end of %s", r->path);
		}
	}
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
			double t = timeout_ms * 1e-3;
			struct timespec ts = {(time_t)t, (long)((t - (double)(time_t)t) * 1e9)};
			nanosleep(&ts, NULL);
			return rs_error_set(err, RS_TIMEOUT, "replay: next sample not due yet");
		}
		struct timespec ts = {(time_t)wait, (long)((wait - (double)(time_t)wait) * 1e9)};
		nanosleep(&ts, NULL);
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
	RS_ASSERT(out_source);
	*out_source = NULL;
	if (!path || !path[0])
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
	if (st != RS_OK) {
		replay_destroy(r);
		return st;
	}
	return rs_track_source_create(&replay_ops, r, out_source, err);
}
