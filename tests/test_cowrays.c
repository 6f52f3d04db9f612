/* Traversal of the packed BVH on the paper's Cow1 scene (rs_scenegen) against brute
 * force, for the sah, paper and linear builders: 100,000 random rays must find the same
 * closest hit, and any-hit must agree with brute-force occlusion for shadow feelers.
 * (The none builder is checked in test_cowrays_none.c to keep each run short.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_cowrays_common.h"

static struct rs_scene *scene;
static struct cow_ref *refs;

static int setup(void **state)
{
	scene = cow_scene(1);
	refs = cow_references(scene, 0, COW_RAYS);
	return 0;
}

static int teardown(void **state)
{
	free(refs);
	rs_scene_destroy(&scene);
	return 0;
}

static void check(enum rs_bvh_builder builder)
{
	struct cow_world w = cow_pack(scene, builder);
	cow_compare(&w, refs, 0, COW_RAYS, rs_bvh_builder_name(builder));
	cow_world_free(&w);
}

/* The fast reference agrees with the library's plain brute force on 1 ray in 50. */
static void reference_matches_plain_brute_force(void **state)
{
	struct cow_world w = cow_pack(scene, RS_BVH_SAH);
	cow_check_reference(&w, refs, 0, COW_RAYS, 50);
	cow_world_free(&w);
}

static void sah_matches_brute_force(void **state)
{
	check(RS_BVH_SAH);
}

static void paper_matches_brute_force(void **state)
{
	check(RS_BVH_PAPER);
}

static void linear_matches_brute_force(void **state)
{
	check(RS_BVH_LINEAR);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(reference_matches_plain_brute_force),
	    cmocka_unit_test(sah_matches_brute_force),
	    cmocka_unit_test(paper_matches_brute_force),
	    cmocka_unit_test(linear_matches_brute_force),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
