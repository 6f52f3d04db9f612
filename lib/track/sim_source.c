/*
 * The simulator as a tracker source ("sim:"): samples go through the wire encoding and
 * the parser, so a consumer sees exactly what a device speaking the protocol would send.
 */
#include <stdlib.h>
#include <time.h>

#include "raystream/rs_track.h"

struct sim_source {
	struct rs_sim *sim;
	struct rs_sim_desc desc; /* for reopen (script/layout pointers are not kept) */
	struct {
		char script[512];
		double layout[RS_TRACK_MARKERS][3];
		int has_layout;
	} copy;
	int realtime;
	double host_origin;
	int have_pending;
	struct rs_marker_sample pending;
	struct rs_proto_parser parser;
};

static void sleep_s(double s)
{
	if (!(s > 0))
		return;
	if (s > 1e6) /* keeps the timespec conversion in range */
		s = 1e6;
	struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
	nanosleep(&ts, NULL);
}

static enum rs_status sim_read(void *impl, struct rs_marker_sample *out, int timeout_ms,
                               struct rs_error *err)
{
	struct sim_source *s = impl;
	if (!s->have_pending) {
		struct rs_marker_sample raw;
		enum rs_status st = rs_sim_next(s->sim, &raw, NULL, NULL);
		if (st == RS_END)
			return rs_error_set(err, RS_END, "sim: end of the simulated run");
		if (st != RS_OK)
			return st;
		uint8_t frame[RS_PROTO_FRAME_SIZE];
		st = rs_proto_encode(&raw, frame, err);
		if (st != RS_OK)
			return st;
		const uint8_t *p = frame;
		size_t n = sizeof frame;
		if (!rs_proto_parser_feed(&s->parser, &p, &n, &s->pending))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "sim: frame rejected by the parser");
		s->pending.host_time_s = raw.host_time_s;
		s->have_pending = 1;
	}
	if (s->realtime) {
		double wait = s->host_origin + s->pending.host_time_s - rs_track_now_s();
		if (wait > 0 && timeout_ms >= 0 && wait > timeout_ms * 1e-3) {
			sleep_s(timeout_ms * 1e-3);
			return rs_error_set(err, RS_TIMEOUT, "sim: next sample not due yet");
		}
		if (wait > 0)
			sleep_s(wait);
		s->pending.host_time_s = rs_track_now_s();
	}
	*out = s->pending;
	s->have_pending = 0;
	return RS_OK;
}

static enum rs_status sim_start(struct sim_source *s, struct rs_error *err)
{
	struct rs_sim_desc d = s->desc;
	d.script = s->copy.script[0] ? s->copy.script : NULL;
	d.layout = s->copy.has_layout ? (const double(*)[3])s->copy.layout : NULL;
	rs_sim_destroy(&s->sim);
	enum rs_status st = rs_sim_create(&d, &s->sim, err);
	if (st != RS_OK)
		return st;
	rs_proto_parser_reset(&s->parser);
	s->have_pending = 0;
	s->host_origin = rs_track_now_s();
	return RS_OK;
}

static enum rs_status sim_reopen(void *impl, struct rs_error *err)
{
	return sim_start(impl, err);
}

static void sim_stats(const void *impl, struct rs_proto_stats *out)
{
	const struct sim_source *s = impl;
	*out = *rs_proto_parser_stats(&s->parser);
}

static void sim_destroy_impl(void *impl)
{
	struct sim_source *s = impl;
	if (!s)
		return;
	rs_sim_destroy(&s->sim);
	free(s);
}

static const struct rs_track_source_ops sim_ops = {
    .read = sim_read,
    .reopen = sim_reopen,
    .get_proto_stats = sim_stats,
    .destroy = sim_destroy_impl,
};

enum rs_status rs_track_sim_open(const struct rs_track_sim_source_desc *desc,
                                 struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(out_source);
	*out_source = NULL;
	struct sim_source *s = calloc(1, sizeof *s);
	if (!s)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "sim: out of memory");
	if (desc) {
		rs_sim_desc_resolve(&desc->sim, &s->desc);
		s->realtime = desc->realtime;
		if (desc->sim.script) {
			size_t n = 0;
			while (desc->sim.script[n] && n + 1 < sizeof s->copy.script)
				n++;
			if (desc->sim.script[n]) {
				free(s);
				return rs_error_set(err, RS_ERR_INVALID, "sim: script too long");
			}
			for (size_t i = 0; i <= n; i++)
				s->copy.script[i] = desc->sim.script[i];
		}
		if (desc->sim.layout) {
			s->copy.has_layout = 1;
			for (int m = 0; m < RS_TRACK_MARKERS; m++)
				for (int a = 0; a < 3; a++)
					s->copy.layout[m][a] = desc->sim.layout[m][a];
		}
	} else {
		rs_sim_desc_resolve(NULL, &s->desc);
	}
	rs_proto_parser_init(&s->parser);
	enum rs_status st = sim_start(s, err);
	if (st != RS_OK) {
		sim_destroy_impl(s);
		return st;
	}
	return rs_track_source_create(&sim_ops, s, out_source, err);
}
