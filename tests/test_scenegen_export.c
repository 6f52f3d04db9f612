/* rs_scene_export: OBJ + MTL + view file that rs_load_scene reads back as the same scene,
 * written atomically. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>
#include <sys/stat.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"
#include "test_load_fixture.h"

static struct rs_scene *build(enum rs_scenegen_kind kind, uint32_t cows)
{
	struct rs_scenegen_desc d = {.kind = kind, .cows = cows}; /* the shipped cow */
	struct rs_scene *s = NULL;

	assert_int_equal(rs_scenegen_build(&d, &s, NULL), RS_OK);
	return s;
}

static void assert_same_material(const struct rs_material *a, const struct rs_material *b)
{
	/* MTL stores 9 significant digits (float round trip); transmittance passes through
	 * d = 1 - t in double and back in float: 1e-6 covers one float rounding near 1. */
	for (int k = 0; k < 3; k++)
		assert_near(a->diffuse[k], b->diffuse[k], 1e-6);
	assert_near(a->specular, b->specular, 1e-6);
	assert_near(a->shininess, b->shininess, 1e-6);
	assert_near(a->reflectance, b->reflectance, 1e-6);
	assert_near(a->transmittance, b->transmittance, 1e-6);
	assert_near(a->ior == 0.0f ? 1.0f : a->ior, b->ior == 0.0f ? 1.0f : b->ior, 1e-6);
	assert_int_equal(a->flags, b->flags);
}

/* Export, load back with rs_load_scene and compare triangle by triangle. */
static void round_trip(struct rs_scene *a)
{
	struct fx fx;
	char obj[1024], view[1024];
	struct rs_scene *b = NULL;
	struct rs_error err;
	struct rs_environment ea, eb;
	struct rs_camera ca, cb;
	const float *pa = rs_scene_positions(a), *na = rs_scene_normals(a);
	const uint32_t *ia = rs_scene_indices(a), *ma = rs_scene_triangle_materials(a);
	const float *pb, *nb;
	const uint32_t *ib, *mb;

	fx_init(&fx);
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "scene.obj"));
	snprintf(view, sizeof(view), "%s", fx_path(&fx, "scene.json"));
	assert_int_equal(rs_scene_export(a, obj, view, &err), RS_OK);
	assert_int_equal(fx_count(&fx), 3); /* obj, mtl, json: no temporary files left */
	assert_int_equal(rs_load_scene(NULL, obj, &b, &err), RS_OK);
	fx_cleanup(&fx);
	pb = rs_scene_positions(b);
	nb = rs_scene_normals(b);
	ib = rs_scene_indices(b);
	mb = rs_scene_triangle_materials(b);
	assert_int_equal(rs_scene_triangle_count(b), rs_scene_triangle_count(a));
	for (size_t t = 0; t < rs_scene_triangle_count(a); t++) {
		for (int c = 0; c < 3; c++)
			for (int k = 0; k < 3; k++) {
				/* %.9g identifies a float exactly, but assimp's fast_atof is
				 * not correctly rounded (seen: 1 ulp off at 9.8e-5): allow 2
				 * ulps, relative (FLT_EPSILON * |x| >= 1 ulp of x). */
				float x = pa[3 * ia[3 * t + c] + k];

				assert_near(x, pb[3 * ib[3 * t + c] + k],
				            2.0 * FLT_EPSILON * fabsf(x));
				/* unit normals: 2 ulps of 1 plus renormalisation, 1e-6 */
				assert_near(na[3 * ia[3 * t + c] + k], nb[3 * ib[3 * t + c] + k],
				            1e-6);
			}
		assert_same_material(&rs_scene_materials(a)[ma[t]], &rs_scene_materials(b)[mb[t]]);
	}
	/* camera, lights, environment and ambient go through JSON doubles: bit-exact */
	rs_camera_resolve(rs_scene_camera(a), &ca);
	rs_camera_resolve(rs_scene_camera(b), &cb);
	assert_memory_equal(&ca, &cb, sizeof(ca));
	assert_int_equal(rs_scene_light_count(b), rs_scene_light_count(a));
	assert_memory_equal(rs_scene_lights(a), rs_scene_lights(b),
	                    rs_scene_light_count(a) * sizeof(struct rs_light));
	rs_scene_environment(a, &ea);
	rs_scene_environment(b, &eb);
	assert_memory_equal(&ea, &eb, sizeof(ea));
	assert_true(rs_scene_ambient(a) == rs_scene_ambient(b));
	rs_scene_destroy(&b);
}

static void cow2_round_trips(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 2);

	round_trip(s);
	rs_scene_destroy(&s);
}

static void box_round_trips(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);

	round_trip(s);
	rs_scene_destroy(&s);
}

/* Materials the generated scenes do not use: Fresnel flags and both refraction and
 * reflection on one surface. */
static void unusual_materials_round_trip(void **state)
{
	static const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	static const uint32_t idx[3] = {0, 1, 2};
	static const struct rs_material mats[2] = {
	    {.diffuse = {0.3f, 0.2f, 0.1f},
	     .reflectance = 0.4f,
	     .transmittance = 0.5f,
	     .ior = 1.33f,
	     .flags = RS_MATERIAL_FRESNEL},
	    {.diffuse = {0.7f, 0.7f, 0.7f},
	     .reflectance = 0.6f,
	     .specular = 0.2f,
	     .shininess = 8.0f,
	     .flags = RS_MATERIAL_FRESNEL},
	};
	struct rs_scene *s = NULL;
	struct rs_camera cam = {.eye = {0, 0, 5}, .target = {0, 0, 0}, .up = {0, 1, 0}};

	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	for (uint32_t m = 0; m < 2; m++) {
		uint32_t id;
		struct rs_mesh_desc d = {
		    .positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};

		assert_int_equal(rs_scene_add_material(s, &mats[m], &id, NULL), RS_OK);
		d.material = id;
		assert_int_equal(rs_scene_add_mesh(s, &d, NULL), RS_OK);
	}
	assert_int_equal(rs_scene_set_camera(s, &cam, NULL), RS_OK);
	round_trip(s);
	rs_scene_destroy(&s);
}

static void failed_export_leaves_nothing(void **state)
{
	struct fx fx;
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);
	struct rs_error err;
	char obj[1024];

	fx_init(&fx);
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "missing/scene.obj"));
	assert_int_equal(rs_scene_export(s, obj, NULL, &err), RS_ERR_IO);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "scene.mtl"));
	assert_int_equal(fx_count(&fx), 0);
	fx_cleanup(&fx);
	rs_scene_destroy(&s);
}

/* The OBJ and MTL used to be renamed into place before the view file was opened: an
 * unwritable view path left a half set behind. */
static void unwritable_view_leaves_no_obj_or_mtl(void **state)
{
	struct fx fx;
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);
	struct rs_error err;
	char obj[1024], view[1024];

	fx_init(&fx);
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "scene.obj"));
	snprintf(view, sizeof(view), "%s", fx_path(&fx, "missing/scene.json"));
	assert_int_equal(rs_scene_export(s, obj, view, &err), RS_ERR_IO);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "scene.json"));
	assert_int_equal(fx_count(&fx), 0);
	fx_cleanup(&fx);
	rs_scene_destroy(&s);
}

/* rename() over a FIFO or device replaces the node (as root: /dev/null itself). */
static void fifo_target_is_refused_and_kept(void **state)
{
	struct fx fx;
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);
	struct rs_error err;
	struct stat st;
	char obj[1024];

	fx_init(&fx);
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "scene.obj"));
	assert_int_equal(mkfifo(obj, 0600), 0);
	assert_int_equal(rs_scene_export(s, obj, NULL, &err), RS_ERR_IO);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "not a regular file"));
	assert_int_equal(stat(obj, &st), 0);
	assert_true(S_ISFIFO(st.st_mode));
	assert_int_equal(fx_count(&fx), 1); /* the FIFO only: no MTL, no temporaries */
	fx_cleanup(&fx);
	rs_scene_destroy(&s);
}

/* "--out-obj scene.json" made the view file overwrite the OBJ (same sidecar name) and
 * still reported success. */
static void clashing_names_are_refused(void **state)
{
	struct fx fx;
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);
	struct rs_error err;
	char obj[1024];

	fx_init(&fx);
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "scene.json"));
	assert_int_equal(rs_scene_export(s, obj, obj, &err), RS_ERR_INVALID);
	assert_one_line(&err);
	assert_non_null(strstr(err.message, "distinct"));
	snprintf(obj, sizeof(obj), "%s", fx_path(&fx, "scene.mtl"));
	assert_int_equal(rs_scene_export(s, obj, NULL, &err), RS_ERR_INVALID);
	assert_int_equal(fx_count(&fx), 0);
	fx_cleanup(&fx);
	rs_scene_destroy(&s);
}

/* An existing file is replaced as a whole (rename), not overwritten in place. */
static void export_replaces_existing_files(void **state)
{
	struct fx fx;
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0), *b = NULL;
	char obj[1024], junk[4096];
	FILE *f;

	memset(junk, '#', sizeof(junk));
	junk[sizeof(junk) - 1] = '\n';
	fx_init(&fx);
	fx_write_n(&fx, "scene.json", junk, sizeof(junk));
	snprintf(obj, sizeof(obj), "%s", fx_write_n(&fx, "scene.obj", junk, sizeof(junk)));
	assert_int_equal(rs_scene_export(s, obj, NULL, NULL), RS_OK);
	/* view_path NULL: the old junk sidecar stays, and is (correctly) refused */
	assert_int_equal(rs_load_scene(NULL, obj, &b, NULL), RS_ERR_PARSE);
	assert_int_equal(rs_load_view_file(fx_path(&fx, "scene.json"), s, NULL), RS_ERR_PARSE);
	f = fopen(obj, "rb");
	assert_non_null(f);
	assert_int_equal(fgetc(f), '#');
	assert_int_equal(fgetc(f), ' '); /* "# raystream scene", not the junk */
	fclose(f);
	fx_cleanup(&fx);
	rs_scene_destroy(&s);
}

static void empty_scene_is_refused(void **state)
{
	struct rs_scene *s = NULL;
	struct rs_error err;

	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	assert_int_equal(rs_scene_export(s, "/tmp/never-written.obj", NULL, &err), RS_ERR_INVALID);
	assert_one_line(&err);
	rs_scene_destroy(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cow2_round_trips),
	    cmocka_unit_test(box_round_trips),
	    cmocka_unit_test(unusual_materials_round_trip),
	    cmocka_unit_test(failed_export_leaves_nothing),
	    cmocka_unit_test(unwritable_view_leaves_no_obj_or_mtl),
	    cmocka_unit_test(fifo_target_is_refused_and_kept),
	    cmocka_unit_test(clashing_names_are_refused),
	    cmocka_unit_test(export_replaces_existing_files),
	    cmocka_unit_test(empty_scene_is_refused),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
