/* rs_trace: no shadow acne on flat and curved lit surfaces, and no NaN anywhere on a scene
 * full of degenerate triangles and awkward lights. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "test_trace_render_fixture.h"

#define SIZE 32

static void tilted_plane_far_from_the_origin_has_no_acne(void **state)
{
	/* A quad of two coplanar triangles, tilted and 1000 units out, with coordinates that
	 * floats cannot hold exactly. Without the offset the feeler of one triangle finds its
	 * coplanar neighbour at t ~ 0 and speckles the image with ambient-only pixels. */
	struct fx fx = {.scene = fx_scene()};
	struct rs_material m = {.diffuse = {0.7f, 0.7f, 0.7f}};
	const float pos[12] = {997.1f,  -3.3f, 1001.7f, 1003.3f, -2.1f, 998.9f,
	                       1002.9f, 3.7f,  999.3f,  996.7f,  2.5f,  1002.1f};
	const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
	fx_mesh(fx.scene, pos, 4, idx, 2, NULL, fx_material(fx.scene, m));
	double n[3], e1[3], e2[3];
	for (int a = 0; a < 3; ++a) {
		e1[a] = (double)pos[3 + a] - pos[a];
		e2[a] = (double)pos[6 + a] - pos[a];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	double c[3] = {1000, 0.2, 1000.5}, eye[3], lp[3];
	for (int a = 0; a < 3; ++a) {
		eye[a] = c[a] + 8.0 * n[a] / sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		lp[a] = c[a] + 40.0 * n[a] / sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	}
	lp[0] += 60.0; /* off to the side: feelers leave at about 40 degrees */
	fx_camera(fx.scene, eye, c, SIZE);
	fx_light(fx.scene, lp[0], lp[1], lp[2], 1, 1, 1);
	fx_pack(&fx, RS_BVH_SAH);
	static float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	struct rs_trace_desc d = {.passes = 1};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, rgb, depth, NULL, NULL), RS_OK);
	int hits = 0;
	for (int i = 0; i < SIZE * SIZE; ++i) {
		if (isinf(depth[i]))
			continue;
		hits++;
		/* lit: ambient 0.07 plus 0.7 N.L, N.L > 0.3 for this light everywhere */
		assert_true(rgb[i * 3] > 0.07f + 0.7f * 0.3f);
	}
	assert_true(hits > SIZE * SIZE / 2);
	fx_free(&fx);
}

/* UV sphere of radius 1 at the origin, 16 stacks x 32 slices, shared vertices (so the
 * scene computes smooth normals). */
static void add_sphere(struct rs_scene *scene, uint32_t material)
{
	enum { ST = 16, SL = 32 };
	static float pos[(ST + 1) * (SL + 1) * 3];
	static uint32_t idx[ST * SL * 6];
	size_t nv = 0, nt = 0;
	for (int i = 0; i <= ST; ++i) {
		double th = RS_PI * i / ST;
		for (int j = 0; j <= SL; ++j) {
			double ph = 2.0 * RS_PI * j / SL;
			pos[nv * 3 + 0] = (float)(sin(th) * cos(ph));
			pos[nv * 3 + 1] = (float)cos(th);
			pos[nv * 3 + 2] = (float)(sin(th) * sin(ph));
			nv++;
		}
	}
	for (int i = 0; i < ST; ++i) {
		for (int j = 0; j < SL; ++j) {
			uint32_t a = (uint32_t)(i * (SL + 1) + j), b = a + SL + 1;
			/* skip the zero-area triangles at the poles: keep the mesh clean here */
			if (i != 0) {
				idx[nt * 3 + 0] = a, idx[nt * 3 + 1] = a + 1, idx[nt * 3 + 2] = b;
				nt++;
			}
			if (i != ST - 1) {
				idx[nt * 3 + 0] = a + 1, idx[nt * 3 + 1] = b + 1,
				             idx[nt * 3 + 2] = b;
				nt++;
			}
		}
	}
	fx_mesh(scene, pos, nv, idx, nt, NULL, material);
}

static void lit_side_of_a_closed_sphere_has_no_speckles(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material m = {.diffuse = {0.8f, 0.8f, 0.8f}, .specular = 0.5f, .shininess = 20};
	add_sphere(fx.scene, fx_material(fx.scene, m));
	const double eye[3] = {0.3, 0.4, 4}, target[3] = {0, 0, 0}, lp[3] = {6, 5, 8};
	fx_camera(fx.scene, eye, target, SIZE);
	fx_light(fx.scene, lp[0], lp[1], lp[2], 1, 1, 1);
	fx_pack(&fx, RS_BVH_SAH);
	struct rs_trace_desc d = {.passes = 1};
	int lit = 0;
	for (uint32_t y = 0; y < SIZE; ++y) {
		for (uint32_t x = 0; x < SIZE; ++x) {
			struct rs_ray r;
			struct rs_trace_path p;
			rs_trace_camera_ray(rs_scene_camera(fx.scene), SIZE, SIZE, x + 0.5, y + 0.5,
			                    &r);
			assert_int_equal(
			    rs_trace_ray_path(fx.scene, &fx.packed, &d, &r, &p, NULL, NULL), RS_OK);
			if (isinf(p.depth))
				continue;
			double q[3], l[3], ql = 0.0, ll = 0.0, dot = 0.0;
			for (int a = 0; a < 3; ++a) {
				q[a] = r.origin[a] + p.depth * r.dir[a];
				l[a] = lp[a] - q[a];
				ql += q[a] * q[a];
				ll += l[a] * l[a];
				dot += q[a] * l[a];
			}
			/* Clearly on the lit side (facets deviate from the sphere by < 6 degrees):
			 * the feeler must get through, so the pixel is brighter than ambient
			 * (0.08) plus 0.8 x N.L >= 0.8 x 0.2. */
			if (dot / sqrt(ql * ll) > 0.3) {
				assert_true(p.rgb[0] > 0.08 + 0.16);
				lit++;
			}
		}
	}
	assert_true(lit > 50);
	fx_free(&fx);
}

static void degenerate_triangles_and_odd_lights_never_give_nan(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}, .specular = 1, .shininess = 0};
	struct rs_material glass = {.diffuse = {0.1f, 0.1f, 0.1f},
	                            .reflectance = 0.2f,
	                            .transmittance = 0.8f,
	                            .ior = 1.5f,
	                            .flags = RS_MATERIAL_FRESNEL};
	struct rs_material shiny = {.reflectance = 0.9f, .specular = 0.5f, .shininess = 1000};
	uint32_t g = fx_material(fx.scene, grey), gl = fx_material(fx.scene, glass),
	         sh = fx_material(fx.scene, shiny);
	fx_quad(fx.scene, 1, 0.0, -5, 5, 0, g);
	/* collinear, coincident, needle and sliver triangles in view, with zero normals */
	const float pos[] = {-1,         0.5f, 0,    0,    1,    0,    1,    1.5f,
	                     0, /* collinear */
	                     0.5f,       1,    0.5f, 0.5f, 1,    0.5f, 0.5f, 1,
	                     0.5f, /* a point */
	                     -2,         0.2f, 1,    2,    0.2f, 1,    2,    0.2f + 1e-7f,
	                     1, /* needle */
	                     -1,         2,    -1,   1,    2,    -1,   0,    2,
	                     -1 + 1e-30f}; /* sliver */
	const float zero_normals[12 * 3] = {0};
	const uint32_t idx[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
	fx_mesh(fx.scene, pos, 12, idx, 4, zero_normals, sh);
	fx_mesh(fx.scene, pos, 12, idx, 4, NULL, gl);
	const double lo[3] = {1, 0, 1}, hi[3] = {2, 1, 2};
	fx_box(fx.scene, lo, hi, gl);
	fx_light(fx.scene, 0, 0, 0, 1, 1, 1);       /* exactly on the floor */
	fx_light(fx.scene, 1.5, 0.5, 1.5, 1, 1, 1); /* inside the glass box */
	fx_light(fx.scene, 0, 6, 3, 1, 1, 1);
	const double eye[3] = {0, 3, 6}, target[3] = {0, 0.5, 0};
	fx_camera(fx.scene, eye, target, SIZE);
	fx_pack(&fx, RS_BVH_SAH);
	static float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	for (uint32_t test = 0; test < 2; ++test) {
		struct rs_trace_desc d = {.passes = 6, .triangle_test = test};
		assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, rgb, depth, NULL, NULL),
		                 RS_OK);
		for (int i = 0; i < SIZE * SIZE; ++i) {
			for (int c = 0; c < 3; ++c)
				assert_true(isfinite(rgb[i * 3 + c]) && rgb[i * 3 + c] >= 0.0f);
			assert_true(depth[i] > 0.0f); /* a distance or +inf, never NaN */
		}
	}
	fx_free(&fx);
}

/* R7's reach: the largest packed-frame coordinate of bounds (centre + half-diagonal),
 * environment box, lights and the eye; 0 for an empty scene. */
static void frame_reach_covers_bounds_environment_lights_and_eye(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_trace_frame f;
	struct rs_error err;
	fx_pack(&fx, RS_BVH_SAH);
	assert_int_equal(rs_trace_frame_init(fx.scene, &fx.packed, NULL, &f, &err), RS_OK);
	const double eye[3] = {0, 0, 5};
	assert_true(rs_trace_frame_reach(&f, eye) == 0.0); /* no geometry */
	fx_free(&fx);
	fx.scene = fx_scene();
	uint32_t mat = fx_material(fx.scene, (struct rs_material){.diffuse = {0.5f, 0.5f, 0.5f}});
	fx_rect(fx.scene, 2, 0.0, -1, 1, -1, 1, 0, mat); /* z = 0, x and y in [-1, 1] */
	fx_light(fx.scene, 0.0, 30.0, 0.0, 1, 1, 1);
	struct rs_environment env = {.half_size = 10.0};
	assert_int_equal(rs_scene_set_environment(fx.scene, &env, NULL), RS_OK);
	fx_pack(&fx, RS_BVH_SAH);
	assert_int_equal(rs_trace_frame_init(fx.scene, &fx.packed, NULL, &f, &err), RS_OK);
	assert_true(fabs(rs_trace_frame_reach(&f, eye) - 30.0) < 1e-12); /* the light */
	const double far_eye[3] = {0, -40, 0};
	assert_true(fabs(rs_trace_frame_reach(&f, far_eye) - 40.0) < 1e-12);
	fx_free(&fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(tilted_plane_far_from_the_origin_has_no_acne),
	    cmocka_unit_test(lit_side_of_a_closed_sphere_has_no_speckles),
	    cmocka_unit_test(degenerate_triangles_and_odd_lights_never_give_nan),
	    cmocka_unit_test(frame_reach_covers_bounds_environment_lights_and_eye),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
