/* A test scene for the GL kernels at any scale and place (test_gl_wide.c, test_gl_hits_only.c):
 * boxes of varied sizes, some mirrors, over a floor, with a camera and a light. After
 * cmocka.h and test_gl_common.h. */
#ifndef TEST_GL_FIELD_H
#define TEST_GL_FIELD_H

#include "test_trace_render_fixture.h"

/* A field of 5 x 5 x 2 boxes of varied sizes over a floor, `scale` times, shifted by `off`;
 * flat: squares in the plane y = off[1] instead; camera `size` pixels square. */
static inline struct rs_scene *field(double scale, const double off[3], bool flat, uint32_t size)
{
	struct rs_scene *scene = fx_scene();
	uint32_t m = fx_material(scene, (struct rs_material){.diffuse = {0.7f, 0.6f, 0.5f}});
	uint32_t mirror = fx_material(
	    scene, (struct rs_material){.diffuse = {0.2f, 0.3f, 0.8f}, .reflectance = 0.5f});
	for (int i = 0; i < 5; i++)
		for (int j = 0; j < 5; j++)
			for (int k = 0; k < (flat ? 1 : 2); k++) {
				double s = 0.4 + 0.1 * ((i * 7 + j * 3 + k) % 5);
				double lo[3] = {off[0] + scale * (i * 1.5 - 3.5),
				                off[1] + scale * (k * 1.3),
				                off[2] + scale * (j * 1.5 - 3.5)};
				double hi[3] = {lo[0] + scale * s, lo[1] + scale * s,
				                lo[2] + scale * s};
				if (flat)
					fx_rect(scene, 1, off[1], lo[2], hi[2], lo[0], hi[0], 0,
					        (i + j) % 3 ? m : mirror);
				else
					fx_box(scene, lo, hi, (i + j + k) % 3 ? m : mirror);
			}
	if (!flat)
		fx_rect(scene, 1, off[1] - 0.01 * scale, off[2] - 5 * scale, off[2] + 5 * scale,
		        off[0] - 5 * scale, off[0] + 5 * scale, 0, m);
	double eye[3] = {off[0] + 4 * scale, off[1] + 6 * scale, off[2] + 7 * scale};
	fx_camera(scene, eye, off, size);
	fx_light(scene, off[0] - 2 * scale, off[1] + 8 * scale, off[2] + 3 * scale, 1, 1, 1);
	return scene;
}

#endif
