/* The none builder (one box of every triangle) on the paper's Cow1 scene against brute
 * force: 100,000 random rays find the same closest hit and any-hit agrees for shadow
 * feelers. Its own executable: each ray tests all 5,837 triangles, which is slow under
 * ASan. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_cowrays_common.h"

static void none_matches_brute_force(void **state)
{
	struct rs_scene *scene = cow_scene(1);
	struct cow_ref *refs = cow_references(scene);
	struct cow_world w = cow_pack(scene, RS_BVH_NONE);
	cow_check_reference(&w, refs, 1000);
	cow_compare(&w, refs, "none");
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
