/* The incremental stream parser: header hunt, bounds, then the body codec (wire.c). */
#include "stream_internal.h"

size_t rs_stream_parser_bound(size_t max_image)
{
	size_t most = (size_t)RS_STREAM_MAX_SIDE * RS_STREAM_MAX_SIDE * 4u;
	if (max_image > most)
		max_image = most;
	size_t frame = RS_STREAM_HEADER_SIZE + RS_STREAM_FRAME_FIXED + max_image;
	size_t other = RS_STREAM_HEADER_SIZE + RS_STREAM_MAX_CLIENT_PAYLOAD;
	return frame > other ? frame : other;
}

void rs_stream_parser_init(struct rs_stream_parser *parser, uint8_t *buf, size_t cap)
{
	RS_ASSERT(parser && buf && cap >= RS_STREAM_HEADER_SIZE);
	memset(parser, 0, sizeof *parser);
	parser->buf = buf;
	parser->cap = cap;
}

const struct rs_stream_faults *rs_stream_parser_faults(const struct rs_stream_parser *parser)
{
	RS_ASSERT(parser);
	return &parser->faults;
}

uint64_t rs_stream_faults_total(const struct rs_stream_faults *f)
{
	RS_ASSERT(f);
	return f->garbage_bytes + f->bad_version + f->unknown_type + f->oversized + f->bad_length +
	       f->bad_value;
}

static void drop_front(struct rs_stream_parser *p, size_t n)
{
	memmove(p->buf, p->buf + n, p->len - n);
	p->len -= n;
}

/* Keep the buffer starting at something that can still become 'R' 'S'. */
static void rescan(struct rs_stream_parser *p)
{
	size_t i = 0;
	while (i < p->len && !(p->buf[i] == 'R' && (i + 1 >= p->len || p->buf[i + 1] == 'S')))
		++i;
	p->faults.garbage_bytes += i;
	drop_front(p, i);
}

/* A header fault: its magic bytes go, the rest is searched for the next message. */
static enum rs_status header_fault(struct rs_stream_parser *p, uint64_t *counter, enum rs_status st,
                                   struct rs_error *err, const char *what, uint32_t value)
{
	++*counter;
	drop_front(p, 2);
	rescan(p);
	return rs_error_set(err, st, "stream: %s %u", what, value);
}

enum rs_status rs_stream_parser_feed(struct rs_stream_parser *p, const uint8_t **data, size_t *len,
                                     struct rs_stream_msg *out_msg, struct rs_error *err)
{
	RS_ASSERT(p && data && len && out_msg && (*data || *len == 0));
	for (;;) {
		if (p->len < RS_STREAM_HEADER_SIZE) {
			if (*len == 0)
				return RS_END;
			p->buf[p->len++] = **data;
			++*data;
			--*len;
			rescan(p);
			continue;
		}
		uint32_t version = p->buf[2], type = p->buf[3], length = rs_le_get32(p->buf + 4);
		if (version != RS_STREAM_VERSION)
			return header_fault(p, &p->faults.bad_version, RS_ERR_UNSUPPORTED, err,
			                    "unsupported protocol version", version);
		uint32_t most = rs_stream_max_payload(type);
		if (most == 0)
			return header_fault(p, &p->faults.unknown_type, RS_ERR_PARSE, err,
			                    "unknown message type", type);
		if (length > most || length > p->cap - RS_STREAM_HEADER_SIZE)
			return header_fault(p, &p->faults.oversized, RS_ERR_LIMIT, err,
			                    "oversized message, bytes:", length);
		size_t need = RS_STREAM_HEADER_SIZE + (size_t)length;
		if (p->len < need) {
			size_t take = need - p->len < *len ? need - p->len : *len;
			memcpy(p->buf + p->len, *data, take);
			p->len += take;
			*data += take;
			*len -= take;
			if (p->len < need)
				return RS_END;
		}
		/* The message is consumed whatever its body holds; a frame's data stays in the
		 * buffer until the next call. */
		p->len = 0;
		enum rs_status st = rs_stream_decode_body(type, p->buf + RS_STREAM_HEADER_SIZE,
		                                          length, out_msg, err);
		if (st == RS_ERR_PARSE)
			++p->faults.bad_length;
		else if (st != RS_OK)
			++p->faults.bad_value;
		else
			++p->faults.messages;
		return st;
	}
}
