/* Four floats at a time for the SAH builder's box unions (SSE where the compiler targets
 * it, plain C elsewhere). Only exact operations live here (min, max, and the bin index
 * below), so both versions give the same bits and the tree never depends on which ran.
 * Lane 3 of a box carries no coordinate (a record keeps its id there) and is ignored.
 * -DRS_BVH_PLAIN_C forces the plain C version (to check that it builds the same tree). */
#ifndef RS_BVH_V4_H
#define RS_BVH_V4_H

#include <float.h>
#include <stdint.h>

#if defined(__SSE2__) && defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0 &&                       \
    !defined(RS_BVH_PLAIN_C)
#include <emmintrin.h>
#define RS_BVH_SSE 1
/* AVX where the CPU has it, chosen at run time (bvh_sah.c's plane costs): the compiler must
 * take target attributes. */
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#define RS_BVH_WIDE 1
#endif

typedef __m128 rs_v4;

static inline rs_v4 rs_v4_load(const float *p)
{
	return _mm_loadu_ps(p);
}
static inline void rs_v4_store(float *p, rs_v4 v)
{
	_mm_storeu_ps(p, v);
}
static inline rs_v4 rs_v4_min(rs_v4 a, rs_v4 b)
{
	return _mm_min_ps(a, b);
}
static inline rs_v4 rs_v4_max(rs_v4 a, rs_v4 b)
{
	return _mm_max_ps(a, b);
}
static inline rs_v4 rs_v4_set(float x, float y, float z, float w)
{
	return _mm_setr_ps(x, y, z, w);
}
/* 0.5 lo + 0.5 hi: no overflow, and (with contraction off for this module) the same
 * rounding as the plain C version. */
static inline rs_v4 rs_v4_centroid(rs_v4 lo, rs_v4 hi)
{
	const __m128 half = _mm_set1_ps(0.5f);
	return _mm_add_ps(_mm_mul_ps(half, lo), _mm_mul_ps(half, hi));
}
/* The bin of centroid c on each axis: (c - clo) k clamped to [0, top] (max first, so NaN,
 * from inf * 0 near FLT_MAX, lands in bin 0), then truncated. */
static inline void rs_v4_bins(rs_v4 c, rs_v4 clo, rs_v4 k, rs_v4 top, int32_t out[4])
{
	__m128 f = _mm_mul_ps(_mm_sub_ps(c, clo), k);
	f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top);
	_mm_storeu_si128((__m128i *)(void *)out, _mm_cvttps_epi32(f));
}
/* Bit i set when lane i of a >= b. */
static inline int rs_v4_ge_mask(rs_v4 a, rs_v4 b)
{
	return _mm_movemask_ps(_mm_cmpge_ps(a, b));
}
static inline rs_v4 rs_v4_sub(rs_v4 a, rs_v4 b)
{
	return _mm_sub_ps(a, b);
}
static inline rs_v4 rs_v4_mul(rs_v4 a, rs_v4 b)
{
	return _mm_mul_ps(a, b);
}
static inline rs_v4 rs_v4_add(rs_v4 a, rs_v4 b)
{
	return _mm_add_ps(a, b);
}
/* p[0..2], lane 3 zero; p[3] must be readable (it is read, then dropped). */
static inline rs_v4 rs_v4_load3(const float *p)
{
	return _mm_and_ps(_mm_loadu_ps(p), _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)));
}
#else
typedef struct {
	float f[4];
} rs_v4;

static inline rs_v4 rs_v4_load(const float *p)
{
	return (rs_v4){{p[0], p[1], p[2], p[3]}};
}
static inline void rs_v4_store(float *p, rs_v4 v)
{
	for (int i = 0; i < 4; i++)
		p[i] = v.f[i];
}
/* The same rule as minps/maxps (the second operand when unordered). */
static inline rs_v4 rs_v4_min(rs_v4 a, rs_v4 b)
{
	for (int i = 0; i < 4; i++)
		a.f[i] = a.f[i] < b.f[i] ? a.f[i] : b.f[i];
	return a;
}
static inline rs_v4 rs_v4_max(rs_v4 a, rs_v4 b)
{
	for (int i = 0; i < 4; i++)
		a.f[i] = a.f[i] > b.f[i] ? a.f[i] : b.f[i];
	return a;
}
static inline rs_v4 rs_v4_set(float x, float y, float z, float w)
{
	return (rs_v4){{x, y, z, w}};
}
static inline rs_v4 rs_v4_centroid(rs_v4 lo, rs_v4 hi)
{
	for (int i = 0; i < 4; i++)
		lo.f[i] = 0.5f * lo.f[i] + 0.5f * hi.f[i];
	return lo;
}
static inline void rs_v4_bins(rs_v4 c, rs_v4 clo, rs_v4 k, rs_v4 top, int32_t out[4])
{
	for (int i = 0; i < 4; i++) {
		float f = (c.f[i] - clo.f[i]) * k.f[i];
		f = f > 0.0f ? f : 0.0f;
		f = f < top.f[i] ? f : top.f[i];
		out[i] = (int32_t)f;
	}
}
static inline int rs_v4_ge_mask(rs_v4 a, rs_v4 b)
{
	int m = 0;
	for (int i = 0; i < 4; i++)
		m |= (a.f[i] >= b.f[i]) << i;
	return m;
}
static inline rs_v4 rs_v4_sub(rs_v4 a, rs_v4 b)
{
	for (int i = 0; i < 4; i++)
		a.f[i] -= b.f[i];
	return a;
}
static inline rs_v4 rs_v4_mul(rs_v4 a, rs_v4 b)
{
	for (int i = 0; i < 4; i++)
		a.f[i] *= b.f[i];
	return a;
}
static inline rs_v4 rs_v4_add(rs_v4 a, rs_v4 b)
{
	for (int i = 0; i < 4; i++)
		a.f[i] += b.f[i];
	return a;
}
static inline rs_v4 rs_v4_load3(const float *p)
{
	return (rs_v4){{p[0], p[1], p[2], 0.0f}};
}
#endif

/* Grow box (lo, hi) by box (plo, phi), 4 lanes each. */
static inline void rs_v4_grow(float *lo, float *hi, const float *plo, const float *phi)
{
	rs_v4_store(lo, rs_v4_min(rs_v4_load(lo), rs_v4_load(plo)));
	rs_v4_store(hi, rs_v4_max(rs_v4_load(hi), rs_v4_load(phi)));
}

#endif
