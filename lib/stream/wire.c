/* Message bodies on the wire (docs/stream-protocol.md): one validator per type, shared by
 * the encoder and the parser so that everything encoded parses and vice versa. */
#include <math.h>
#include <stdio.h>

#include "stream_internal.h"

#define HELLO_FIXED 8u
#define WELCOME_SIZE 12u
#define POSE_SIZE 112u
#define STATS_SIZE 32u
#define BYE_FIXED 8u

const char *rs_stream_type_name(uint32_t type)
{
	static const char *names[] = {"UNKNOWN", "HELLO", "WELCOME", "POSE",
	                              "FRAME",   "STATS", "BYE"};
	return type >= 1 && type <= 6 ? names[type] : names[0];
}

uint32_t rs_stream_max_payload(uint32_t type)
{
	switch (type) {
	case RS_STREAM_HELLO:
		return HELLO_FIXED + RS_STREAM_MAX_TOKEN + RS_STREAM_MAX_SCENE;
	case RS_STREAM_WELCOME:
		return WELCOME_SIZE;
	case RS_STREAM_POSE:
		return POSE_SIZE;
	case RS_STREAM_FRAME:
		return RS_STREAM_FRAME_FIXED + RS_STREAM_MAX_SIDE * RS_STREAM_MAX_SIDE * 4u;
	case RS_STREAM_STATS:
		return STATS_SIZE;
	case RS_STREAM_BYE:
		return BYE_FIXED + RS_STREAM_MAX_TEXT;
	}
	return 0;
}

static int printable(const char *s, size_t n)
{
	for (size_t i = 0; i < n; ++i)
		if (s[i] < 0x20 || s[i] > 0x7e)
			return 0;
	return 1;
}

static int side_ok(uint32_t w, uint32_t h)
{
	return w >= 1 && h >= 1 && w <= RS_STREAM_MAX_SIDE && h <= RS_STREAM_MAX_SIDE;
}

static enum rs_status validate(const struct rs_stream_msg *m, struct rs_error *err)
{
	const char *name = rs_stream_type_name(m->type);
	switch (m->type) {
	case RS_STREAM_HELLO: {
		const struct rs_stream_hello *h = &m->u.hello;
		size_t tl = strnlen(h->token, sizeof h->token),
		       sl = strnlen(h->scene, sizeof h->scene);
		if (!side_ok(h->width, h->height) || h->quality > 100)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "HELLO: size %ux%u or quality %u out of range",
			                    h->width, h->height, h->quality);
		if (tl > RS_STREAM_MAX_TOKEN || sl > RS_STREAM_MAX_SCENE ||
		    !printable(h->token, tl) || !printable(h->scene, sl))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "HELLO: token or scene not printable ASCII");
		return RS_OK;
	}
	case RS_STREAM_WELCOME: {
		const struct rs_stream_welcome *w = &m->u.welcome;
		if (!side_ok(w->width, w->height) || w->quality > 100 ||
		    (w->encoding != RS_STREAM_ENC_JPEG && w->encoding != RS_STREAM_ENC_RGBA8))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "WELCOME: size, quality or encoding out of range");
		return RS_OK;
	}
	case RS_STREAM_POSE: {
		const struct rs_stream_pose *p = &m->u.pose;
		const double *v[5] = {p->eye, p->target, p->up, &p->fov_y_deg, p->shift};
		const int n[5] = {3, 3, 3, 1, 2};
		for (int i = 0; i < 5; ++i)
			for (int k = 0; k < n[i]; ++k)
				if (!isfinite(v[i][k]) || fabs(v[i][k]) > 1e12)
					return rs_error_set(err, RS_ERR_BAD_DATA,
					                    "POSE %u: non-finite or huge value",
					                    p->pose_id);
		if (!(p->fov_y_deg > 0.0 && p->fov_y_deg < 180.0))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "POSE %u: fov %g outside (0, 180)", p->pose_id,
			                    p->fov_y_deg);
		return RS_OK;
	}
	case RS_STREAM_FRAME: {
		const struct rs_stream_frame *f = &m->u.frame;
		if (!side_ok(f->width, f->height) || f->size == 0)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "FRAME %u: size %ux%u or empty image", f->frame_id,
			                    f->width, f->height);
		if (f->encoding == RS_STREAM_ENC_RGBA8 &&
		    f->size != (uint32_t)f->width * f->height * 4u)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "FRAME %u: raw image of %u bytes for %ux%u",
			                    f->frame_id, f->size, f->width, f->height);
		if (f->encoding != RS_STREAM_ENC_JPEG && f->encoding != RS_STREAM_ENC_RGBA8)
			return rs_error_set(err, RS_ERR_BAD_DATA, "FRAME %u: unknown encoding %u",
			                    f->frame_id, f->encoding);
		return RS_OK;
	}
	case RS_STREAM_STATS: {
		const struct rs_stream_stats *s = &m->u.stats;
		const float v[4] = {s->fps, s->latency_median_ms, s->latency_p99_ms, s->link_mbps};
		for (int i = 0; i < 4; ++i)
			if (!isfinite(v[i]) || v[i] < 0.0f)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "STATS: negative or non-finite figure");
		return RS_OK;
	}
	case RS_STREAM_BYE: {
		size_t tl = strnlen(m->u.bye.text, sizeof m->u.bye.text);
		if (tl > RS_STREAM_MAX_TEXT || !printable(m->u.bye.text, tl))
			return rs_error_set(err, RS_ERR_BAD_DATA, "BYE: text not printable ASCII");
		return RS_OK;
	}
	}
	return rs_error_set(err, RS_ERR_BAD_DATA, "%s: unknown message type %d", name,
	                    (int)m->type);
}

static uint32_t body_size(const struct rs_stream_msg *m)
{
	switch (m->type) {
	case RS_STREAM_HELLO:
		return HELLO_FIXED + (uint32_t)strnlen(m->u.hello.token, RS_STREAM_MAX_TOKEN + 1) +
		       (uint32_t)strnlen(m->u.hello.scene, RS_STREAM_MAX_SCENE + 1);
	case RS_STREAM_WELCOME:
		return WELCOME_SIZE;
	case RS_STREAM_POSE:
		return POSE_SIZE;
	case RS_STREAM_FRAME:
		return RS_STREAM_FRAME_FIXED + m->u.frame.size;
	case RS_STREAM_STATS:
		return STATS_SIZE;
	case RS_STREAM_BYE:
		return BYE_FIXED + (uint32_t)strnlen(m->u.bye.text, RS_STREAM_MAX_TEXT + 1);
	}
	return 0;
}

size_t rs_stream_encoded_size(const struct rs_stream_msg *msg)
{
	RS_ASSERT(msg);
	return RS_STREAM_HEADER_SIZE + (size_t)body_size(msg);
}

static void put_f64(uint8_t *p, double v)
{
	uint64_t u;
	memcpy(&u, &v, sizeof u);
	rs_le_put64(p, u);
}
static double get_f64(const uint8_t *p)
{
	uint64_t u = rs_le_get64(p);
	double v;
	memcpy(&v, &u, sizeof v);
	return v;
}
static void put_f32(uint8_t *p, float v)
{
	uint32_t u;
	memcpy(&u, &v, sizeof u);
	rs_le_put32(p, u);
}
static float get_f32(const uint8_t *p)
{
	uint32_t u = rs_le_get32(p);
	float v;
	memcpy(&v, &u, sizeof v);
	return v;
}

/* The 12 doubles of a pose, in wire order. */
static void pose_fields(struct rs_stream_pose *p, double *f[12])
{
	for (int k = 0; k < 3; ++k) {
		f[k] = &p->eye[k];
		f[3 + k] = &p->target[k];
		f[6 + k] = &p->up[k];
	}
	f[9] = &p->fov_y_deg;
	f[10] = &p->shift[0];
	f[11] = &p->shift[1];
}

enum rs_status rs_stream_encode(const struct rs_stream_msg *msg, uint8_t *out, size_t cap,
                                size_t *out_size, struct rs_error *err)
{
	RS_ASSERT(msg && out_size && (out || cap == 0));
	*out_size = 0;
	enum rs_status st = validate(msg, err);
	if (st != RS_OK)
		return st;
	uint32_t n = body_size(msg);
	if ((size_t)n + RS_STREAM_HEADER_SIZE > cap || n > rs_stream_max_payload(msg->type))
		return rs_error_set(err, RS_ERR_LIMIT, "%s: %u bytes do not fit %zu",
		                    rs_stream_type_name(msg->type), n + RS_STREAM_HEADER_SIZE, cap);
	out[0] = 'R';
	out[1] = 'S';
	out[2] = RS_STREAM_VERSION;
	out[3] = (uint8_t)msg->type;
	rs_le_put32(out + 4, n);
	uint8_t *b = out + RS_STREAM_HEADER_SIZE;
	memset(b, 0, n);
	const struct rs_stream_msg *u = msg;
	switch (msg->type) {
	case RS_STREAM_HELLO: {
		size_t tl = strlen(u->u.hello.token), sl = strlen(u->u.hello.scene);
		rs_le_put16(b, u->u.hello.width);
		rs_le_put16(b + 2, u->u.hello.height);
		b[4] = u->u.hello.quality;
		b[5] = (uint8_t)tl;
		b[6] = (uint8_t)sl;
		memcpy(b + HELLO_FIXED, u->u.hello.token, tl);
		memcpy(b + HELLO_FIXED + tl, u->u.hello.scene, sl);
		break;
	}
	case RS_STREAM_WELCOME:
		rs_le_put32(b, u->u.welcome.viewer_id);
		rs_le_put16(b + 4, u->u.welcome.width);
		rs_le_put16(b + 6, u->u.welcome.height);
		b[8] = u->u.welcome.quality;
		b[9] = u->u.welcome.encoding;
		break;
	case RS_STREAM_POSE: {
		struct rs_stream_pose p = u->u.pose;
		double *f[12];
		pose_fields(&p, f);
		rs_le_put32(b, p.pose_id);
		rs_le_put32(b + 4, p.flags);
		rs_le_put64(b + 8, p.time_us);
		for (int k = 0; k < 12; ++k)
			put_f64(b + 16 + 8 * k, *f[k]);
		break;
	}
	case RS_STREAM_FRAME:
		rs_le_put32(b, u->u.frame.frame_id);
		rs_le_put32(b + 4, u->u.frame.pose_id);
		rs_le_put64(b + 8, u->u.frame.pose_time_us);
		rs_le_put16(b + 16, u->u.frame.width);
		rs_le_put16(b + 18, u->u.frame.height);
		b[20] = u->u.frame.encoding;
		rs_le_put16(b + 22, u->u.frame.samples);
		rs_le_put32(b + 24, u->u.frame.render_us);
		rs_le_put32(b + 28, u->u.frame.encode_us);
		memcpy(b + RS_STREAM_FRAME_FIXED, u->u.frame.data, u->u.frame.size);
		break;
	case RS_STREAM_STATS:
		rs_le_put32(b, u->u.stats.frames);
		rs_le_put32(b + 4, u->u.stats.dropped);
		rs_le_put64(b + 8, u->u.stats.bytes);
		put_f32(b + 16, u->u.stats.fps);
		put_f32(b + 20, u->u.stats.latency_median_ms);
		put_f32(b + 24, u->u.stats.latency_p99_ms);
		put_f32(b + 28, u->u.stats.link_mbps);
		break;
	case RS_STREAM_BYE: {
		size_t tl = strlen(u->u.bye.text);
		rs_le_put32(b, u->u.bye.reason);
		b[4] = (uint8_t)tl;
		memcpy(b + BYE_FIXED, u->u.bye.text, tl);
		break;
	}
	}
	*out_size = RS_STREAM_HEADER_SIZE + (size_t)n;
	return RS_OK;
}

static enum rs_status bad_length(uint32_t type, uint32_t length, struct rs_error *err)
{
	return rs_error_set(err, RS_ERR_PARSE, "%s: length %u does not fit its layout",
	                    rs_stream_type_name(type), length);
}

enum rs_status rs_stream_decode_body(uint32_t type, const uint8_t *b, uint32_t length,
                                     struct rs_stream_msg *out, struct rs_error *err)
{
	struct rs_stream_msg m;
	memset(&m, 0, sizeof m);
	m.type = (enum rs_stream_type)type;
	switch (type) {
	case RS_STREAM_HELLO: {
		if (length < HELLO_FIXED || length != HELLO_FIXED + (uint32_t)b[5] + b[6])
			return bad_length(type, length, err);
		if (b[5] > RS_STREAM_MAX_TOKEN || b[6] > RS_STREAM_MAX_SCENE)
			return rs_error_set(err, RS_ERR_BAD_DATA, "HELLO: token or scene too long");
		m.u.hello.width = rs_le_get16(b);
		m.u.hello.height = rs_le_get16(b + 2);
		m.u.hello.quality = b[4];
		memcpy(m.u.hello.token, b + HELLO_FIXED, b[5]);
		memcpy(m.u.hello.scene, b + HELLO_FIXED + b[5], b[6]);
		/* an embedded NUL would shorten the string: not printable, refused */
		if (strlen(m.u.hello.token) != b[5] || strlen(m.u.hello.scene) != b[6])
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "HELLO: NUL inside token or scene");
		break;
	}
	case RS_STREAM_WELCOME:
		if (length != WELCOME_SIZE)
			return bad_length(type, length, err);
		m.u.welcome.viewer_id = rs_le_get32(b);
		m.u.welcome.width = rs_le_get16(b + 4);
		m.u.welcome.height = rs_le_get16(b + 6);
		m.u.welcome.quality = b[8];
		m.u.welcome.encoding = b[9];
		break;
	case RS_STREAM_POSE: {
		if (length != POSE_SIZE)
			return bad_length(type, length, err);
		double *f[12];
		pose_fields(&m.u.pose, f);
		m.u.pose.pose_id = rs_le_get32(b);
		m.u.pose.flags = rs_le_get32(b + 4);
		m.u.pose.time_us = rs_le_get64(b + 8);
		for (int k = 0; k < 12; ++k)
			*f[k] = get_f64(b + 16 + 8 * k);
		break;
	}
	case RS_STREAM_FRAME:
		if (length <= RS_STREAM_FRAME_FIXED)
			return bad_length(type, length, err);
		m.u.frame.frame_id = rs_le_get32(b);
		m.u.frame.pose_id = rs_le_get32(b + 4);
		m.u.frame.pose_time_us = rs_le_get64(b + 8);
		m.u.frame.width = rs_le_get16(b + 16);
		m.u.frame.height = rs_le_get16(b + 18);
		m.u.frame.encoding = b[20];
		m.u.frame.samples = rs_le_get16(b + 22);
		m.u.frame.render_us = rs_le_get32(b + 24);
		m.u.frame.encode_us = rs_le_get32(b + 28);
		m.u.frame.data = b + RS_STREAM_FRAME_FIXED;
		m.u.frame.size = length - RS_STREAM_FRAME_FIXED;
		break;
	case RS_STREAM_STATS:
		if (length != STATS_SIZE)
			return bad_length(type, length, err);
		m.u.stats.frames = rs_le_get32(b);
		m.u.stats.dropped = rs_le_get32(b + 4);
		m.u.stats.bytes = rs_le_get64(b + 8);
		m.u.stats.fps = get_f32(b + 16);
		m.u.stats.latency_median_ms = get_f32(b + 20);
		m.u.stats.latency_p99_ms = get_f32(b + 24);
		m.u.stats.link_mbps = get_f32(b + 28);
		break;
	case RS_STREAM_BYE:
		if (length < BYE_FIXED || length != BYE_FIXED + (uint32_t)b[4])
			return bad_length(type, length, err);
		if (b[4] > RS_STREAM_MAX_TEXT)
			return rs_error_set(err, RS_ERR_BAD_DATA, "BYE: text too long");
		m.u.bye.reason = rs_le_get32(b);
		memcpy(m.u.bye.text, b + BYE_FIXED, b[4]);
		if (strlen(m.u.bye.text) != b[4])
			return rs_error_set(err, RS_ERR_BAD_DATA, "BYE: NUL inside text");
		break;
	default:
		return rs_error_set(err, RS_ERR_PARSE, "unknown message type %u", type);
	}
	enum rs_status st = validate(&m, err);
	if (st != RS_OK)
		return st;
	*out = m;
	return RS_OK;
}
