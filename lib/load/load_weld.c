/*
 * Exact vertex welding for the loader. assimp's JoinIdenticalVertices merges positions up
 * to 1e-5 apart (an absolute tolerance), which moves vertices of small models and collapses
 * thin slivers; here only vertices whose position (and, when the file's normals are used,
 * normal) are exactly equal are shared. Sharing is what gives computed normals their
 * smoothness; the ray tracer's watertightness needs equal coordinates, not shared indices.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"

/* Bits of a float with -0 read as +0 (they are the same point). */
static uint32_t key_bits(float f)
{
	uint32_t u;
	if (f == 0.0f)
		f = 0.0f;
	memcpy(&u, &f, sizeof u);
	return u;
}

static uint64_t hash_vertex(const float *p, const float *n)
{
	uint64_t h = 0x9e3779b97f4a7c15ull;
	for (int k = 0; k < 6; k++) {
		if (k >= 3 && !n)
			break;
		h ^= key_bits(k < 3 ? p[k] : n[k - 3]);
		h *= 0xff51afd7ed558ccdull;
		h ^= h >> 29;
	}
	return h;
}

static int same(const float *a, const float *b, int count)
{
	for (int k = 0; k < count; k++)
		if (!(a[k] == b[k]))
			return 0;
	return 1;
}

enum rs_status rs_load_weld(const float *pos, const float *nrm, size_t stride, size_t count,
                            uint32_t *out_remap, uint32_t *out_source, size_t *out_unique)
{
	size_t cap = 16;
	while (cap < 2 * count)
		cap *= 2;
	uint32_t *table = malloc(cap * sizeof *table);
	if (!table)
		return RS_ERR_NO_MEMORY;
	memset(table, 0xff, cap * sizeof *table);
	size_t unique = 0;
	for (size_t v = 0; v < count; v++) {
		const float *p = (const float *)((const char *)pos + v * stride);
		const float *n = nrm ? (const float *)((const char *)nrm + v * stride) : NULL;
		size_t slot = (size_t)hash_vertex(p, n) & (cap - 1);
		for (;; slot = (slot + 1) & (cap - 1)) {
			uint32_t u = table[slot];
			if (u == UINT32_MAX) {
				table[slot] = (uint32_t)unique;
				out_source[unique] = (uint32_t)v;
				out_remap[v] = (uint32_t)unique++;
				break;
			}
			size_t s = out_source[u];
			const float *q = (const float *)((const char *)pos + s * stride);
			const float *m =
			    nrm ? (const float *)((const char *)nrm + s * stride) : NULL;
			if (same(p, q, 3) && (!n || same(n, m, 3))) {
				out_remap[v] = u;
				break;
			}
		}
	}
	free(table);
	*out_unique = unique;
	return RS_OK;
}
