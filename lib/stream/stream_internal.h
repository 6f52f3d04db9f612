/* Private to rs_stream: little-endian field access and the per-type body codec. */
#ifndef RS_STREAM_INTERNAL_H
#define RS_STREAM_INTERNAL_H

#include <string.h>

#include "raystream/rs_stream.h"

static inline void st_put16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}
static inline void st_put32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		p[i] = (uint8_t)(v >> (8 * i));
}
static inline void st_put64(uint8_t *p, uint64_t v)
{
	for (int i = 0; i < 8; ++i)
		p[i] = (uint8_t)(v >> (8 * i));
}
static inline uint16_t st_get16(const uint8_t *p)
{
	return (uint16_t)(p[0] | (p[1] << 8));
}
static inline uint32_t st_get32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
	       ((uint32_t)p[3] << 24);
}
static inline uint64_t st_get64(const uint8_t *p)
{
	return (uint64_t)st_get32(p) | ((uint64_t)st_get32(p + 4) << 32);
}

/* Largest payload a message of `type` may declare (frames: the fixed part plus
 * RS_STREAM_MAX_SIDE^2 * 4 raw bytes; the parser's buffer bounds it further). 0: unknown. */
uint32_t rs_stream_max_payload(uint32_t type);

/* Decode and validate one complete body. RS_ERR_PARSE for a length that does not fit the
 * layout, RS_ERR_BAD_DATA for a field out of range; `err` names it. */
enum rs_status rs_stream_decode_body(uint32_t type, const uint8_t *body, uint32_t length,
                                     struct rs_stream_msg *out, struct rs_error *err);

#endif
