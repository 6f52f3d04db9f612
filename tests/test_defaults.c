/* Defaults mean one thing: the library's zero rs_render_desc (through rs_renderer_open with
 * no backend name, i.e. auto) and `raystream-render --scene box` with no other option
 * render the same image, pixel for pixel (issue 18: they once differed in lights and
 * backend). RS_RENDER_BIN names the tool (tests/defaults.cmake). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "raystream/rs_image.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"

static void zero_descriptor_and_tool_without_options_agree(void **state)
{
	const char *bin = getenv("RS_RENDER_BIN");
	if (!bin || !*bin)
		skip();
	char dir[] = "/tmp/rs_defaults_XXXXXX";
	assert_non_null(mkdtemp(dir));
	char cmd[4096];
	/* No --out: the tool writes out.png in its working folder and says so. */
	snprintf(cmd, sizeof cmd, "cd '%s' && '%s' --scene box >stdout.txt", dir, bin);
	assert_int_equal(system(cmd), 0);
	char path[512], line[512] = "";
	snprintf(path, sizeof path, "%s/stdout.txt", dir);
	FILE *f = fopen(path, "r");
	assert_non_null(f);
	bool named = false;
	while (fgets(line, sizeof line, f))
		named = named || strcmp(line, "wrote out.png\n") == 0;
	fclose(f);
	assert_true(named);

	uint8_t *tool = NULL;
	uint32_t w = 0, h = 0;
	snprintf(path, sizeof path, "%s/out.png", dir);
	assert_int_equal(rs_image_read_png(path, &tool, &w, &h, NULL), RS_OK);

	struct rs_scene *scene = NULL;
	struct rs_renderer *r = NULL;
	struct rs_error err = {0};
	const struct rs_render_desc zero = {0};
	assert_int_equal(rs_scenegen_load("box", &scene, &err), RS_OK);
	if (rs_renderer_open(NULL, &zero, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("%s", err.message);
	const struct rs_render_desc *d = rs_renderer_desc(r);
	assert_int_equal(d->width, w);
	assert_int_equal(d->height, h);
	assert_int_equal(d->lights, 0); /* all of the scene's */
	float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
	uint8_t *lib = malloc((size_t)w * h * 3);
	assert_non_null(rgb);
	assert_non_null(lib);
	struct rs_frame frame = {.rgb = rgb};
	if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("%s", err.message);
	rs_image_quantize(rgb, w, h, lib);
	size_t differ = 0;
	for (size_t i = 0; i < (size_t)w * h * 3; ++i)
		differ += lib[i] != tool[i];
	if (differ)
		fail_msg("%zu of %zu channel values differ (library on %s)", differ,
		         (size_t)w * h * 3, rs_renderer_backend(r));
	free(rgb);
	free(lib);
	rs_free(tool);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	assert_int_equal(system(cmd), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(zero_descriptor_and_tool_without_options_agree),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
