/* Contract checks, module by module: a NULL handle or out-pointer reaches RS_ASSERT (always
 * on, NDEBUG or not) instead of being dereferenced or reported as bad data. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "contract.h"
#include "raystream/rs_bvh.h"
#include "raystream/rs_image.h"
#include "raystream/rs_load.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_pose.h"
#include "raystream/rs_proto.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"
#include "raystream/rs_sim.h"
#include "raystream/rs_trace.h"
#include "raystream/rs_track.h"
#include "raystream/rs_serial.h"
#include "raystream/rs_tracker.h"
#ifdef RS_HAVE_HID
#include "raystream/rs_hid.h"
#endif
#ifdef RS_HAVE_USB
#include "raystream/rs_usb.h"
#endif

static void scene_calls_check_their_handles(void **state)
{
	struct rs_material m = {0};
	struct rs_camera cam = {.eye = {0, 0, 1}, .up = {0, 1, 0}};
	uint32_t id;
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_create(NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_add_material(NULL, &m, &id, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_set_camera(NULL, &cam, NULL));
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_add_mesh(scene, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_add_light(scene, NULL, NULL));
	rs_scene_destroy(&scene);
}

static void bvh_pack_and_trace_check_their_outputs(void **state)
{
	const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const uint32_t idx[3] = {0, 1, 2};
	struct rs_bvh_node nodes[4];
	uint32_t order[1];
	size_t count;
	enum rs_bvh_builder b;
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_bvh_build(NULL, pos, 3, idx, 1, nodes, 4, order, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_bvh_build(NULL, pos, 3, idx, 1, NULL, 4, order, &count, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_bvh_builder_parse("sah", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_bvh_builder_parse(NULL, &b, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pack_layout(NULL, 1, 1, 1, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pack_check(NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pack_alloc(NULL, NULL));
	struct rs_packed packed = {0};
	RS_EXPECT_CONTRACT_VIOLATION(rs_trace_render(NULL, &packed, NULL, NULL, NULL, NULL, NULL));
}

static void load_scenegen_and_image_check_paths_and_outputs(void **state)
{
	struct rs_scene *scene = NULL;
	struct rs_scenegen_desc d = {0};
	char name[16];
	uint8_t *px;
	uint32_t w, h;
	RS_EXPECT_CONTRACT_VIOLATION(rs_load_scene(NULL, "x.obj", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_load_scene(NULL, NULL, &scene, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_load_mesh_file(NULL, "x.obj", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_load_sidecar_path("a.obj", NULL, 8, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scenegen_build(&d, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scenegen_name(NULL, name, sizeof name, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_scene_export(NULL, "x.obj", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_image_read_png("x.png", NULL, &w, &h, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_image_read_png(NULL, &px, &w, &h, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_image_write_pfm("x.pfm", NULL, 1, 1, 1, NULL));
}

static void tracking_calls_check_their_handles(void **state)
{
	struct rs_marker_sample s = {0};
	struct rs_pose p = {0};
	const uint8_t *data = NULL;
	size_t len = 0;
	uint16_t vid, pid;
	RS_EXPECT_CONTRACT_VIOLATION(rs_track_source_read(NULL, &s, 0, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_track_source_reopen(NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_proto_parser_feed(NULL, &data, &len, &s));
	RS_EXPECT_CONTRACT_VIOLATION(rs_proto_encode(&s, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_sim_next(NULL, &s, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_track_parse_vid_pid("1:2", &vid, &pid, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_track_replay_open(NULL, NULL, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_tracker_open("sim:", NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_filter_predict(NULL, 0.0, &p, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_fit(NULL, NULL, 3, &p, NULL, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_pose_layout_check(NULL, NULL));
}

static void backends_check_their_descriptors(void **state)
{
	struct rs_track_source *src = NULL;
	RS_EXPECT_CONTRACT_VIOLATION(rs_serial_open(NULL, &src, NULL));
	RS_EXPECT_CONTRACT_VIOLATION(rs_serial_pty_create(NULL, NULL));
#ifdef RS_HAVE_HID
	RS_EXPECT_CONTRACT_VIOLATION(rs_hid_open(NULL, &src, NULL));
#endif
#ifdef RS_HAVE_USB
	RS_EXPECT_CONTRACT_VIOLATION(rs_usb_open(NULL, &src, NULL));
#endif
	assert_null(src);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(scene_calls_check_their_handles),
	    cmocka_unit_test(bvh_pack_and_trace_check_their_outputs),
	    cmocka_unit_test(load_scenegen_and_image_check_paths_and_outputs),
	    cmocka_unit_test(tracking_calls_check_their_handles),
	    cmocka_unit_test(backends_check_their_descriptors),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
