/*
 * The generic tracker source (a function table plus bookkeeping) and the stream source
 * that turns any byte transport into samples through the protocol parser.
 */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_track.h"

struct rs_track_source {
	const struct rs_track_source_ops *ops;
	void *impl;
	struct rs_error err;
	uint64_t samples, disconnects, reopens;
	int disconnected;
};

double rs_track_now_s(void)
{
	return rs_now_ms() * 1e-3;
}

enum rs_status rs_track_source_create(const struct rs_track_source_ops *ops, void *impl,
                                      struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(ops && ops->read && ops->destroy && out_source);
	*out_source = NULL;
	struct rs_track_source *s = calloc(1, sizeof *s);
	if (!s) {
		ops->destroy(impl);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "track: out of memory");
	}
	s->ops = ops;
	s->impl = impl;
	*out_source = s;
	return RS_OK;
}

/* The source keeps its last error; the caller's record (if any) gets a copy. */
static enum rs_status report(const struct rs_track_source *s, enum rs_status st,
                             struct rs_error *err)
{
	if (err && st != RS_OK && st != RS_TIMEOUT)
		*err = s->err;
	return st;
}

enum rs_status rs_track_source_read(struct rs_track_source *s, struct rs_marker_sample *out,
                                    int timeout_ms, struct rs_error *err)
{
	RS_ASSERT(s && out);
	if (s->disconnected)
		return report(s,
		              rs_error_set(&s->err, RS_ERR_DISCONNECTED,
		                           "track: device disconnected; reopen the source"),
		              err);
	enum rs_status st = s->ops->read(s->impl, out, timeout_ms, &s->err);
	if (st == RS_OK) {
		s->samples++;
	} else if (st == RS_ERR_DISCONNECTED) {
		s->disconnected = 1;
		s->disconnects++;
	}
	return report(s, st, err);
}

enum rs_status rs_track_source_reopen(struct rs_track_source *s, struct rs_error *err)
{
	RS_ASSERT(s);
	if (!s->ops->reopen)
		return report(
		    s,
		    rs_error_set(&s->err, RS_ERR_UNSUPPORTED, "track: source cannot be reopened"),
		    err);
	enum rs_status st = s->ops->reopen(s->impl, &s->err);
	if (st == RS_OK) {
		s->disconnected = 0;
		s->reopens++;
		rs_error_clear(&s->err);
	}
	return report(s, st, err);
}

void rs_track_source_get_stats(const struct rs_track_source *s, struct rs_track_source_stats *out)
{
	RS_ASSERT(s && out);
	memset(out, 0, sizeof *out);
	if (s->ops->get_proto_stats)
		s->ops->get_proto_stats(s->impl, &out->proto);
	out->samples = s->samples;
	out->disconnects = s->disconnects;
	out->reopens = s->reopens;
}

const char *rs_track_source_last_error(const struct rs_track_source *s)
{
	return s ? s->err.message : "";
}

void rs_track_source_destroy(struct rs_track_source **s)
{
	if (!s || !*s)
		return;
	(*s)->ops->destroy((*s)->impl);
	free(*s);
	*s = NULL;
}

/* ---- Stream source ---------------------------------------------------------------------- */

#define STREAM_CHUNK 4096

struct stream {
	struct rs_track_transport transport;
	void *impl;
	struct rs_proto_parser parser;
	uint8_t chunk[STREAM_CHUNK];
	size_t pos, len;   /* unparsed bytes of chunk[] */
	double chunk_time; /* host time when chunk[] arrived */
};

static int remaining_ms(double deadline)
{
	double left = (deadline - rs_track_now_s()) * 1e3;
	return left <= 0 ? 0 : left >= INT_MAX - 1 ? INT_MAX : (int)(left + 0.999);
}

static enum rs_status stream_read(void *impl, struct rs_marker_sample *out, int timeout_ms,
                                  struct rs_error *err)
{
	struct stream *st = impl;
	double deadline = timeout_ms >= 0 ? rs_track_now_s() + timeout_ms * 1e-3 : 0;
	int first = 1;
	for (;;) {
		const uint8_t *p = st->chunk + st->pos;
		size_t n = st->len - st->pos;
		int got = rs_proto_parser_feed(&st->parser, &p, &n, out);
		st->pos = st->len - n;
		if (got) {
			out->host_time_s = st->chunk_time;
			return RS_OK;
		}
		int wait = timeout_ms < 0 ? -1 : remaining_ms(deadline);
		if (wait == 0 && !first)
			return rs_error_set(err, RS_TIMEOUT, "track: no sample within %d ms",
			                    timeout_ms);
		first = 0;
		size_t got_n = 0;
		enum rs_status s =
		    st->transport.read(st->impl, st->chunk, sizeof st->chunk, wait, &got_n, err);
		st->pos = st->len = 0;
		/* A transport may come back early with nothing (a tty read of 0 bytes after a
		 * spurious wake-up): keep waiting until the caller's deadline, or for ever. */
		if (s == RS_TIMEOUT)
			continue;
		if (s != RS_OK)
			return s;
		st->chunk_time = rs_track_now_s();
		st->len = got_n < sizeof st->chunk ? got_n : sizeof st->chunk;
	}
}

static enum rs_status stream_reopen(void *impl, struct rs_error *err)
{
	struct stream *st = impl;
	if (!st->transport.reopen)
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "track: transport cannot be reopened");
	enum rs_status s = st->transport.reopen(st->impl, err);
	if (s == RS_OK) {
		rs_proto_parser_reset(&st->parser);
		st->pos = st->len = 0;
	}
	return s;
}

static void stream_stats(const void *impl, struct rs_proto_stats *out)
{
	const struct stream *st = impl;
	*out = *rs_proto_parser_stats(&st->parser);
}

static void stream_destroy(void *impl)
{
	struct stream *st = impl;
	if (!st)
		return;
	st->transport.destroy(st->impl);
	free(st);
}

static const struct rs_track_source_ops stream_ops = {
    .read = stream_read,
    .reopen = stream_reopen,
    .get_proto_stats = stream_stats,
    .destroy = stream_destroy,
};

enum rs_status rs_track_stream_create(const struct rs_track_transport *transport, void *impl,
                                      struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(transport && transport->read && transport->destroy && out_source);
	*out_source = NULL;
	struct stream *st = calloc(1, sizeof *st);
	if (!st) {
		transport->destroy(impl);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "track: out of memory");
	}
	st->transport = *transport;
	st->impl = impl;
	rs_proto_parser_init(&st->parser);
	return rs_track_source_create(&stream_ops, st, out_source, err);
}
