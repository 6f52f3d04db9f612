/* The none builder (one box of every triangle) on the paper's Cow1 scene against brute
 * force: the first half of the 100,000 random rays find the same closest hit and any-hit
 * agrees for shadow feelers (test_cowrays_none2.c checks the second half). Executables of
 * their own: each ray tests all 5,837 triangles, which is slow under ASan. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_cowrays_common.h"

#ifndef COW_NONE_BEGIN
#define COW_NONE_BEGIN 0
#define COW_NONE_END (COW_RAYS / 2)
#endif

static void none_matches_brute_force(void **state)
{
	struct rs_scene *scene = cow_scene(1);
	struct cow_ref *refs = cow_references(scene, COW_NONE_BEGIN, COW_NONE_END);
	struct cow_world w = cow_pack(scene, RS_BVH_NONE);
	cow_check_reference(&w, refs, COW_NONE_BEGIN, COW_NONE_END, 1000);
	cow_compare(&w, refs, COW_NONE_BEGIN, COW_NONE_END, "none");
	cow_world_free(&w);
	free(refs);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(none_matches_brute_force),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
