/* rs_trace, closest-hit rules (docs/tracer.md R3, R4): the BVH never changes the result.
 * On overlapping, coincident and near-coincident faces all four builders give bit-identical
 * images with both triangle tests: the slab test is conservative on both sides and equal t
 * goes to the lower scene triangle id, whatever order the BVH visits triangles in. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "test_trace_render_fixture.h"

#define SIZE 128

static const enum rs_bvh_builder builders[4] = {RS_BVH_NONE, RS_BVH_LINEAR, RS_BVH_PAPER,
                                                RS_BVH_SAH};

/* A square at height z on axis 2 spanning [x0, x0 + w] x [y0, y0 + w], split along one
 * diagonal or the other, wound to face +z. */
static void square(struct rs_scene *scene, float z, float x0, float y0, float w, int diagonal,
                   uint32_t material)
{
	const float pos[12] = {x0, y0, z, x0 + w, y0, z, x0 + w, y0 + w, z, x0, y0 + w, z};
	const uint32_t d0[6] = {0, 1, 2, 0, 2, 3}, d1[6] = {0, 1, 3, 1, 2, 3};
	fx_mesh(scene, pos, 4, diagonal ? d1 : d0, 2, NULL, material);
}

/* Layers of squares in (nearly) one plane, each in its own colour, plus a tilted square
 * crossing them at a tiny angle, and a few copies of the same square (exact duplicates).
 * Built several times over so the SAH reorders them and the paper tree gets flat leaves. */
static void overlap_scene(struct fx *fx)
{
	fx->scene = fx_scene();
	uint32_t mat[6];
	for (int k = 0; k < 6; ++k) {
		struct rs_material m = {
		    .diffuse = {0.15f * (float)k, 0.9f - 0.12f * (float)k, (float)(k % 2)}};
		mat[k] = fx_material(fx->scene, m);
	}
	const float z = 0.3f;
	for (int rep = 0; rep < 3; ++rep) {
		float dx = 0.37f * (float)rep - 0.4f;
		square(fx->scene, z, dx - 1.0f, -1.0f, 2.0f, rep % 2, mat[(rep + 5) % 6]);
		square(fx->scene, z, dx - 1.0f, -1.0f, 2.0f, 1 - rep % 2, mat[0]); /* coincident */
		square(fx->scene, z, dx - 1.0f, -1.0f, 2.0f, rep % 2, mat[1]);     /* duplicate */
		square(fx->scene, nextafterf(z, 1.0f), dx - 0.5f, -0.7f, 2.0f, 0, mat[2]);
		square(fx->scene, nextafterf(z, 0.0f), dx - 1.3f, -0.2f, 1.5f, 1, mat[3]);
		square(fx->scene, z + 1e-6f, dx - 0.2f, -1.2f, 1.0f, 0, mat[4]);
	}
	/* tilted by ~1e-6 rad about the y axis: crosses the layers along a line */
	const float tilt[12] = {-1.5f, -1.5f, z - 1.5e-6f, 1.5f,  -1.5f, z + 1.5e-6f,
	                        1.5f,  1.5f,  z + 1.5e-6f, -1.5f, 1.5f,  z - 1.5e-6f};
	const uint32_t t_idx[6] = {0, 1, 2, 0, 2, 3};
	fx_mesh(fx->scene, tilt, 4, t_idx, 2, NULL, mat[5]);
	const double eye[3] = {0.4, 0.9, 3.0}, target[3] = {0.0, 0.0, 0.3};
	fx_camera(fx->scene, eye, target, SIZE);
	fx_light(fx->scene, 1.0, 2.0, 2.0, 1, 1, 1);
}

static float rgb[4][SIZE * SIZE * 3], depth[4][SIZE * SIZE];

static void all_builders_give_bit_identical_images(void **state)
{
	for (int test = 0; test < 2; ++test) {
		for (int b = 0; b < 4; ++b) {
			struct fx fx;
			overlap_scene(&fx);
			fx_pack(&fx, builders[b]);
			struct rs_trace_desc d = {.passes = 2,
			                          .triangle_test = test
			                                               ? RS_TRIANGLE_MOLLER_TRUMBORE
			                                               : RS_TRIANGLE_WATERTIGHT};
			assert_int_equal(
			    rs_trace_render(fx.scene, &fx.packed, &d, rgb[b], depth[b], NULL, NULL),
			    RS_OK);
			fx_free(&fx);
		}
		for (int b = 1; b < 4; ++b) {
			size_t off = 0;
			for (size_t i = 0; i < (size_t)SIZE * SIZE; ++i)
				off += memcmp(&rgb[0][3 * i], &rgb[b][3 * i], 3 * sizeof(float)) ||
				       memcmp(&depth[0][i], &depth[b][i], sizeof(float));
			if (off)
				fail_msg("test %d, builder %d: %zu pixels differ from 'none'", test,
				         b, off);
		}
	}
}

/* Exact duplicates: whatever the builder, the lowest scene triangle id is the hit. */
static void equal_t_goes_to_the_lower_triangle_id(void **state)
{
	for (int b = 0; b < 4; ++b) {
		struct fx fx;
		overlap_scene(&fx);
		fx_pack(&fx, builders[b]);
		for (int i = 0; i < 400; ++i) {
			double x = -0.9 + 1.8 * (i % 20) / 19.0, y = -0.9 + 1.8 * (i / 20) / 19.0;
			struct rs_ray r = {.origin = {x, y, 2.0},
			                   .dir = {0.01, -0.02, -1.0},
			                   .tmax = INFINITY,
			                   .skip_slot = RS_NO_SLOT};
			struct rs_hit h, hb;
			for (int test = 0; test < 2; ++test) {
				enum rs_triangle_test tt =
				    test ? RS_TRIANGLE_MOLLER_TRUMBORE : RS_TRIANGLE_WATERTIGHT;
				bool a = rs_trace_closest(&fx.packed, tt, &r, &h, NULL);
				/* brute force tests slots in order; the rule is order-free */
				bool c = rs_trace_closest_brute(&fx.packed, tt, &r, &hb);
				assert_int_equal(a, c);
				if (!a)
					continue;
				assert_true(h.t == hb.t);
				assert_int_equal(h.triangle, hb.triangle);
				/* no triangle with an id below the winner ties with it (tested
				 * in the packed frame, as the traversal does: same t, bit for
				 * bit) */
				struct rs_ray one = r;
				one.tmax = nextafter(h.t, INFINITY);
				for (int ax = 0; ax < 3; ++ax)
					one.origin[ax] -= fx.packed.origin[ax];
				for (uint32_t s = 0; s < fx.packed.triangle_count; ++s) {
					double v[3][3], t, u, w;
					const float *tx = rs_pack_texel(
					    &fx.packed.triangles, RS_PACK_TRIANGLE_TEXELS, s, 0);
					if ((uint32_t)tx[3] >= h.triangle)
						continue;
					for (int k = 0; k < 3; ++k)
						for (int ax = 0; ax < 3; ++ax)
							v[k][ax] =
							    rs_pack_texel(&fx.packed.triangles,
							                  RS_PACK_TRIANGLE_TEXELS,
							                  s, (uint32_t)k)[ax];
					if (rs_intersect_triangle(tt, v[0], v[1], v[2], &one, &t,
					                          &u, &w))
						assert_true(t > h.t);
				}
			}
		}
		fx_free(&fx);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(all_builders_give_bit_identical_images),
	    cmocka_unit_test(equal_t_goes_to_the_lower_triangle_id),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
