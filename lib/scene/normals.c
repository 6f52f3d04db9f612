/*
 * Vertex normals when a file has none: each face's unit normal weighted by the corner angle
 * it makes at the vertex, accumulated in double. Angle weighting makes the result
 * independent of how a surface is tessellated, unlike area or plain averaging. The edges
 * come from the double positions: a small mesh far from the origin keeps its shape there,
 * where its float rounding may not (the tracers' geometry is the doubles too).
 */
#include <math.h>
#include <stdlib.h>

#include "scene_internal.h"

static void sub(const double *a, const double *b, double *out)
{
	for (int i = 0; i < 3; ++i)
		out[i] = a[i] - b[i];
}

static double len(const double *v)
{
	return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static double corner_angle(const double *e1, const double *e2)
{
	double l1 = len(e1), l2 = len(e2);
	if (l1 == 0.0 || l2 == 0.0)
		return 0.0;
	double c = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / (l1 * l2);
	return acos(c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c);
}

int rs_scene_angle_weighted_normals(const double *positions, const uint32_t *indices,
                                    size_t triangle_count, size_t first_vertex, size_t vertex_count,
                                    float *out)
{
	double *acc = calloc(vertex_count * 3, sizeof *acc);
	if (!acc)
		return 0;
	for (size_t t = 0; t < triangle_count; ++t) {
		const uint32_t *tri = indices + t * 3;
		const double *p[3] = {positions + (size_t)tri[0] * 3,
		                      positions + (size_t)tri[1] * 3,
		                      positions + (size_t)tri[2] * 3};
		double e01[3], e02[3], n[3];
		sub(p[1], p[0], e01);
		sub(p[2], p[0], e02);
		n[0] = e01[1] * e02[2] - e01[2] * e02[1];
		n[1] = e01[2] * e02[0] - e01[0] * e02[2];
		n[2] = e01[0] * e02[1] - e01[1] * e02[0];
		double nl = len(n);
		if (nl == 0.0 || !isfinite(nl))
			continue; /* zero-area triangles have no direction to contribute */
		for (int k = 0; k < 3; ++k) {
			double a[3], b[3];
			sub(p[(k + 1) % 3], p[k], a);
			sub(p[(k + 2) % 3], p[k], b);
			double w = corner_angle(a, b) / nl;
			double *dst = acc + ((size_t)tri[k] - first_vertex) * 3;
			for (int i = 0; i < 3; ++i)
				dst[i] += w * n[i];
		}
	}
	for (size_t i = 0; i < vertex_count; ++i) {
		double l = len(acc + i * 3);
		for (int a = 0; a < 3; ++a)
			out[i * 3 + a] =
			    l > 0.0 ? (float)(acc[i * 3 + a] / l) : (a == 1 ? 1.0f : 0.0f);
	}
	free(acc);
	return 1;
}

void rs_scene_normalize_normals(float *normals, size_t count)
{
	for (size_t i = 0; i < count; ++i) {
		float *n = normals + i * 3;
		double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
		for (int a = 0; a < 3; ++a)
			n[a] = l > 0.0 ? (float)(n[a] / l) : (a == 1 ? 1.0f : 0.0f);
	}
}
