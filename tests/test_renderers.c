/* rs_renderers: backends opened by name; unknown and missing backends refused clearly. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_renderers.h"

static void cpu_is_always_built(void **state)
{
	struct rs_renderer *r = NULL;
	assert_true(rs_renderer_has_backend("cpu"));
	assert_int_equal(rs_renderer_open("cpu", NULL, &r, NULL), RS_OK);
	assert_string_equal(rs_renderer_stats(r)->backend, "cpu");
	rs_renderer_destroy(&r);
	assert_non_null(strstr(rs_renderer_backends(), "cpu"));
}

/* The default is auto: a GL backend where a context opens, else cpu with a note saying
 * so; a descriptor's backend is used when no name is given. */
static void auto_is_the_default_and_says_when_it_falls_back(void **state)
{
	struct rs_renderer *a = NULL, *r = NULL;
	struct rs_error note = {.message = "stale"}, err;
	assert_true(rs_renderer_has_backend("auto"));
	assert_int_equal(rs_renderer_open_noted("auto", NULL, &a, &note, &err), RS_OK);
	const char *picked = rs_renderer_backend(a);
	bool has_gl = rs_renderer_has_backend("egl") || rs_renderer_has_backend("osmesa");
	if (strcmp(picked, "cpu") == 0) {
		assert_non_null(strstr(note.message, "rendering on cpu"));
		assert_non_null(strstr(note.message, has_gl ? "no GL context" : "no GL backend"));
	} else {
		assert_string_equal(note.message, "");
	}
	assert_int_equal(rs_renderer_open(NULL, NULL, &r, NULL), RS_OK);
	assert_string_equal(rs_renderer_backend(r), picked);
	rs_renderer_destroy(&r);
	rs_renderer_destroy(&a);
	struct rs_render_desc desc = {0};
	assert_int_equal(rs_render_desc_set(&desc, "backend", "cpu", NULL), RS_OK);
	assert_int_equal(rs_renderer_open_noted(NULL, &desc, &r, &note, NULL), RS_OK);
	assert_string_equal(rs_renderer_backend(r), "cpu");
	assert_string_equal(note.message, "");
	rs_renderer_destroy(&r);
}

static void unknown_backend_is_invalid(void **state)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_false(rs_renderer_has_backend("vulkan"));
	assert_false(rs_renderer_has_backend(NULL));
	assert_int_equal(rs_renderer_open("vulkan", NULL, &r, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "vulkan"));
	assert_null(r);
}

static void known_backends_are_built_or_refused_as_unsupported(void **state)
{
	const char *names[] = {"egl", "osmesa"};
	for (int i = 0; i < 2; ++i) {
		if (rs_renderer_has_backend(names[i])) {
			assert_non_null(strstr(rs_renderer_backends(), names[i]));
			continue;
		}
		struct rs_renderer *r = NULL;
		struct rs_error err;
		assert_int_equal(rs_renderer_open(names[i], NULL, &r, &err), RS_ERR_UNSUPPORTED);
		assert_non_null(strstr(err.message, "not part of this build"));
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cpu_is_always_built),
	    cmocka_unit_test(auto_is_the_default_and_says_when_it_falls_back),
	    cmocka_unit_test(unknown_backend_is_invalid),
	    cmocka_unit_test(known_backends_are_built_or_refused_as_unsupported),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
