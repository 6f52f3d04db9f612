/* Ray/box and ray/triangle tests in double precision: the slab test (robust to zero
 * direction components and empty boxes), Moller-Trumbore (the paper's) and the watertight
 * test of Woop, Benthin & Wald 2013. Triangle vertices are floats widened to double, so
 * edge vectors are exact and the rounding of det-like quantities is known; that is what
 * the zero-area and parallel rejections below rely on. Details: docs/bvh.md. */
#include <math.h>

#include "raystream/rs_trace.h"

#include "intersect_internal.h"
#include "private/rs_vec.h"

/* Both slab distances are widened outwards by K (docs/tracer.md R3). Ize 2013 ("Robust BVH
 * ray traversal") shows 1 + 2 gamma_3 covers the rounding of (b - o) * inv; K = 16 ulps also
 * covers the triangle test's rounding of t, so a flat box around a hit one ulp nearer than
 * its computed near distance is still entered (the BVH must never change the result). */
#define BOX_K RS_TRACE_BOX_K
/* A ray this close to the triangle's plane (relative |d.n| / (|d| |n|), max norms) counts
 * as parallel: t would be dominated by rounding. ~1e-13 rad, far below any real grazing.
 * Moller-Trumbore scales it by |e1| |e2| instead of |n| (no extra cross product). */
#define PARALLEL_EPS RS_TRACE_PARALLEL_EPS

/* R3's outward widening, monotone in t: so widening the largest near and the smallest far
 * once equals widening every slab's, and costs two multiplications per box, not six. */
static double widen_down(double t)
{
	return t * (t > 0.0 ? 1.0 - BOX_K : 1.0 + BOX_K);
}

static double widen_up(double t)
{
	return t * (t > 0.0 ? 1.0 + BOX_K : 1.0 - BOX_K);
}

bool rs_intersect_box(const float lo[3], const float hi[3], const double origin[3],
                      const double inv_dir[3], double tmin, double tmax)
{
	double tn = tmin, tf = tmax;
	for (int a = 0; a < 3; a++) {
		double inv = inv_dir[a];
		if (isinf(inv) || isnan(inv)) {
			/* Direction component 0: (b - o) * inf could be 0 * inf = NaN. The ray
			 * stays in its plane; it is inside the slab iff the origin is
			 * (boundary inclusive; an empty box's lo > hi fails here). */
			if (!(origin[a] >= lo[a] && origin[a] <= hi[a]))
				return false;
			continue;
		}
		/* Pick near/far by the direction's sign, never by min/max: an empty box
		 * (lo > hi) must stay empty instead of being flipped into a huge one. */
		double t0 = ((double)lo[a] - origin[a]) * inv;
		double t1 = ((double)hi[a] - origin[a]) * inv;
		double near = inv >= 0.0 ? t0 : t1;
		double far = inv >= 0.0 ? t1 : t0;
		tn = near > tn ? near : tn;
		tf = far < tf ? far : tf;
	}
	return !(widen_down(tn) > widen_up(tf));
}

static double maxabs3(const double a[3])
{
	double m = fabs(a[0]);
	m = fabs(a[1]) > m ? fabs(a[1]) : m;
	return fabs(a[2]) > m ? fabs(a[2]) : m;
}

void rs__ray_prepare(const struct rs_ray *ray, struct rs__ray_pre *out)
{
	const double *d = ray->dir;
	out->ray = ray;
	out->dir_max = maxabs3(d);
	/* Watertight: project onto the plane orthogonal to the dominant axis kz; swapping
	 * kx, ky keeps the winding when d[kz] < 0. */
	int kz = 0;
	if (fabs(d[1]) > fabs(d[kz]))
		kz = 1;
	if (fabs(d[2]) > fabs(d[kz]))
		kz = 2;
	int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
	if (d[kz] < 0.0) {
		int t = kx;
		kx = ky;
		ky = t;
	}
	out->kx = kx;
	out->ky = ky;
	out->kz = kz;
	out->sx = d[kx] / d[kz];
	out->sy = d[ky] / d[kz];
	out->sz = 1.0 / d[kz];
	out->edge_slack = 0.0;
}

/* Watertight rejection of zero-area triangles (exact: the normal of float vertices is
 * computed from exact edges) and rays (nearly) in the triangle's plane. Returns d.n or 0. */
static double plane_facing(const double e1[3], const double e2[3], const struct rs__ray_pre *pre)
{
	double n[3];
	rs_v3_cross(e1, e2, n);
	double nm = maxabs3(n);
	if (nm == 0.0)
		return 0.0;
	double dn = rs_v3_dot(pre->ray->dir, n);
	return fabs(dn) <= PARALLEL_EPS * pre->dir_max * nm ? 0.0 : dn;
}

static bool moller_trumbore(const double v0[3], const double v1[3], const double v2[3],
                            const struct rs__ray_pre *pre, double *out_t, double *out_u,
                            double *out_v)
{
	const struct rs_ray *ray = pre->ray;
	double e1[3], e2[3], p[3], s[3], q[3];
	rs_v3_sub(v1, v0, e1);
	rs_v3_sub(v2, v0, e2);
	rs_v3_cross(ray->dir, e2, p);
	double det = rs_v3_dot(e1, p);
	/* det = -d.(e1 x e2): zero for a zero-area triangle and for a ray in its plane. The
	 * edges are exact, so its rounding stays near 1e-16 |d| |e1| |e2|; 1e-13 of that
	 * rejects both cases (and slivers met within ~1e-13 / sin(edge angle) of parallel). */
	if (fabs(det) <= PARALLEL_EPS * pre->dir_max * maxabs3(e1) * maxabs3(e2))
		return false;
	/* Compare numerators against det (sign-adjusted) and divide only for a hit. */
	double sign = det > 0.0 ? 1.0 : -1.0, adet = fabs(det);
	rs_v3_sub(ray->origin, v0, s);
	double un = rs_v3_dot(s, p) * sign;
	if (un < 0.0 || un > adet)
		return false;
	rs_v3_cross(s, e1, q);
	double vn = rs_v3_dot(ray->dir, q) * sign;
	if (vn < 0.0 || un + vn > adet)
		return false;
	double inv = 1.0 / det;
	double t = rs_v3_dot(e2, q) * inv;
	if (!(t > ray->tmin && t <= ray->tmax))
		return false;
	*out_t = t;
	*out_u = un * sign * inv;
	*out_v = vn * sign * inv;
	return true;
}

/* Every quantity below depends only on the ray and one vertex, or is an exact sign flip
 * between the two triangles sharing an edge, so a ray can never pass between them. */
static bool watertight(const double v0[3], const double v1[3], const double v2[3],
                       const struct rs__ray_pre *pre, double *out_t, double *out_u, double *out_v)
{
	const struct rs_ray *ray = pre->ray;
	double e1[3], e2[3];
	rs_v3_sub(v1, v0, e1);
	rs_v3_sub(v2, v0, e2);
	if (plane_facing(e1, e2, pre) == 0.0)
		return false;
	const int kx = pre->kx, ky = pre->ky, kz = pre->kz;
	double a[3], b[3], c[3];
	rs_v3_sub(v0, ray->origin, a);
	rs_v3_sub(v1, ray->origin, b);
	rs_v3_sub(v2, ray->origin, c);
	double ax = a[kx] - pre->sx * a[kz], ay = a[ky] - pre->sy * a[kz];
	double bx = b[kx] - pre->sx * b[kz], by = b[ky] - pre->sy * b[kz];
	double cx = c[kx] - pre->sx * c[kz], cy = c[ky] - pre->sy * c[kz];
	double u = cx * by - cy * bx;
	double v = ax * cy - ay * cx;
	double w = bx * ay - by * ax;
	double s = pre->edge_slack > 0.0 ? pre->edge_slack * (fabs(u) + fabs(v) + fabs(w)) : 0.0;
	if ((u < -s || v < -s || w < -s) && (u > s || v > s || w > s))
		return false;
	double det = u + v + w;
	if (det == 0.0)
		return false;
	double sz = pre->sz;
	double t = (u * sz * a[kz] + v * sz * b[kz] + w * sz * c[kz]) / det;
	if (!(t > ray->tmin && t <= ray->tmax))
		return false;
	*out_t = t;
	*out_u = v / det;
	*out_v = w / det;
	return true;
}

bool rs__intersect_triangle_pre(enum rs_triangle_test test, const double v0[3], const double v1[3],
                                const double v2[3], const struct rs__ray_pre *pre, double *out_t,
                                double *out_u, double *out_v)
{
	if (test == RS_TRIANGLE_WATERTIGHT)
		return watertight(v0, v1, v2, pre, out_t, out_u, out_v);
	return moller_trumbore(v0, v1, v2, pre, out_t, out_u, out_v);
}

bool rs_intersect_triangle(enum rs_triangle_test test, const double v0[3], const double v1[3],
                           const double v2[3], const struct rs_ray *ray, double *out_t,
                           double *out_u, double *out_v)
{
	struct rs__ray_pre pre;
	rs__ray_prepare(ray, &pre);
	double t, u, v;
	/* the traversal's form accepts t == tmax (for the tie-break); this one keeps it open */
	if (!rs__intersect_triangle_pre(test, v0, v1, v2, &pre, &t, &u, &v) || !(t < ray->tmax))
		return false;
	*out_t = t;
	*out_u = u;
	*out_v = v;
	return true;
}
