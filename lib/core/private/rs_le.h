/*
 * Private to raystream (never installed): the one little-endian byte codec, for every wire
 * and file format the tree writes itself (tracker protocol, replay recordings, stream
 * messages). Assembled byte by byte, so the host's byte order and alignment never matter.
 */
#ifndef RS_LE_H
#define RS_LE_H

#include <stdint.h>

static inline void rs_le_put16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static inline void rs_le_put32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		p[i] = (uint8_t)(v >> (8 * i));
}

static inline void rs_le_put64(uint8_t *p, uint64_t v)
{
	rs_le_put32(p, (uint32_t)v);
	rs_le_put32(p + 4, (uint32_t)(v >> 32));
}

static inline uint16_t rs_le_get16(const uint8_t *p)
{
	return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t rs_le_get32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
	       ((uint32_t)p[3] << 24);
}

static inline uint64_t rs_le_get64(const uint8_t *p)
{
	return (uint64_t)rs_le_get32(p) | ((uint64_t)rs_le_get32(p + 4) << 32);
}

#endif
