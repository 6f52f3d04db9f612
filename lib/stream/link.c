/* Link emulation: a token bucket for the bandwidth of a link such as the paper's 802.11g
 * (about 25 Mbit/s); the one-way delay is a ready time the sender keeps per message. */
#include <math.h>

#include "raystream/rs_stream.h"

enum rs_status rs_stream_link_init(struct rs_stream_link *link,
                                   const struct rs_stream_link_desc *desc, struct rs_error *err)
{
	RS_ASSERT(link);
	struct rs_stream_link_desc d = {0};
	if (desc)
		d = *desc;
	if (!isfinite(d.rate_bits_per_s) || d.rate_bits_per_s < 0.0 || !isfinite(d.latency_s) ||
	    d.latency_s < 0.0)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "link: rate and latency must be finite, >= 0");
	if (d.burst_bytes == 0) {
		/* 10 ms of rate: a sender woken late by a busy machine does not lose tokens it
		 * was owed, so the long-run rate holds; short bursts stay small */
		double ten_ms = d.rate_bits_per_s / 8.0 * 0.01;
		d.burst_bytes = ten_ms > 1500.0 ? (size_t)ten_ms : 1500u;
	}
	*link = (struct rs_stream_link){.desc = d};
	return RS_OK;
}

static void refill(struct rs_stream_link *l, double now_s)
{
	if (!l->started) {
		l->started = 1;
		l->tokens = (double)l->desc.burst_bytes;
		l->last_s = now_s;
		return;
	}
	double dt = now_s - l->last_s;
	if (dt > 0.0) {
		l->tokens += dt * l->desc.rate_bits_per_s / 8.0;
		if (l->tokens > (double)l->desc.burst_bytes)
			l->tokens = (double)l->desc.burst_bytes;
		l->last_s = now_s;
	}
}

size_t rs_stream_link_allow(struct rs_stream_link *link, double now_s, size_t want)
{
	RS_ASSERT(link);
	if (link->desc.rate_bits_per_s == 0.0)
		return want;
	refill(link, now_s);
	double t = floor(link->tokens);
	return t <= 0.0 ? 0 : (double)want < t ? want : (size_t)t;
}

void rs_stream_link_spend(struct rs_stream_link *link, size_t sent)
{
	RS_ASSERT(link);
	if (link->desc.rate_bits_per_s > 0.0)
		link->tokens -= (double)sent;
}

double rs_stream_link_wait_s(struct rs_stream_link *link, double now_s, size_t want)
{
	RS_ASSERT(link);
	if (link->desc.rate_bits_per_s == 0.0)
		return 0.0;
	refill(link, now_s);
	double need = (double)(want < link->desc.burst_bytes ? want : link->desc.burst_bytes);
	if (link->tokens >= need)
		return 0.0;
	return (need - link->tokens) * 8.0 / link->desc.rate_bits_per_s;
}
