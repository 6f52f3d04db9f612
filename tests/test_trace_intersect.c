/* rs_trace part 1, single primitives: the slab test with zero direction components and
 * empty boxes, both ray/triangle tests on known answers, degenerate and parallel
 * triangles, the open (tmin, tmax) interval, and agreement of the two algorithms. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <cmocka.h>

#include "raystream/rs_trace.h"

static uint64_t rng_state = 0x853c49e6748fea9bull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* A float-valued double (vertices are floats in the packed scene). Through a volatile:
 * GCC 12's SLP vectoriser at -O3 was seen to drop the float rounding when inlined. */
static double rnd_float(void)
{
	volatile float f = (float)(rnd() * 2 - 1);
	return f;
}

static const enum rs_triangle_test tests_both[2] = {RS_TRIANGLE_MOLLER_TRUMBORE,
                                                    RS_TRIANGLE_WATERTIGHT};

static struct rs_ray make_ray(double ox, double oy, double oz, double dx, double dy, double dz)
{
	struct rs_ray r = {{ox, oy, oz}, {dx, dy, dz}, 0.0, INFINITY, RS_NO_SLOT};
	return r;
}

static bool box_hit(const float lo[3], const float hi[3], const struct rs_ray *r)
{
	double inv[3] = {1.0 / r->dir[0], 1.0 / r->dir[1], 1.0 / r->dir[2]};
	return rs_intersect_box(lo, hi, r->origin, inv, r->tmin, r->tmax);
}

static const float unit_lo[3] = {0, 0, 0}, unit_hi[3] = {1, 1, 1};

static void box_hits_and_misses(void **state)
{
	struct rs_ray r = make_ray(-1, 0.5, 0.5, 1, 0.1, 0.1);
	assert_true(box_hit(unit_lo, unit_hi, &r));
	r = make_ray(-1, 2.5, 0.5, 1, 0.1, 0.1);
	assert_false(box_hit(unit_lo, unit_hi, &r));
	r = make_ray(0.5, 0.5, 0.5, -0.3, 0.7, 0.2); /* origin inside */
	assert_true(box_hit(unit_lo, unit_hi, &r));
}

/* dir components of +0 and -0 give inverse +-inf; origins on the slab planes give
 * (b - o) * inf = 0 * inf = NaN in a naive slab test. */
static void box_zero_direction_components(void **state)
{
	const double z[2] = {0.0, -0.0};
	for (int s = 0; s < 2; s++) {
		struct rs_ray r = make_ray(-1, 0.5, 0.5, 1, z[s], z[s]);
		assert_true(box_hit(unit_lo, unit_hi, &r));
		r = make_ray(-1, 1.5, 0.5, 1, z[s], z[s]); /* parallel, outside the y slab */
		assert_false(box_hit(unit_lo, unit_hi, &r));
		r = make_ray(-1, 0.0, 1.0, 1, z[s], z[s]); /* on the lo-y and hi-z planes */
		assert_true(box_hit(unit_lo, unit_hi, &r));
		r = make_ray(0.5, 1.0, 0.5, z[s], z[s], 1); /* on hi-y, along z */
		assert_true(box_hit(unit_lo, unit_hi, &r));
		r = make_ray(0.5, 1.0, 2.0, z[s], z[s], 1); /* same, but the box is behind */
		assert_false(box_hit(unit_lo, unit_hi, &r));
	}
}

static void box_empty_never_hit(void **state)
{
	const float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
	for (int i = 0; i < 1000; i++) {
		struct rs_ray r = make_ray(rnd() * 10 - 5, rnd() * 10 - 5, rnd() * 10 - 5,
		                           rnd() - 0.5, rnd() - 0.5, i % 3 ? rnd() - 0.5 : 0.0);
		assert_false(box_hit(lo, hi, &r));
	}
	struct rs_ray r = make_ray(0, 0, 0, 1, 0, 0);
	assert_false(box_hit(lo, hi, &r));
}

static void box_respects_interval(void **state)
{
	struct rs_ray r = make_ray(-2, 0.5, 0.5, 1, 0, 0); /* box spans t in [2, 3] */
	r.tmax = 1.5;
	assert_false(box_hit(unit_lo, unit_hi, &r));
	r.tmax = 2.5;
	assert_true(box_hit(unit_lo, unit_hi, &r));
	r.tmin = 3.5;
	r.tmax = INFINITY;
	assert_false(box_hit(unit_lo, unit_hi, &r));
	r = make_ray(2, 0.5, 0.5, 1, 0, 0); /* box behind the origin */
	assert_false(box_hit(unit_lo, unit_hi, &r));
}

/* docs/tracer.md R3: both slab ends are widened, so a flat box is still entered when the
 * closest hit so far lies 6 ulps before its computed near distance (the previous test
 * widened only the far end and culled it: the BVH then changed the result). */
static void box_near_end_is_conservative(void **state)
{
	const float lo[3] = {-1.0f, -1.0f, 0.3f}, hi[3] = {1.0f, 1.0f, 0.3f};
	struct rs_ray r = make_ray(0.1, 0.2, 2.0, 0.3, -0.1, -1.7);
	double inv[3] = {1.0 / r.dir[0], 1.0 / r.dir[1], 1.0 / r.dir[2]};
	double near = ((double)lo[2] - r.origin[2]) * inv[2];
	double tmax = near;
	for (int k = 0; k < 6; ++k) /* K = 2^-49 covers 8 ulps; 6 leaves room for rounding */
		tmax = nextafter(tmax, 0.0);
	assert_true(rs_intersect_box(lo, hi, r.origin, inv, 0.0, tmax));
	/* and still culled well before it */
	assert_false(rs_intersect_box(lo, hi, r.origin, inv, 0.0, near * (1.0 - 1e-12)));
	/* the far end likewise: a ray starting a few ulps behind the plane still enters */
	double far = near;
	for (int k = 0; k < 6; ++k)
		far = nextafter(far, INFINITY);
	assert_true(rs_intersect_box(lo, hi, r.origin, inv, far, INFINITY));
}

/* Triangle in z = 0: v0 (0,0), v1 (4,0), v2 (0,4). Hits are exact in binary. */
static const double tv0[3] = {0, 0, 0}, tv1[3] = {4, 0, 0}, tv2[3] = {0, 4, 0};

static void triangle_known_hit(void **state)
{
	for (int k = 0; k < 2; k++) {
		struct rs_ray r = make_ray(1, 2, 8, 0, 0, -2);
		double t, u, v;
		assert_true(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		/* Tolerance 1e-15: a few rounding steps on values of order 1. */
		assert_true(fabs(t - 4.0) < 1e-15);
		assert_true(fabs(u - 0.25) < 1e-15); /* weight of v1 */
		assert_true(fabs(v - 0.5) < 1e-15);  /* weight of v2 */
		r = make_ray(1, 2, -8, 0, 0, 2);     /* from the back: no culling */
		assert_true(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		r = make_ray(3, 3, 8, 0, 0, -1); /* outside the hypotenuse */
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
	}
}

static void triangle_interval_is_open(void **state)
{
	for (int k = 0; k < 2; k++) {
		struct rs_ray r = make_ray(1, 1, 2, 0, 0, -1); /* hit at t = 2 exactly */
		double t, u, v;
		r.tmax = 2.0;
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		r.tmax = INFINITY;
		r.tmin = 2.0;
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		r.tmin = 1.999;
		r.tmax = 2.001;
		assert_true(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		r = make_ray(1, 1, 2, 0, 0, 1); /* pointing away */
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
	}
}

static void degenerate_triangles_never_hit(void **state)
{
	const double a[3] = {0, 0, 0}, b[3] = {1, 1, 1}, c[3] = {2, 2, 2}, d[3] = {0.5, 0.5, 0.5};
	const double *tris[][3] = {{a, b, c}, {a, a, b}, {a, a, a}, {a, d, b}, {c, b, a}};
	for (int k = 0; k < 2; k++) {
		for (size_t i = 0; i < sizeof tris / sizeof tris[0]; i++) {
			for (int j = 0; j < 2000; j++) {
				/* Rays aimed at points on the segment, from anywhere. */
				double s = rnd() * 2;
				double o[3] = {rnd() * 6 - 3, rnd() * 6 - 3, rnd() * 6 - 3};
				struct rs_ray r =
				    make_ray(o[0], o[1], o[2], s - o[0], s - o[1], s - o[2]);
				double t = NAN, u = NAN, v = NAN;
				assert_false(rs_intersect_triangle(tests_both[k], tris[i][0],
				                                   tris[i][1], tris[i][2], &r, &t,
				                                   &u, &v));
			}
		}
	}
}

static void parallel_rays_never_hit(void **state)
{
	for (int k = 0; k < 2; k++) {
		double t, u, v;
		struct rs_ray r = make_ray(-1, 1, 0, 1, 0.1, 0); /* in the plane, through it */
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		r = make_ray(-1, 1, 1e-9, 1, 0.3, 0); /* parallel, just above */
		assert_false(rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v));
		/* A tilted triangle and in-plane rays in random directions within its plane. */
		const double p0[3] = {0.1, 0.2, 0.3}, p1[3] = {1.7, -0.4, 0.9},
		             p2[3] = {-0.3, 1.1, 2.2};
		for (int i = 0; i < 10000; i++) {
			double s = rnd(), w = rnd() * (1 - s), os = rnd() * 4 - 2,
			       ow = rnd() * 4 - 2;
			double q[3], o[3];
			for (int a = 0; a < 3; a++) {
				q[a] = p0[a] + s * (p1[a] - p0[a]) + w * (p2[a] - p0[a]);
				o[a] = p0[a] + os * (p1[a] - p0[a]) + ow * (p2[a] - p0[a]);
			}
			r = make_ray(o[0], o[1], o[2], q[0] - o[0], q[1] - o[1], q[2] - o[2]);
			if (rs_intersect_triangle(tests_both[k], p0, p1, p2, &r, &t, &u, &v))
				fail_msg("in-plane ray %d hit (test %d) at t=%g", i, k, t);
		}
	}
}

/* Grazing rays (1e-6 rad off the plane) still give finite, consistent answers. */
static void grazing_rays_are_finite(void **state)
{
	for (int k = 0; k < 2; k++) {
		for (int i = 0; i < 10000; i++) {
			double x = rnd() * 2, y = rnd() * 2;
			struct rs_ray r =
			    make_ray(x - 1, y, 1e-6, 1, 0, -1e-6); /* crosses z=0 at t=1 */
			double t = NAN, u = NAN, v = NAN;
			bool hit =
			    rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v);
			assert_true(hit); /* (x, y) lies inside the triangle (x + y <= 4) */
			/* t = 1 up to rounding amplified by 1/sin(1e-6) ~ 1e6: 1e-8 is generous. */
			assert_true(fabs(t - 1.0) < 1e-8);
			assert_true(isfinite(u) && isfinite(v));
		}
	}
}

/* Away from the edges both algorithms decide alike and agree on t, u, v. */
static void both_tests_agree_on_random_rays(void **state)
{
	int hits = 0;
	for (int i = 0; i < 100000; i++) {
		double v[3][3], o[3], q[3];
		for (int k = 0; k < 3; k++)
			for (int a = 0; a < 3; a++)
				v[k][a] = rnd_float();
		double b1 = rnd() * 1.4 - 0.2, b2 = rnd() * 1.4 - 0.2;
		for (int a = 0; a < 3; a++) {
			q[a] = v[0][a] + b1 * (v[1][a] - v[0][a]) + b2 * (v[2][a] - v[0][a]);
			o[a] = rnd() * 6 - 3;
		}
		struct rs_ray r = make_ray(o[0], o[1], o[2], q[0] - o[0], q[1] - o[1], q[2] - o[2]);
		double t1, u1, w1, t2, u2, w2;
		bool h1 = rs_intersect_triangle(RS_TRIANGLE_MOLLER_TRUMBORE, v[0], v[1], v[2], &r,
		                                &t1, &u1, &w1);
		bool h2 = rs_intersect_triangle(RS_TRIANGLE_WATERTIGHT, v[0], v[1], v[2], &r, &t2,
		                                &u2, &w2);
		double margin = fmin(fmin(b1, b2), 1 - b1 - b2);
		if (fabs(margin) < 1e-6)
			continue; /* at an edge the two may legitimately differ */
		assert_int_equal(h1, h2);
		assert_int_equal(h1, margin > 0);
		if (!h1)
			continue;
		hits++;
		/* Both are O(1e-16) accurate on these O(1) values except for skinny
		 * triangles; 1e-7 leaves room for condition numbers up to ~1e8. */
		assert_true(fabs(t1 - t2) <= 1e-7 * fabs(t1) + 1e-12);
		/* t = 1 at q, unless the ray grazes the plane (|cos| < 1e-3), where the rounding
		 * of q (1e-16) is amplified beyond the tolerance. */
		double e1[3], e2[3], n[3];
		for (int a = 0; a < 3; a++) {
			e1[a] = v[1][a] - v[0][a];
			e2[a] = v[2][a] - v[0][a];
		}
		n[0] = e1[1] * e2[2] - e1[2] * e2[1];
		n[1] = e1[2] * e2[0] - e1[0] * e2[2];
		n[2] = e1[0] * e2[1] - e1[1] * e2[0];
		double dn = n[0] * r.dir[0] + n[1] * r.dir[1] + n[2] * r.dir[2];
		double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		double dd = sqrt(r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2]);
		if (fabs(dn) > 1e-3 * nn * dd && !(fabs(t1 - 1.0) < 1e-7))
			fail_msg("ray %d: t %.17g (MT) %.17g (WT)", i, t1, t2);
		assert_true(fabs(u1 - u2) < 1e-7 && fabs(w1 - w2) < 1e-7);
	}
	assert_true(hits > 20000); /* ~25% of (b1, b2) fall inside */
}

static void nan_free_on_edge_cases(void **state)
{
	/* Huge and tiny direction magnitudes and components. */
	const double dirs[][3] = {
	    {1e-300, 1e-300, -1e-300}, {1e300, 1e-300, -1e300}, {0, 0, -1e-310}, {1e-200, 0, -1}};
	for (int k = 0; k < 2; k++) {
		for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
			struct rs_ray r = make_ray(1, 1, 1, dirs[i][0], dirs[i][1], dirs[i][2]);
			double t = 0, u = 0, v = 0;
			if (rs_intersect_triangle(tests_both[k], tv0, tv1, tv2, &r, &t, &u, &v))
				assert_true(isfinite(t) && isfinite(u) && isfinite(v));
		}
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(box_hits_and_misses),
	    cmocka_unit_test(box_zero_direction_components),
	    cmocka_unit_test(box_empty_never_hit),
	    cmocka_unit_test(box_respects_interval),
	    cmocka_unit_test(box_near_end_is_conservative),
	    cmocka_unit_test(triangle_known_hit),
	    cmocka_unit_test(triangle_interval_is_open),
	    cmocka_unit_test(degenerate_triangles_never_hit),
	    cmocka_unit_test(parallel_rays_never_hit),
	    cmocka_unit_test(grazing_rays_are_finite),
	    cmocka_unit_test(both_tests_agree_on_random_rays),
	    cmocka_unit_test(nan_free_on_edge_cases),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
