/* rs_load: vertices are welded only when exactly equal, so small models keep every vertex
 * where the file puts it (assimp's own welding merged positions up to 1e-5 apart). */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <cmocka.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"

#include "test_load_fixture.h"

/* A small model at `scale`: a 3 x 3 grid of vertices 1 unit apart (8 triangles sharing
 * them), a thin sliver 0.001 units high, and a second "v" line repeating vertex 1 exactly,
 * used by one more triangle. Distinct vertices are 0.001 * scale or more apart. */
#define MODEL_VERTS 13
static void model(double scale, double v[MODEL_VERTS][3], char *text, size_t size)
{
	size_t n = 0, len = 0;
	for (int j = 0; j < 3; j++)
		for (int i = 0; i < 3; i++, n++) {
			v[n][0] = i * scale;
			v[n][1] = j * scale;
			v[n][2] = 0.25 * i * j * scale;
		}
	const double sliver[3][3] = {{3, 0, 0}, {5, 0, 0}, {4, 0.001, 0}};
	for (int k = 0; k < 3; k++, n++)
		for (int a = 0; a < 3; a++)
			v[n][a] = sliver[k][a] * scale;
	for (int a = 0; a < 3; a++)
		v[n][a] = v[1][a]; /* exact duplicate of vertex 1 (file index 2) */
	for (size_t k = 0; k < MODEL_VERTS; k++)
		len += (size_t)snprintf(text + len, size - len, "v %.9g %.9g %.9g\n", v[k][0],
		                        v[k][1], v[k][2]);
	static const char faces[] = "f 1 2 5\nf 1 5 4\nf 2 3 6\nf 2 6 5\nf 4 5 8\nf 4 8 7\n"
	                            "f 5 6 9\nf 5 9 8\nf 10 11 12\nf 13 3 12\n";
	snprintf(text + len, size - len, "%s", faces);
}

static double area(const float *p0, const float *p1, const float *p2)
{
	double e[2][3], c[3];
	for (int a = 0; a < 3; a++) {
		e[0][a] = (double)p1[a] - p0[a];
		e[1][a] = (double)p2[a] - p0[a];
	}
	c[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
	c[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
	c[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
	return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

static void small_models_keep_every_vertex(void **state)
{
	const double scales[2] = {1e-4, 1e-6};
	for (int s = 0; s < 2; s++) {
		double v[MODEL_VERTS][3];
		char text[2048];
		struct fx fx;
		struct rs_scene *scene = NULL;
		struct rs_error err;
		model(scales[s], v, text, sizeof text);
		fx_init(&fx);
		assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
		enum rs_status st =
		    rs_load_mesh_file(NULL, fx_write(&fx, "m.obj", text), scene, &err);
		fx_cleanup(&fx);
		if (st != RS_OK)
			fail_msg("%s", err.message);
		/* 13 "v" lines, one an exact repeat: 12 distinct positions, welded to 12 */
		assert_int_equal(rs_scene_vertex_count(scene), MODEL_VERTS - 1);
		assert_int_equal(rs_scene_triangle_count(scene), 10);
		/* every corner where the file puts it (assimp's parser: 2 float ulps) */
		static const unsigned f[10][3] = {{1, 2, 5},    {1, 5, 4},  {2, 3, 6}, {2, 6, 5},
		                                  {4, 5, 8},    {4, 8, 7},  {5, 6, 9}, {5, 9, 8},
		                                  {10, 11, 12}, {13, 3, 12}};
		const float *p = rs_scene_positions(scene);
		const uint32_t *idx = rs_scene_indices(scene);
		for (int t = 0; t < 10; t++) {
			for (int k = 0; k < 3; k++)
				for (int a = 0; a < 3; a++) {
					float want = (float)v[f[t][k] - 1][a];
					assert_true(fabsf(p[3 * idx[3 * t + k] + a] - want) <=
					            2.0f * FLT_EPSILON * fabsf(want));
				}
			/* no triangle collapsed: area within 1e-3 of the file's */
			double got = area(&p[3 * idx[3 * t]], &p[3 * idx[3 * t + 1]],
			                  &p[3 * idx[3 * t + 2]]);
			float w[3][3];
			for (int k = 0; k < 3; k++)
				for (int a = 0; a < 3; a++)
					w[k][a] = (float)v[f[t][k] - 1][a];
			double want = area(w[0], w[1], w[2]);
			assert_true(want > 0.0 && fabs(got - want) <= 1e-3 * want);
		}
		/* the repeated "v" line shares vertex 1's index */
		assert_int_equal(idx[3 * 9], idx[1]);
		rs_scene_destroy(&scene);
	}
}

/* A flat-shaded cube: 8 "v" lines, 6 "vn" lines, each face's corners with its face normal.
 * With the file's normals a corner is welded only with corners of the same normal (24
 * vertices: 8 positions x 3 faces); without them, by position alone (8 vertices). */
static void normals_take_part_in_the_weld(void **state)
{
	static const char cube[] =
	    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
	    "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
	    "f 1//1 3//1 2//1\nf 1//1 4//1 3//1\nf 5//2 6//2 7//2\nf 5//2 7//2 8//2\n"
	    "f 1//3 2//3 6//3\nf 1//3 6//3 5//3\nf 4//4 7//4 3//4\nf 4//4 8//4 7//4\n"
	    "f 1//5 5//5 8//5\nf 1//5 8//5 4//5\nf 2//6 3//6 7//6\nf 2//6 7//6 6//6\n";
	for (int ignore = 0; ignore < 2; ignore++) {
		struct fx fx;
		struct rs_scene *scene = NULL;
		struct rs_error err;
		struct rs_load_desc desc = {.ignore_file_normals = ignore != 0};
		fx_init(&fx);
		assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
		enum rs_status st =
		    rs_load_mesh_file(&desc, fx_write(&fx, "cube.obj", cube), scene, &err);
		fx_cleanup(&fx);
		if (st != RS_OK)
			fail_msg("%s", err.message);
		assert_int_equal(rs_scene_triangle_count(scene), 12);
		assert_int_equal(rs_scene_vertex_count(scene), ignore ? 8 : 24);
		rs_scene_destroy(&scene);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(small_models_keep_every_vertex),
	    cmocka_unit_test(normals_take_part_in_the_weld),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
