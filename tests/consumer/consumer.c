/* Links the installed library: a tracker source opened by URI (the simulator, through the
 * backend dispatcher, so every backend library must link), one triangle, a BVH and a tiny
 * CPU render. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <raystream/rs_bvh.h>
#include <raystream/rs_pack.h>
#include <raystream/rs_scene.h>
#include <raystream/rs_trace.h>
#include <raystream/rs_tracker.h>

/* A few samples from "sim:" through rs_tracker_open(), which references every backend. */
static int read_tracker(void)
{
	struct rs_track_source *src = NULL;
	struct rs_error err = {0};
	if (rs_tracker_open("sim:seed=3&rate=1000", &src, &err) != RS_OK) {
		fprintf(stderr, "consumer: %s\n", err.message);
		return 0;
	}
	int got = 0;
	struct rs_marker_sample s;
	for (int i = 0; i < 5; i++)
		if (rs_track_source_read(src, &s, 1000, &err) == RS_OK && s.marker_count == 3)
			got++;
	rs_track_source_destroy(&src);
	return got == 5;
}

int main(void)
{
	if (!read_tracker())
		return 6;
	struct rs_scene *scene = NULL;
	struct rs_error err = {0};
	if (rs_scene_create(NULL, &scene, &err) != RS_OK)
		return 1;
	struct rs_material m = {.diffuse = {1, 1, 1}};
	uint32_t id;
	float pos[9] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
	uint32_t idx[3] = {0, 1, 2};
	struct rs_mesh_desc mesh = {
	    .positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};
	struct rs_light light = {.position = {0, 0, 5}, .color = {1, 1, 1}};
	struct rs_camera cam = {.eye = {0, 0, 5}, .up = {0, 1, 0}, .width = 8, .height = 8};
	if (rs_scene_add_material(scene, &m, &id, NULL) || rs_scene_add_mesh(scene, &mesh, NULL) ||
	    rs_scene_add_light(scene, &light, NULL) || rs_scene_set_camera(scene, &cam, NULL))
		return 2;
	struct rs_bvh_node nodes[8];
	uint32_t order[1];
	size_t count;
	struct rs_packed packed;
	if (rs_bvh_build(NULL, pos, 3, idx, 1, nodes, 8, order, &count, &err) ||
	    rs_pack_layout(NULL, count, 1, 1, &packed, &err) || rs_pack_alloc(&packed, &err) ||
	    rs_pack_scene(scene, nodes, count, order, &packed, &err))
		return 3;
	float rgb[8 * 8 * 3], depth[8 * 8];
	if (rs_trace_render(scene, &packed, NULL, rgb, depth, NULL, &err) != RS_OK)
		return 4;
	/* The centre pixel sees the triangle 5 units away. */
	float d = depth[4 * 8 + 4];
	printf("consumer: 5 tracker samples from sim:, centre depth %.3f\n", d);
	rs_pack_free(&packed);
	rs_scene_destroy(&scene);
	return fabsf(d - 5.0f) < 0.05f ? 0 : 5;
}
