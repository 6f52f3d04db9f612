/* rs_render_desc_set/parse/get: every option spelled as the command line spells it, bad
 * values refused with the valid range named and the descriptor left alone, and the
 * spelling read back (what --help shows as defaults). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_render.h"

static void every_option_round_trips(void **state)
{
	static const char *const cases[][2] = {
	    {"backend", "egl"},        {"size", "320x240"},
	    {"passes", "5"},           {"lights", "3"},
	    {"lights", "all"},         {"shadows", "rays"},
	    {"shadows", "map:1024:5"}, {"primary", "raster"},
	    {"reflections", "envmap"}, {"reflections", "interreflect:3"},
	    {"bvh", "paper"},          {"nodes", "paper:single"},
	    {"scene-storage", "2d"},   {"threads", "7"},
	    {"triangle-test", "mt"},   {"chain", "separate"},
	    {"nodes", "wide4"},        {"nodes", "wide4"},
	    {"shadows", "none"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		struct rs_render_desc d = {0};
		struct rs_error err = {0};
		char back[64];
		assert_int_equal(rs_render_desc_set(&d, cases[i][0], cases[i][1], &err), RS_OK);
		assert_int_equal(rs_render_desc_get(&d, cases[i][0], back, sizeof back, &err),
		                 RS_OK);
		assert_string_equal(back, cases[i][1]);
		/* What the command line accepts the library accepts. */
		struct rs_render_desc resolved;
		assert_int_equal(rs_render_desc_resolve(&d, &resolved, &err), RS_OK);
	}
}

static void fields_take_the_values_named(void **state)
{
	struct rs_render_desc d = {0};
	assert_int_equal(rs_render_desc_parse(&d, "passes=3,lights=2,size=64x32,bvh=none", NULL),
	                 RS_OK);
	assert_int_equal(d.passes, 3);
	assert_int_equal(d.lights, 2);
	assert_int_equal(d.width, 64);
	assert_int_equal(d.height, 32);
	assert_int_equal(d.bvh.builder, RS_BVH_NONE);
	assert_int_equal(rs_render_desc_set(&d, "shadows", "map", NULL), RS_OK);
	assert_int_equal(d.shadows, RS_SHADOW_MAP);
	assert_int_equal(d.shadow_map_size, 0); /* resolved to 512 */
	/* none forgets a map's size as rays does, and rays undoes none */
	assert_int_equal(rs_render_desc_parse(&d, "shadows=map:1024,shadows=none", NULL), RS_OK);
	assert_int_equal(d.shadows, RS_SHADOW_NONE);
	assert_int_equal(d.shadow_map_size, 0);
	assert_int_equal(rs_render_desc_set(&d, "shadows", "rays", NULL), RS_OK);
	assert_int_equal(d.shadows, RS_SHADOW_RAYS);
	assert_int_equal(rs_render_desc_set(&d, "backend", "cpu", NULL), RS_OK);
	assert_string_equal(d.backend, "cpu");
}

/* The zero descriptor reads as the documented defaults: what --help prints. */
static void zero_descriptor_reads_as_the_defaults(void **state)
{
	size_t n = 0;
	const struct rs_render_option *o = rs_render_options(&n);
	assert_true(n >= 11);
	struct rs_render_desc zero = {0};
	for (size_t i = 0; i < n; ++i) {
		char text[64];
		assert_int_equal(rs_render_desc_get(&zero, o[i].key, text, sizeof text, NULL),
		                 RS_OK);
		assert_string_equal(text, o[i].fallback);
		assert_ptr_equal(rs_render_option_find(o[i].key), &o[i]);
	}
	char text[8];
	assert_int_equal(rs_render_desc_get(&zero, "lights", text, sizeof text, NULL), RS_OK);
	assert_string_equal(text, "all");
}

static void bad_values_name_the_option_and_its_range(void **state)
{
	static const char *const bad[][3] = {
	    {"passes", "0", "passes: '0' is not 1..64"},
	    {"passes", "65", "1..64"},
	    {"passes", "-1", "1..64"},
	    {"passes", "2x", "1..64"},
	    {"lights", "0", "1..64|all"},
	    {"size", "0x10", "WxH"},
	    {"size", "16384x16385", "WxH"},
	    {"shadows", "map:4", "map[:RES[:FILTER]]"},
	    {"shadows", "map:512:0", "map[:RES[:FILTER]]"},
	    {"shadows", "none:3", "rays|map[:RES[:FILTER]]|none"},
	    {"reflections", "interreflect:9", "interreflect[:1..8]"},
	    {"backend", "vulkan", "auto|cpu|egl|osmesa"},
	    {"nodes", "compact:sideways", "compact|paper[:directional|octant|single]"},
	    {"nodes", "wide4:single", "wide4"},
	    {"threads", "257", "1..256"},
	    {"frobnicate", "1", "unknown render option 'frobnicate'"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
		struct rs_render_desc d = {.passes = 4};
		struct rs_error err = {0};
		assert_int_equal(rs_render_desc_set(&d, bad[i][0], bad[i][1], &err),
		                 RS_ERR_INVALID);
		if (!strstr(err.message, bad[i][2]))
			fail_msg("%s=%s: '%s' lacks '%s'", bad[i][0], bad[i][1], err.message,
			         bad[i][2]);
		assert_int_equal(d.passes, 4); /* unchanged */
	}
}

static void a_config_string_is_all_or_nothing(void **state)
{
	struct rs_render_desc d = {0};
	struct rs_error err = {0};
	assert_int_equal(rs_render_desc_parse(&d, "passes=3,lights=many", &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "lights: 'many'"));
	assert_int_equal(d.passes, 0);
	assert_int_equal(rs_render_desc_parse(&d, "passes", &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "not key=value"));
	assert_int_equal(rs_render_desc_parse(&d, "", &err), RS_OK);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(every_option_round_trips),
	    cmocka_unit_test(fields_take_the_values_named),
	    cmocka_unit_test(zero_descriptor_reads_as_the_defaults),
	    cmocka_unit_test(bad_values_name_the_option_and_its_range),
	    cmocka_unit_test(a_config_string_is_all_or_nothing),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
