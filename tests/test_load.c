/* rs_load mesh files: the shipped cow, OBJ/MTL/PLY features, and every kind of bad input
 * (each from a small fixture generated into a temporary directory). */
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

static const char tri_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

static struct rs_scene *new_scene(void)
{
	struct rs_scene *s = NULL;

	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	return s;
}

/* Load `text` written as `name`; returns the status and leaves the scene in *out. */
static enum rs_status load_text(const struct rs_load_desc *desc, const char *name, const char *text,
                                struct rs_scene **out, struct rs_error *err)
{
	struct fx fx;
	enum rs_status st;

	fx_init(&fx);
	*out = new_scene();
	rs_error_clear(err);
	st = rs_load_mesh_file(desc, fx_write(&fx, name, text), *out, err);
	fx_cleanup(&fx);
	return st;
}

/* A rejected file: expected status, one-line message naming the file, scene untouched. */
static void expect_rejected(const char *name, const char *text, enum rs_status want,
                            const char *words)
{
	struct rs_scene *s;
	struct rs_error err;

	assert_int_equal(load_text(NULL, name, text, &s, &err), want);
	assert_int_equal(err.status, want);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, name));
	assert_non_null(strstr(err.message, words));
	assert_int_equal(rs_scene_triangle_count(s), 0);
	rs_scene_destroy(&s);
}

/* assimp must not drop or alter the cow: the file has 2903 vertices and 5804 faces, and
 * its bounds are the extreme coordinates written in it (1e-6: ~2 float ulps at 6). */
static void cow_loads_unchanged(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_bounds b;
	const float *n;

	assert_int_equal(rs_load_mesh_file(NULL, RS_DATA_DIR "/cow.obj", s, NULL), RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 5804);
	assert_int_equal(rs_scene_vertex_count(s), 2903);
	rs_scene_bounds(s, &b);
	assert_near(b.lo[0], -4.445835, 1e-6);
	assert_near(b.hi[0], 5.998088, 1e-6);
	assert_near(b.lo[1], -3.637036, 1e-6);
	assert_near(b.hi[1], 2.759720, 1e-6);
	assert_near(b.lo[2], -1.701405, 1e-6);
	assert_near(b.hi[2], 1.701405, 1e-6);
	/* No normals in the file: computed ones are unit length (float rounding: 1e-5). */
	n = rs_scene_normals(s);
	for (size_t v = 0; v < rs_scene_vertex_count(s); v++)
		assert_near(sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] +
		                 n[3 * v + 2] * n[3 * v + 2]),
		            1.0, 1e-5);
	/* No material in the file: the default 0.8 grey. */
	assert_int_equal(rs_scene_material_count(s), 1);
	assert_true(rs_scene_materials(s)[0].diffuse[1] == 0.8f);
	rs_scene_destroy(&s);
}

/* Every triangle of the cow, corner by corner, against a direct read of the file's "v" and
 * "f a b c" lines: nothing dropped, reordered or moved. strtod is correctly rounded,
 * assimp's fast_atof not always: 2 float ulps, relative. */
static void cow_matches_a_direct_parse(void **state)
{
	static float v[2903][3];
	struct rs_scene *s = new_scene();
	FILE *f = fopen(RS_DATA_DIR "/cow.obj", "r");
	char line[256];
	size_t nv = 0, t = 0;
	const float *p;
	const uint32_t *idx;

	assert_non_null(f);
	assert_int_equal(rs_load_mesh_file(NULL, RS_DATA_DIR "/cow.obj", s, NULL), RS_OK);
	p = rs_scene_positions(s);
	idx = rs_scene_indices(s);
	while (fgets(line, sizeof(line), f) != NULL) {
		unsigned a[3];

		if (line[0] == 'v' && line[1] == ' ') {
			double x, y, z;

			assert_true(nv < 2903);
			assert_int_equal(sscanf(line + 2, "%lf %lf %lf", &x, &y, &z), 3);
			v[nv][0] = (float)x, v[nv][1] = (float)y, v[nv][2] = (float)z;
			nv++;
		} else if (line[0] == 'f' && line[1] == ' ') {
			assert_int_equal(sscanf(line + 2, "%u %u %u", &a[0], &a[1], &a[2]), 3);
			assert_true(t < rs_scene_triangle_count(s));
			for (int c = 0; c < 3; c++)
				for (int k = 0; k < 3; k++) {
					float want = v[a[c] - 1][k];

					assert_near(p[3 * idx[3 * t + c] + k], want,
					            2.0 * FLT_EPSILON * fabsf(want));
				}
			t++;
		}
	}
	fclose(f);
	assert_int_equal(t, rs_scene_triangle_count(s));
	rs_scene_destroy(&s);
}

static void quad_is_triangulated(void **state)
{
	struct rs_scene *s;
	struct rs_error err;

	assert_int_equal(load_text(NULL, "quad.obj",
	                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", &s, &err),
	                 RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 2);
	assert_int_equal(rs_scene_vertex_count(s), 4);
	rs_scene_destroy(&s);
}

/* The file's normal is tilted away from the face normal (0,0,1): kept means we see it. */
static const char tilted_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0.6 0.8\n"
                                 "f 1//1 2//1 3//1\n";

static void file_normals_are_kept(void **state)
{
	struct rs_scene *s;
	struct rs_error err;
	const float *n;

	assert_int_equal(load_text(NULL, "n.obj", tilted_obj, &s, &err), RS_OK);
	n = rs_scene_normals(s);
	for (int v = 0; v < 3; v++) {
		assert_near(n[3 * v + 1], 0.6, 1e-6); /* float rounding of 0.6, 0.8 */
		assert_near(n[3 * v + 2], 0.8, 1e-6);
	}
	rs_scene_destroy(&s);
}

static void ignored_file_normals_are_computed(void **state)
{
	struct rs_load_desc desc = {.ignore_file_normals = 1};
	struct rs_scene *s;
	struct rs_error err;
	const float *n;

	assert_int_equal(load_text(&desc, "n.obj", tilted_obj, &s, &err), RS_OK);
	n = rs_scene_normals(s);
	for (int v = 0; v < 3; v++) {
		assert_near(n[3 * v + 1], 0.0, 1e-6);
		assert_near(n[3 * v + 2], 1.0, 1e-6);
	}
	rs_scene_destroy(&s);
}

/* MTL keys map as documented in rs_load.h; float fields compared at float precision. */
static void mtl_materials_are_mapped(void **state)
{
	struct fx fx;
	struct rs_scene *s = new_scene();
	const struct rs_material *m;
	const uint32_t *tm;

	fx_init(&fx);
	fx_write(&fx, "m.mtl",
	         "newmtl glass\nKd 0.1 0.2 0.3\nKs 0.3 0.6 0.9\nNs 32\nNi 1.5\nd 0.25\n"
	         "Pm 0.125\nillum 7\n"
	         "newmtl chrome\nKd 0 0 0\nKs 0.5 0.5 0.5\nillum 3\n");
	fx_write(&fx, "m.obj",
	         "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
	         "usemtl chrome\nf 1 2 3\nusemtl glass\nf 2 4 3\n");
	assert_int_equal(rs_load_mesh_file(NULL, fx.path, s, NULL), RS_OK);
	fx_cleanup(&fx);
	assert_int_equal(rs_scene_triangle_count(s), 2);
	assert_int_equal(rs_scene_material_count(s), 2);
	m = rs_scene_materials(s);
	tm = rs_scene_triangle_materials(s);
	/* chrome: no Pm, illum 3 -> reflectance = mean Ks; no Fresnel */
	assert_near(m[tm[0]].reflectance, 0.5, 1e-6);
	assert_int_equal(m[tm[0]].flags & RS_MATERIAL_FRESNEL, 0);
	/* glass */
	assert_near(m[tm[1]].diffuse[2], 0.3, 1e-6);
	assert_near(m[tm[1]].specular, 0.6, 1e-6);
	assert_near(m[tm[1]].shininess, 32.0, 1e-6);
	assert_near(m[tm[1]].ior, 1.5, 1e-6);
	assert_near(m[tm[1]].transmittance, 0.75, 1e-6);
	assert_near(m[tm[1]].reflectance, 0.125, 1e-6);
	assert_int_equal(m[tm[1]].flags & RS_MATERIAL_FRESNEL, RS_MATERIAL_FRESNEL);
	rs_scene_destroy(&s);
}

/* A negative colour is refused before the scene changes. */
static void bad_mtl_value_is_bad_data(void **state)
{
	struct fx fx;
	struct rs_scene *s = new_scene();
	struct rs_error err;

	fx_init(&fx);
	fx_write(&fx, "neg.mtl", "newmtl neg\nKd -1 0 0\n");
	fx_write(&fx, "neg.obj",
	         "mtllib neg.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl neg\n"
	         "f 1 2 3\n");
	assert_int_equal(rs_load_mesh_file(NULL, fx.path, s, &err), RS_ERR_BAD_DATA);
	fx_cleanup(&fx);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "bad material"));
	assert_int_equal(rs_scene_material_count(s), 0);
	assert_int_equal(rs_scene_triangle_count(s), 0);
	rs_scene_destroy(&s);
}

static void default_material_is_applied(void **state)
{
	struct rs_material red = {.diffuse = {1.0f, 0.0f, 0.0f}};
	struct rs_load_desc desc = {.default_material = &red};
	struct rs_scene *s;
	struct rs_error err;

	assert_int_equal(load_text(&desc, "t.obj", tri_obj, &s, &err), RS_OK);
	assert_int_equal(rs_scene_material_count(s), 1);
	assert_true(rs_scene_materials(s)[0].diffuse[0] == 1.0f &&
	            rs_scene_materials(s)[0].diffuse[1] == 0.0f);
	rs_scene_destroy(&s);
}

static const char ply_head[] = "ply\nformat ascii 1.0\nelement vertex 3\n"
                               "property float x\nproperty float y\nproperty float z\n";

static void ply_ascii_with_normals_loads(void **state)
{
	char text[512];
	struct rs_scene *s;
	struct rs_error err;
	const float *n, *p;

	snprintf(text, sizeof(text),
	         "%sproperty float nx\nproperty float ny\nproperty float nz\nelement face 1\n"
	         "property list uchar int vertex_indices\nend_header\n"
	         "0 0 0 0 0.6 0.8\n2 0 0 0 0.6 0.8\n0 3 0 0 0.6 0.8\n3 0 1 2\n",
	         ply_head);
	assert_int_equal(load_text(NULL, "a.ply", text, &s, &err), RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 1);
	p = rs_scene_positions(s);
	assert_true(p[3 * rs_scene_indices(s)[1]] == 2.0f);
	assert_true(p[3 * rs_scene_indices(s)[2] + 1] == 3.0f);
	n = rs_scene_normals(s);
	assert_near(n[1], 0.6, 1e-6);
	rs_scene_destroy(&s);
}

static void ply_binary_quad_loads(void **state)
{
	static const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
	                           "property float x\nproperty float y\nproperty float z\n"
	                           "element face 1\nproperty list uchar int vertex_indices\n"
	                           "end_header\n";
	const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
	const unsigned char count = 4;
	const int32_t idx[4] = {0, 1, 2, 3};
	unsigned char buf[512];
	size_t n = 0;
	struct fx fx;
	struct rs_scene *s = new_scene();
	const uint16_t probe = 1;

	/* The binary payload is written in host order: skip on big-endian hosts. */
	if (*(const unsigned char *)&probe != 1)
		skip();
	memcpy(buf + n, head, sizeof(head) - 1), n += sizeof(head) - 1;
	memcpy(buf + n, v, sizeof(v)), n += sizeof(v);
	memcpy(buf + n, &count, 1), n += 1;
	memcpy(buf + n, idx, sizeof(idx)), n += sizeof(idx);
	fx_init(&fx);
	assert_int_equal(rs_load_mesh_file(NULL, fx_write_n(&fx, "b.ply", buf, n), s, NULL), RS_OK);
	fx_cleanup(&fx);
	assert_int_equal(rs_scene_triangle_count(s), 2);
	rs_scene_destroy(&s);
}

static void missing_file_is_not_found(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(rs_load_mesh_file(NULL, "/nonexistent/rs_none.obj", s, &err),
	                 RS_ERR_NOT_FOUND);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "rs_none.obj"));
	rs_scene_destroy(&s);
}

static void directory_is_rejected(void **state)
{
	struct rs_scene *s = new_scene();
	struct rs_error err;

	assert_int_equal(rs_load_mesh_file(NULL, RS_DATA_DIR, s, &err), RS_ERR_IO);
	assert_one_line(&err);
	rs_scene_destroy(&s);
}

static void malformed_obj_is_parse_error(void **state)
{
	expect_rejected("junk.obj", "garbage here\x01\x02 !!\nf a b c\n", RS_ERR_PARSE,
	                "cannot import");
}

static void empty_file_is_parse_error(void **state)
{
	expect_rejected("empty.obj", "", RS_ERR_PARSE, "cannot import");
}

static void nan_vertex_is_bad_data(void **state)
{
	expect_rejected("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", RS_ERR_BAD_DATA,
	                "non-finite");
}

static void infinite_vertex_is_bad_data(void **state)
{
	expect_rejected("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n", RS_ERR_BAD_DATA,
	                "non-finite");
}

static void nan_normal_is_bad_data(void **state)
{
	expect_rejected("nn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan 0 1\nf 1//1 2//1 3//1\n",
	                RS_ERR_BAD_DATA, "non-finite normal");
}

/* assimp's OBJ reader refuses these itself: the message passes its reason on. */
static void obj_index_out_of_range_is_rejected(void **state)
{
	expect_rejected("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", RS_ERR_PARSE,
	                "index out of range");
}

/* assimp's PLY reader drops the bad index and keeps a 2-corner face: caught by us. */
static void ply_index_out_of_range_is_rejected(void **state)
{
	char text[512];

	snprintf(text, sizeof(text),
	         "%selement face 2\nproperty list uchar int vertex_indices\nend_header\n"
	         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n",
	         ply_head);
	expect_rejected("oor.ply", text, RS_ERR_BAD_DATA, "out of range");
}

static void vertices_only_is_no_triangles(void **state)
{
	expect_rejected("v.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", RS_ERR_BAD_DATA, "no triangles");
}

static void lines_only_is_no_triangles(void **state)
{
	expect_rejected("l.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n", RS_ERR_BAD_DATA,
	                "no triangles");
}

/* An OBJ cut off mid-line: assimp dropped the short face or vertex without a word (issue
 * 18). Named by element and line; a backslash continues a line as OBJ allows. */
static void obj_cut_mid_line_is_refused(void **state)
{
	expect_rejected("f2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4",
	                RS_ERR_PARSE, "line 6: face with 2 vertices");
	expect_rejected("f1.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n  f 1\n", RS_ERR_PARSE,
	                "line 5: face with 1 vertices");
	expect_rejected("v2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1\nf 1 2 3\n", RS_ERR_PARSE,
	                "line 4: vertex with 2 coordinates");
	struct rs_scene *s;
	assert_int_equal(
	    load_text(NULL, "cont.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n 3\n", &s, NULL),
	    RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 1);
	rs_scene_destroy(&s);
}

static void ply_without_faces_is_no_triangles(void **state)
{
	char text[256];

	snprintf(text, sizeof(text), "%send_header\n0 0 0\n1 0 0\n0 1 0\n", ply_head);
	expect_rejected("p.ply", text, RS_ERR_BAD_DATA, "no triangles");
}

/* assimp reserves memory for every declared element before reading one: a 200-byte file
 * declaring 3*10^8 faces made it take over 8 GB. Such headers are refused up front. */
static void ply_face_count_beyond_file_size_is_refused(void **state)
{
	char text[512];

	snprintf(text, sizeof(text),
	         "%selement face 300000000\nproperty list uchar int vertex_indices\n"
	         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	         ply_head);
	expect_rejected("lie.ply", text, RS_ERR_PARSE, "'face'");
}

static void binary_ply_vertex_count_beyond_file_size_is_refused(void **state)
{
	/* 4e9 vertices of 12 bytes each, and no payload at all. */
	expect_rejected("lie_bin.ply",
	                "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
	                "property float x\nproperty float y\nproperty float z\nelement face 1\n"
	                "property list uchar int vertex_indices\nend_header\n",
	                RS_ERR_PARSE, "'vertex'");
}

/* The guard must not refuse a file that holds exactly what it declares, even without a
 * final newline (ASCII: the smallest element is one character and a separator per
 * property, the last line's separator may be missing). */
static void ply_with_exact_counts_and_no_final_newline_loads(void **state)
{
	char text[512];
	struct rs_scene *s;
	struct rs_error err;

	snprintf(text, sizeof(text),
	         "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
	         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2",
	         ply_head);
	assert_int_equal(load_text(NULL, "exact.ply", text, &s, &err), RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 1);
	rs_scene_destroy(&s);
}

/* assimp's PLY reader never returned from a header whose end_header line is misspelt. */
static void ply_without_end_header_is_refused(void **state)
{
	char text[512];

	snprintf(text, sizeof(text),
	         "%selement face 1\nproperty list uchar int vertex_indices\nen4_header\n"
	         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	         ply_head);
	expect_rejected("noend.ply", text, RS_ERR_PARSE, "end_header");
}

/* A face list of length 0 made assimp's Triangulate step abort() on an assertion. */
static void ply_empty_face_is_refused(void **state)
{
	char text[512];

	snprintf(text, sizeof(text),
	         "%selement face 2\nproperty list uchar int vertex_indices\nend_header\n"
	         "0 0 0\n1 0 0\n0 1 0\n0\n0\n",
	         ply_head);
	expect_rejected("emptyface.ply", text, RS_ERR_PARSE, "no vertices");
}

static void too_large_file_is_refused(void **state)
{
	struct rs_load_desc desc = {.max_file_bytes = 16};
	struct rs_scene *s;
	struct rs_error err;

	/* tri_obj is 32 bytes: over the 16-byte limit, refused before parsing. */
	assert_int_equal(load_text(&desc, "big.obj", tri_obj, &s, &err), RS_ERR_LIMIT);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "too large"));
	assert_int_equal(rs_scene_triangle_count(s), 0);
	rs_scene_destroy(&s);
}

/* Meshes go in after all are checked: a bad second object leaves nothing behind. */
static void bad_second_object_adds_nothing(void **state)
{
	expect_rejected("two.obj",
	                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv inf 1 1\no a\nf 1 2 3\no b\nf 1 2 4\n",
	                RS_ERR_BAD_DATA, "non-finite");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cow_loads_unchanged),
	    cmocka_unit_test(cow_matches_a_direct_parse),
	    cmocka_unit_test(quad_is_triangulated),
	    cmocka_unit_test(obj_cut_mid_line_is_refused),
	    cmocka_unit_test(file_normals_are_kept),
	    cmocka_unit_test(ignored_file_normals_are_computed),
	    cmocka_unit_test(mtl_materials_are_mapped),
	    cmocka_unit_test(bad_mtl_value_is_bad_data),
	    cmocka_unit_test(default_material_is_applied),
	    cmocka_unit_test(ply_ascii_with_normals_loads),
	    cmocka_unit_test(ply_binary_quad_loads),
	    cmocka_unit_test(missing_file_is_not_found),
	    cmocka_unit_test(directory_is_rejected),
	    cmocka_unit_test(malformed_obj_is_parse_error),
	    cmocka_unit_test(empty_file_is_parse_error),
	    cmocka_unit_test(nan_vertex_is_bad_data),
	    cmocka_unit_test(infinite_vertex_is_bad_data),
	    cmocka_unit_test(nan_normal_is_bad_data),
	    cmocka_unit_test(obj_index_out_of_range_is_rejected),
	    cmocka_unit_test(ply_index_out_of_range_is_rejected),
	    cmocka_unit_test(vertices_only_is_no_triangles),
	    cmocka_unit_test(lines_only_is_no_triangles),
	    cmocka_unit_test(ply_without_faces_is_no_triangles),
	    cmocka_unit_test(ply_face_count_beyond_file_size_is_refused),
	    cmocka_unit_test(binary_ply_vertex_count_beyond_file_size_is_refused),
	    cmocka_unit_test(ply_with_exact_counts_and_no_final_newline_loads),
	    cmocka_unit_test(ply_without_end_header_is_refused),
	    cmocka_unit_test(ply_empty_face_is_refused),
	    cmocka_unit_test(too_large_file_is_refused),
	    cmocka_unit_test(bad_second_object_adds_nothing),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
