/* Rendering an instanced scene and its flattened twin for comparison, shared by
 * test_gl_instances.c and test_gl_two_level.c: one frame of a backend ("cpu", or a GL one
 * through gl_open) with its ids, depth and counts, and the bars the issue sets (same
 * triangle on >= 99.99 % of pixels, >= 60 dB; GPU counts within 5e-4 of the CPU's, as
 * flattened Cow17 already differs by 2.8e-4). Define SIZE (the image side) before including;
 * after cmocka.h and test_gl_common.h. */
#ifndef TEST_GL_SAME_FRAME_H
#define TEST_GL_SAME_FRAME_H

#include <math.h>
#include <string.h>

#include "raystream/rs_image.h"
#include "raystream/rs_render.h"

struct image {
	float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	uint32_t triangle[SIZE * SIZE];
	uint64_t boxes, triangles, upload_bytes;
};

static bool render(const char *backend, struct rs_render_desc desc, const struct rs_scene *scene,
                   struct image *out)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	if (!strcmp(backend, "cpu")) {
		if (rs_renderer_create_cpu(&desc, &r, &err) != RS_OK)
			fail_msg("cpu: %s", err.message);
	} else if (!(r = gl_open(backend, &desc)))
		return false;
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("%s set_scene: %s", backend, err.message);
	struct rs_frame frame = {.rgb = out->rgb, .depth = out->depth, .triangle = out->triangle};
	if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("%s render: %s", backend, err.message);
	out->boxes = rs_renderer_stats(r)->box_tests;
	out->triangles = rs_renderer_stats(r)->triangle_tests;
	out->upload_bytes = rs_renderer_stats(r)->upload_bytes;
	rs_renderer_destroy(&r);
	return true;
}

static bool near_count(uint64_t gpu, uint64_t cpu)
{
	double d = (double)gpu - (double)cpu;
	return fabs(d) <= 5e-4 * (double)cpu;
}

/* Same triangle on >= 99.99 % of pixels and >= 60 dB; returns the pixels hit. */
static size_t same_frame(const char *what, const struct image *a, const struct image *b)
{
	size_t same = 0, hits = 0;
	for (size_t i = 0; i < SIZE * SIZE; i++) {
		same += a->triangle[i] == b->triangle[i];
		hits += a->triangle[i] != RS_NO_SLOT;
	}
	struct rs_image_diff d;
	rs_image_compare(a->rgb, b->rgb, SIZE, SIZE, 3, 1.0, 1.0 / 255.0, &d);
	print_message("%s: %zu of %u pixels hit, %zu the same triangle, %.1f dB\n", what, hits,
	              SIZE * SIZE, same, d.psnr_db);
	assert_true((double)same >= 0.9999 * SIZE * SIZE);
	assert_true(d.psnr_db >= 60.0);
	return hits;
}

#endif
