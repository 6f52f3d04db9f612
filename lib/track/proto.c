/*
 * Tracker wire protocol: frame encoding, CRC-32 and the incremental, resynchronising
 * parser. Layout in docs/protocol.md; the parser state is a caller-owned fixed buffer.
 */
#include <math.h>
#include <string.h>

#include "private/rs_le.h"
#include "raystream/rs_proto.h"

/* Offsets inside a version-1 frame (docs/protocol.md). */
enum {
	OFF_VERSION = 2,
	OFF_LENGTH = 3,
	OFF_SEQUENCE = 4,
	OFF_TIME = 8,
	OFF_MARKERS = 16,
	MARKER_BYTES = 14,
	OFF_CRC = OFF_MARKERS + RS_TRACK_MARKERS * MARKER_BYTES,
};
_Static_assert(OFF_CRC + 4 == RS_PROTO_FRAME_SIZE, "frame layout");
_Static_assert(RS_PROTO_FRAME_SIZE <= RS_PROTO_HID_REPORT_SIZE, "frame fits a HID report");

static const uint32_t crc_table[256] = {
    0x00000000u, 0x77073096u, 0xee0e612cu, 0x990951bau, 0x076dc419u, 0x706af48fu, 0xe963a535u,
    0x9e6495a3u, 0x0edb8832u, 0x79dcb8a4u, 0xe0d5e91eu, 0x97d2d988u, 0x09b64c2bu, 0x7eb17cbdu,
    0xe7b82d07u, 0x90bf1d91u, 0x1db71064u, 0x6ab020f2u, 0xf3b97148u, 0x84be41deu, 0x1adad47du,
    0x6ddde4ebu, 0xf4d4b551u, 0x83d385c7u, 0x136c9856u, 0x646ba8c0u, 0xfd62f97au, 0x8a65c9ecu,
    0x14015c4fu, 0x63066cd9u, 0xfa0f3d63u, 0x8d080df5u, 0x3b6e20c8u, 0x4c69105eu, 0xd56041e4u,
    0xa2677172u, 0x3c03e4d1u, 0x4b04d447u, 0xd20d85fdu, 0xa50ab56bu, 0x35b5a8fau, 0x42b2986cu,
    0xdbbbc9d6u, 0xacbcf940u, 0x32d86ce3u, 0x45df5c75u, 0xdcd60dcfu, 0xabd13d59u, 0x26d930acu,
    0x51de003au, 0xc8d75180u, 0xbfd06116u, 0x21b4f4b5u, 0x56b3c423u, 0xcfba9599u, 0xb8bda50fu,
    0x2802b89eu, 0x5f058808u, 0xc60cd9b2u, 0xb10be924u, 0x2f6f7c87u, 0x58684c11u, 0xc1611dabu,
    0xb6662d3du, 0x76dc4190u, 0x01db7106u, 0x98d220bcu, 0xefd5102au, 0x71b18589u, 0x06b6b51fu,
    0x9fbfe4a5u, 0xe8b8d433u, 0x7807c9a2u, 0x0f00f934u, 0x9609a88eu, 0xe10e9818u, 0x7f6a0dbbu,
    0x086d3d2du, 0x91646c97u, 0xe6635c01u, 0x6b6b51f4u, 0x1c6c6162u, 0x856530d8u, 0xf262004eu,
    0x6c0695edu, 0x1b01a57bu, 0x8208f4c1u, 0xf50fc457u, 0x65b0d9c6u, 0x12b7e950u, 0x8bbeb8eau,
    0xfcb9887cu, 0x62dd1ddfu, 0x15da2d49u, 0x8cd37cf3u, 0xfbd44c65u, 0x4db26158u, 0x3ab551ceu,
    0xa3bc0074u, 0xd4bb30e2u, 0x4adfa541u, 0x3dd895d7u, 0xa4d1c46du, 0xd3d6f4fbu, 0x4369e96au,
    0x346ed9fcu, 0xad678846u, 0xda60b8d0u, 0x44042d73u, 0x33031de5u, 0xaa0a4c5fu, 0xdd0d7cc9u,
    0x5005713cu, 0x270241aau, 0xbe0b1010u, 0xc90c2086u, 0x5768b525u, 0x206f85b3u, 0xb966d409u,
    0xce61e49fu, 0x5edef90eu, 0x29d9c998u, 0xb0d09822u, 0xc7d7a8b4u, 0x59b33d17u, 0x2eb40d81u,
    0xb7bd5c3bu, 0xc0ba6cadu, 0xedb88320u, 0x9abfb3b6u, 0x03b6e20cu, 0x74b1d29au, 0xead54739u,
    0x9dd277afu, 0x04db2615u, 0x73dc1683u, 0xe3630b12u, 0x94643b84u, 0x0d6d6a3eu, 0x7a6a5aa8u,
    0xe40ecf0bu, 0x9309ff9du, 0x0a00ae27u, 0x7d079eb1u, 0xf00f9344u, 0x8708a3d2u, 0x1e01f268u,
    0x6906c2feu, 0xf762575du, 0x806567cbu, 0x196c3671u, 0x6e6b06e7u, 0xfed41b76u, 0x89d32be0u,
    0x10da7a5au, 0x67dd4accu, 0xf9b9df6fu, 0x8ebeeff9u, 0x17b7be43u, 0x60b08ed5u, 0xd6d6a3e8u,
    0xa1d1937eu, 0x38d8c2c4u, 0x4fdff252u, 0xd1bb67f1u, 0xa6bc5767u, 0x3fb506ddu, 0x48b2364bu,
    0xd80d2bdau, 0xaf0a1b4cu, 0x36034af6u, 0x41047a60u, 0xdf60efc3u, 0xa867df55u, 0x316e8eefu,
    0x4669be79u, 0xcb61b38cu, 0xbc66831au, 0x256fd2a0u, 0x5268e236u, 0xcc0c7795u, 0xbb0b4703u,
    0x220216b9u, 0x5505262fu, 0xc5ba3bbeu, 0xb2bd0b28u, 0x2bb45a92u, 0x5cb36a04u, 0xc2d7ffa7u,
    0xb5d0cf31u, 0x2cd99e8bu, 0x5bdeae1du, 0x9b64c2b0u, 0xec63f226u, 0x756aa39cu, 0x026d930au,
    0x9c0906a9u, 0xeb0e363fu, 0x72076785u, 0x05005713u, 0x95bf4a82u, 0xe2b87a14u, 0x7bb12baeu,
    0x0cb61b38u, 0x92d28e9bu, 0xe5d5be0du, 0x7cdcefb7u, 0x0bdbdf21u, 0x86d3d2d4u, 0xf1d4e242u,
    0x68ddb3f8u, 0x1fda836eu, 0x81be16cdu, 0xf6b9265bu, 0x6fb077e1u, 0x18b74777u, 0x88085ae6u,
    0xff0f6a70u, 0x66063bcau, 0x11010b5cu, 0x8f659effu, 0xf862ae69u, 0x616bffd3u, 0x166ccf45u,
    0xa00ae278u, 0xd70dd2eeu, 0x4e048354u, 0x3903b3c2u, 0xa7672661u, 0xd06016f7u, 0x4969474du,
    0x3e6e77dbu, 0xaed16a4au, 0xd9d65adcu, 0x40df0b66u, 0x37d83bf0u, 0xa9bcae53u, 0xdebb9ec5u,
    0x47b2cf7fu, 0x30b5ffe9u, 0xbdbdf21cu, 0xcabac28au, 0x53b39330u, 0x24b4a3a6u, 0xbad03605u,
    0xcdd70693u, 0x54de5729u, 0x23d967bfu, 0xb3667a2eu, 0xc4614ab8u, 0x5d681b02u, 0x2a6f2b94u,
    0xb40bbe37u, 0xc30c8ea1u, 0x5a05df1bu, 0x2d02ef8du,
};

uint32_t rs_proto_crc32(const uint8_t *data, size_t len)
{
	uint32_t c = 0xFFFFFFFFu;
	for (size_t i = 0; i < len; i++)
		c = crc_table[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
	return c ^ 0xFFFFFFFFu;
}

enum rs_status rs_proto_encode(const struct rs_marker_sample *sample, uint8_t *out_frame,
                               struct rs_error *err)
{
	RS_ASSERT(sample && out_frame);
	uint8_t f[RS_PROTO_FRAME_SIZE];
	memset(f, 0, sizeof f);
	f[0] = RS_PROTO_SYNC0;
	f[1] = RS_PROTO_SYNC1;
	f[OFF_VERSION] = RS_PROTO_VERSION;
	f[OFF_LENGTH] = RS_PROTO_FRAME_SIZE;
	rs_le_put32(f + OFF_SEQUENCE, sample->sequence);
	rs_le_put64(f + OFF_TIME, sample->device_time_us);
	uint32_t count =
	    sample->marker_count < RS_TRACK_MARKERS ? sample->marker_count : RS_TRACK_MARKERS;
	for (uint32_t m = 0; m < RS_TRACK_MARKERS; m++) {
		uint8_t *p = f + OFF_MARKERS + m * MARKER_BYTES;
		if (m >= count) {
			p[0] = (uint8_t)m;
			continue;
		}
		const struct rs_marker *mk = &sample->markers[m];
		if (mk->id > 255 || mk->flags > 255)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "marker %u: id %u or flags 0x%x do not fit a byte", m,
			                    mk->id, mk->flags);
		p[0] = (uint8_t)mk->id;
		p[1] = (uint8_t)mk->flags;
		for (int a = 0; a < 3; a++) {
			/* The whole int32 range is accepted (not just +-RS_PROTO_MAX_COORD_M), so
			 * every frame the parser accepts, e.g. a device's INT32_MIN "no data"
			 * sentinel, encodes again: the recorder must not fail on real input. */
			double v = mk->position[a], um = isfinite(v) ? round(v * 1e6) : 0.0;
			if (!isfinite(v) || !(um >= -2147483648.0 && um <= 2147483647.0))
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "marker %u: coordinate %g not encodable", m, v);
			rs_le_put32(p + 2 + 4 * a, (uint32_t)(int32_t)um);
		}
	}
	rs_le_put32(f + OFF_CRC, rs_proto_crc32(f, OFF_CRC));
	memcpy(out_frame, f, sizeof f);
	return RS_OK;
}

void rs_proto_parser_init(struct rs_proto_parser *parser)
{
	RS_ASSERT(parser);
	memset(parser, 0, sizeof *parser);
}

void rs_proto_parser_reset(struct rs_proto_parser *parser)
{
	RS_ASSERT(parser);
	parser->len = 0;
	parser->have_sequence = 0;
	parser->last_sequence = 0;
	parser->run_length = 0;
}

const struct rs_proto_stats *rs_proto_parser_stats(const struct rs_proto_parser *parser)
{
	return &parser->stats;
}

/* Drop `n` buffered bytes from the front. */
static void drop(struct rs_proto_parser *p, size_t n)
{
	memmove(p->buf, p->buf + n, p->len - n);
	p->len -= n;
}

/* After a rejected candidate frame, drop its first byte only: a real frame may start
 * anywhere inside the bytes already buffered (a truncated frame followed by a good one). */
static void reject(struct rs_proto_parser *p)
{
	drop(p, 1);
}

static void decode(const uint8_t *f, struct rs_marker_sample *s)
{
	memset(s, 0, sizeof *s);
	s->sequence = rs_le_get32(f + OFF_SEQUENCE);
	s->device_time_us = rs_le_get64(f + OFF_TIME);
	s->marker_count = RS_TRACK_MARKERS;
	for (int m = 0; m < RS_TRACK_MARKERS; m++) {
		const uint8_t *p = f + OFF_MARKERS + m * MARKER_BYTES;
		s->markers[m].id = p[0];
		s->markers[m].flags = p[1];
		for (int a = 0; a < 3; a++)
			s->markers[m].position[a] =
			    (double)(int32_t)rs_le_get32(p + 2 + 4 * a) * 1e-6;
	}
}

/* Sequence policy (docs/protocol.md): equal = duplicate, 1..WINDOW-1 behind = out of
 * order (unless RS_PROTO_RESTART_RUN of them in a row count up: a restart), further
 * behind = device restart (accepted); forward gaps count lost frames.
 * Unsigned differences make the 2^32 wrap just another step forward. */
static int accept_sequence(struct rs_proto_parser *p, uint32_t seq)
{
	if (p->have_sequence) {
		uint32_t ahead = seq - p->last_sequence;
		uint32_t behind = p->last_sequence - seq;
		if (ahead == 0) {
			p->stats.duplicates++;
			return 0;
		}
		if (behind < RS_PROTO_SEQ_WINDOW) {
			/* A device that restarted its count without a reconnect would be
			 * refused for up to a whole window (8 s at 120 Hz); a run of
			 * consecutive sequences behind is that restart, not stale frames. */
			p->run_length =
			    p->run_length && seq == p->run_sequence + 1 ? p->run_length + 1 : 1;
			p->run_sequence = seq;
			if (p->run_length < RS_PROTO_RESTART_RUN) {
				p->stats.out_of_order++;
				return 0;
			}
			p->stats.restarts++;
			p->run_length = 0;
			p->last_sequence = seq;
			return 1;
		}
		if (ahead < 0x80000000u)
			p->stats.lost_frames += ahead - 1;
		else
			p->stats.restarts++;
	}
	p->have_sequence = 1;
	p->last_sequence = seq;
	p->run_length = 0;
	return 1;
}

/* Examine the buffer; returns 1 when it produced a frame, 0 when it needs more bytes. */
static int process(struct rs_proto_parser *p, struct rs_marker_sample *out)
{
	for (;;) {
		if (p->len == 0)
			return 0;
		if (p->buf[0] != RS_PROTO_SYNC0) {
			const uint8_t *s = memchr(p->buf, RS_PROTO_SYNC0, p->len);
			size_t skip = s ? (size_t)(s - p->buf) : p->len;
			p->stats.garbage_bytes += skip;
			drop(p, skip);
			continue;
		}
		if (p->len < 2)
			return 0;
		if (p->buf[1] != RS_PROTO_SYNC1) {
			p->stats.garbage_bytes++;
			drop(p, 1);
			continue;
		}
		if (p->len < RS_PROTO_HEADER_SIZE)
			return 0;
		if (p->buf[OFF_VERSION] != RS_PROTO_VERSION) {
			p->stats.bad_version++;
			reject(p);
			continue;
		}
		if (p->buf[OFF_LENGTH] < RS_PROTO_FRAME_SIZE) {
			p->stats.short_frames++;
			reject(p);
			continue;
		}
		if (p->buf[OFF_LENGTH] > RS_PROTO_FRAME_SIZE) {
			p->stats.long_frames++;
			reject(p);
			continue;
		}
		if (p->len < RS_PROTO_FRAME_SIZE)
			return 0;
		if (rs_proto_crc32(p->buf, OFF_CRC) != rs_le_get32(p->buf + OFF_CRC)) {
			p->stats.crc_errors++;
			reject(p);
			continue;
		}
		uint32_t seq = rs_le_get32(p->buf + OFF_SEQUENCE);
		int ok = accept_sequence(p, seq);
		if (ok)
			decode(p->buf, out);
		drop(p, RS_PROTO_FRAME_SIZE);
		if (ok) {
			p->stats.frames++;
			return 1;
		}
	}
}

bool rs_proto_parser_feed(struct rs_proto_parser *parser, const uint8_t **data, size_t *len,
                          struct rs_marker_sample *out_sample)
{
	RS_ASSERT(parser && data && len && out_sample);
	RS_ASSERT(*len == 0 || *data);
	for (;;) {
		if (process(parser, out_sample))
			return true;
		if (*len == 0)
			return false;
		/* process() returned for lack of bytes, so the buffer has room. */
		size_t room = sizeof parser->buf - parser->len;
		size_t n = *len < room ? *len : room;
		memcpy(parser->buf + parser->len, *data, n);
		parser->len += n;
		*data += n;
		*len -= n;
	}
}

void rs_proto_stats_add(struct rs_proto_stats *acc, const struct rs_proto_stats *b)
{
	acc->frames += b->frames;
	acc->garbage_bytes += b->garbage_bytes;
	acc->crc_errors += b->crc_errors;
	acc->short_frames += b->short_frames;
	acc->long_frames += b->long_frames;
	acc->bad_version += b->bad_version;
	acc->duplicates += b->duplicates;
	acc->out_of_order += b->out_of_order;
	acc->lost_frames += b->lost_frames;
	acc->restarts += b->restarts;
}

uint64_t rs_proto_stats_faults(const struct rs_proto_stats *s)
{
	return s->garbage_bytes + s->crc_errors + s->short_frames + s->long_frames +
	       s->bad_version + s->duplicates + s->out_of_order;
}
