/* rs_scene instances: prototypes are not drawn, instances bake into world space like the same
 * geometry given in world space (rotated, scaled, non-uniformly scaled, mirrored, far from the
 * origin), and bad instances are refused with a status and nothing added. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_scene.h"

/* Unit cube, each face split into two triangles, wound outward. */
static const float cube_pos[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                      0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_idx[12 * 3] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                          3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static struct rs_scene *make_scene(uint32_t *proto)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	struct rs_material m = {.diffuse = {0.5f, 0.5f, 0.5f}};
	assert_int_equal(rs_scene_add_material(scene, &m, NULL, NULL), RS_OK);
	assert_int_equal(rs_scene_add_material(scene, &m, NULL, NULL), RS_OK);
	struct rs_mesh_desc mesh = {
	    .positions = cube_pos, .vertex_count = 8, .indices = cube_idx, .triangle_count = 12};
	*proto = 99;
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, proto, NULL), RS_OK);
	assert_int_equal(*proto, 0);
	return scene;
}

static void prototype_is_not_drawn(void **state)
{
	uint32_t proto;
	struct rs_scene *scene = make_scene(&proto);
	assert_int_equal(rs_scene_triangle_count(scene), 0);
	assert_int_equal(rs_scene_prototype_count(scene), 1);
	assert_int_equal(rs_scene_instance_count(scene), 0);
	rs_scene_destroy(&scene);
}

/* A zero descriptor is the identity instance of prototype 0: the same arrays as add_mesh. */
static void zero_descriptor_is_the_mesh_itself(void **state)
{
	uint32_t proto, id = 99;
	struct rs_scene *scene = make_scene(&proto), *flat = make_scene(&proto);
	assert_int_equal(rs_scene_add_instance(scene, &(struct rs_instance_desc){0}, &id, NULL),
	                 RS_OK);
	assert_int_equal(id, 0);
	struct rs_mesh_desc mesh = {
	    .positions = cube_pos, .vertex_count = 8, .indices = cube_idx, .triangle_count = 12};
	assert_int_equal(rs_scene_add_mesh(flat, &mesh, NULL), RS_OK);
	assert_int_equal(rs_scene_triangle_count(scene), 12);
	assert_memory_equal(rs_scene_positions_f64(scene), rs_scene_positions_f64(flat),
	                    8 * 3 * sizeof(double));
	assert_memory_equal(rs_scene_normals(scene), rs_scene_normals(flat), 8 * 3 * sizeof(float));
	assert_memory_equal(rs_scene_indices(scene), rs_scene_indices(flat), 36 * sizeof(uint32_t));
	const struct rs_scene_instance *inst = rs_scene_instances(scene);
	assert_true(inst[0].transform[0][0] == 1.0 && inst[0].transform[1][1] == 1.0 &&
	            inst[0].transform[2][2] == 1.0 && inst[0].transform[0][3] == 0.0);
	assert_int_equal(inst[0].first_triangle, 0);
	assert_int_equal(inst[0].triangle_count, 12);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&flat);
}

static void apply(const double m[3][4], const double p[3], double out[3])
{
	for (int r = 0; r < 3; ++r)
		out[r] = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
}

/* Each baked vertex is M p; the inverse record maps it back; each triangle's geometric normal
 * points out of the transformed cube (away from its centre) and agrees with the vertex
 * normals' side, also for mirrors; vertex normals are the inverse transpose's. */
static void check_instance(const double m[3][4], double tol)
{
	uint32_t proto;
	struct rs_scene *scene = make_scene(&proto);
	struct rs_instance_desc desc = {.mesh = proto, .override_material = true, .material = 1};
	memcpy(desc.transform, m, sizeof desc.transform);
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, NULL), RS_OK);
	const struct rs_scene_instance *inst = rs_scene_instances(scene);
	const double *pos = rs_scene_positions_f64(scene);
	const float *nrm = rs_scene_normals(scene);
	const uint32_t *idx = rs_scene_indices(scene);
	double centre[3], half[3] = {0.5, 0.5, 0.5};
	apply(m, half, centre);
	for (int i = 0; i < 8; ++i) {
		double o[3] = {cube_pos[i * 3], cube_pos[i * 3 + 1], cube_pos[i * 3 + 2]}, w[3],
		       back[3];
		apply(m, o, w);
		apply(inst[0].inverse, pos + i * 3, back);
		for (int a = 0; a < 3; ++a) {
			assert_true(pos[i * 3 + a] == w[a]);
			assert_true(fabs(back[a] - o[a]) <= tol);
		}
		/* the corner normal leaves the transformed cube: n . (p - centre) > 0 */
		double d = 0.0;
		for (int a = 0; a < 3; ++a)
			d += nrm[i * 3 + a] * (pos[i * 3 + a] - centre[a]);
		assert_true(d > 0.0);
	}
	for (int t = 0; t < 12; ++t) {
		assert_int_equal(rs_scene_triangle_materials(scene)[t], 1);
		const double *a = pos + idx[t * 3] * 3, *b = pos + idx[t * 3 + 1] * 3,
		             *c = pos + idx[t * 3 + 2] * 3;
		double e1[3], e2[3], g[3], tc[3];
		for (int k = 0; k < 3; ++k) {
			e1[k] = b[k] - a[k];
			e2[k] = c[k] - a[k];
			tc[k] = (a[k] + b[k] + c[k]) / 3.0 - centre[k];
		}
		g[0] = e1[1] * e2[2] - e1[2] * e2[1];
		g[1] = e1[2] * e2[0] - e1[0] * e2[2];
		g[2] = e1[0] * e2[1] - e1[1] * e2[0];
		/* the prototype is wound outward (e1 x e2 leaves the cube); so is every instance */
		assert_true(g[0] * tc[0] + g[1] * tc[1] + g[2] * tc[2] > 0.0);
	}
	rs_scene_destroy(&scene);
}

static void transformed_instances_bake_as_world_geometry(void **state)
{
	const double c = cos(0.7), s = sin(0.7);
	const double rotated_scaled[3][4] = {
	    {2 * c, 0, 2 * s, 1}, {0, 2, 0, -3}, {-2 * s, 0, 2 * c, 4}};
	const double nonuniform[3][4] = {{3, 0.5, 0, 0}, {0, 0.25, 0, 0}, {0, 0, 7, 0}};
	const double mirrored[3][4] = {{-1, 0, 0, 2}, {0, 1, 0, 0}, {0, 0, 1, 0}};
	const double mirrored_rotated[3][4] = {{c, 0, s, 0}, {0, -1.5, 0, 0}, {-s, 0, c, 0}};
	const double far[3][4] = {{1, 0, 0, 1e6}, {0, 1, 0, -2e6}, {0, 0, 1, 3e6}};
	check_instance(rotated_scaled, 1e-12);
	check_instance(nonuniform, 1e-12);
	check_instance(mirrored, 1e-12);
	check_instance(mirrored_rotated, 1e-12);
	check_instance(far, 1e-9);
}

/* The prototype's winding (side of its geometric normals) is what a mirror must keep. */
static void mirrored_instance_keeps_the_winding_side(void **state)
{
	uint32_t proto;
	struct rs_scene *scene = make_scene(&proto);
	const double mirror[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, -1, 0}};
	struct rs_instance_desc desc = {.mesh = proto};
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, NULL), RS_OK);
	memcpy(desc.transform, mirror, sizeof mirror);
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, NULL), RS_OK);
	const uint32_t *idx = rs_scene_indices(scene);
	/* the mirror swaps v1 and v2 of every triangle (offset by the first instance's 8) */
	for (int t = 0; t < 12; ++t) {
		assert_int_equal(idx[(12 + t) * 3], 8 + cube_idx[t * 3]);
		assert_int_equal(idx[(12 + t) * 3 + 1], 8 + cube_idx[t * 3 + 2]);
		assert_int_equal(idx[(12 + t) * 3 + 2], 8 + cube_idx[t * 3 + 1]);
	}
	rs_scene_destroy(&scene);
}

static void bad_instances_are_refused(void **state)
{
	uint32_t proto;
	struct rs_scene *scene = make_scene(&proto);
	struct rs_error err = {0};
	struct rs_instance_desc desc = {.mesh = 1};
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "prototype mesh 1"));
	desc = (struct rs_instance_desc){.override_material = true, .material = 2};
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "material 2"));
	const double singular[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {1, 1, 0, 0}};
	const double flat[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1e-13, 0}};
	desc = (struct rs_instance_desc){0};
	memcpy(desc.transform, singular, sizeof singular);
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "singular"));
	memcpy(desc.transform, flat, sizeof flat);
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "singular"));
	const double values[] = {NAN, INFINITY, -INFINITY};
	for (int k = 0; k < 3; ++k) {
		desc = (struct rs_instance_desc){0};
		desc.transform[k][k] = 1.0;
		desc.transform[k][3] = values[k];
		assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
		assert_non_null(strstr(err.message, "NaN or infinite"));
	}
	/* a vertex pushed beyond the float range */
	desc = (struct rs_instance_desc){0};
	desc.transform[0][0] = desc.transform[1][1] = desc.transform[2][2] = 1e38;
	desc.transform[0][3] = 3e38;
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_ERR_BAD_DATA);
	assert_int_equal(rs_scene_triangle_count(scene), 0);
	assert_int_equal(rs_scene_instance_count(scene), 0);
	/* a tiny but regular scale is kept: the singularity test is relative */
	desc = (struct rs_instance_desc){0};
	desc.transform[0][0] = desc.transform[1][1] = desc.transform[2][2] = 1e-6;
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, &err), RS_OK);
	rs_scene_destroy(&scene);
}

static void instances_respect_the_triangle_limit(void **state)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(
	    rs_scene_create(&(struct rs_scene_desc){.max_triangles = 20}, &scene, NULL), RS_OK);
	struct rs_material m = {0};
	assert_int_equal(rs_scene_add_material(scene, &m, NULL, NULL), RS_OK);
	struct rs_mesh_desc mesh = {
	    .positions = cube_pos, .vertex_count = 8, .indices = cube_idx, .triangle_count = 12};
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, NULL, NULL), RS_OK);
	struct rs_instance_desc desc = {0};
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, NULL), RS_OK);
	assert_int_equal(rs_scene_add_instance(scene, &desc, NULL, NULL), RS_ERR_LIMIT);
	assert_int_equal(rs_scene_instance_count(scene), 1);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(prototype_is_not_drawn),
	    cmocka_unit_test(zero_descriptor_is_the_mesh_itself),
	    cmocka_unit_test(transformed_instances_bake_as_world_geometry),
	    cmocka_unit_test(mirrored_instance_keeps_the_winding_side),
	    cmocka_unit_test(bad_instances_are_refused),
	    cmocka_unit_test(instances_respect_the_triangle_limit),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
