/*
 * The animated scene (docs/scenes.md): two cows walking a circle, one turning on the spot
 * in the middle and a mirror panel orbiting them, on a floor held by four corner columns.
 * Every frame is a pure function of frame / fps (no clock), so any frame can be made
 * again on its own. The columns and the floor bound every frame's geometry, so the scene's
 * bounds, camera, lights and environment are the same in every frame: frames differ only
 * in positions and normals (rs_renderer_update_vertices() takes any frame after any).
 */
#include <math.h>
#include <stdlib.h>

#include "raystream/rs_scenegen.h"
#include "scenegen_internal.h"

#define HALF 16.0       /* floor half side */
#define COLUMN_H 12.0   /* column height: above every moving thing */
#define WALK_R 8.5      /* walking circle radius */
#define WALK_PERIOD 16. /* seconds a lap */
#define SPIN_PERIOD 8.0 /* seconds a turn of the middle cow */
#define MIRROR_R 13.0   /* mirror orbit radius (inside the columns) */
#define MIRROR_PERIOD 12.0

static const double k_lights[4][3] = {
    {-10.0, 25.0, 20.0}, {15.0, 20.0, 10.0}, {0.0, 30.0, -15.0}, {-20.0, 12.0, -5.0}};

/* Materials in a fixed order: floor, columns, mirror (cow: sg_cow_material, added last). */
static enum rs_status add_static(struct rs_scene *scene, uint32_t ids[3], struct rs_error *err)
{
	static const struct rs_material m[3] = {
	    {.diffuse = {0.8f, 0.8f, 0.8f}},
	    {.diffuse = {0.3f, 0.5f, 0.3f}},
	    {.diffuse = {0.1f, 0.1f, 0.1f}, .reflectance = 0.9f},
	};
	enum rs_status st = RS_OK;
	for (int i = 0; st == RS_OK && i < 3; i++)
		st = sg_material(scene, &m[i], &ids[i], err);
	const double flo[3] = {-HALF, -0.5, -HALF}, fhi[3] = {HALF, 0.0, HALF};
	if (st == RS_OK)
		st = sg_add_box(scene, flo, fhi, 0.0, ids[0], err);
	for (int c = 0; st == RS_OK && c < 4; c++) {
		double x = c & 1 ? HALF - 1.0 : -HALF, z = c & 2 ? HALF - 1.0 : -HALF;
		const double lo[3] = {x, 0.0, z}, hi[3] = {x + 1.0, COLUMN_H, z + 1.0};
		st = sg_add_box(scene, lo, hi, 0.0, ids[1], err);
	}
	return st;
}

/* The mirror at angle a of its orbit: 6 wide, 5 tall, 0.2 thick, facing the centre, its
 * lower edge 0.25 above the floor (no face coplanar with the floor's). */
static enum rs_status add_mirror(struct rs_scene *scene, double a, uint32_t mat,
                                 struct rs_error *err)
{
	double cx = MIRROR_R * sin(a), cz = MIRROR_R * cos(a);
	const double lo[3] = {cx - 3.0, 0.25, cz - 0.1}, hi[3] = {cx + 3.0, 5.25, cz + 0.1};
	/* sg_add_box turns +x towards -z: the panel's +z normal then points along (sin, cos) */
	return sg_add_box(scene, lo, hi, a * 180.0 / RS_PI, mat, err);
}

enum rs_status sg_build_animated(struct rs_scene *scene, const char *cow_path, uint32_t frame,
                                 uint32_t fps, struct rs_error *err)
{
	const double t = (double)frame / (double)fps, tau = 2.0 * RS_PI;
	struct rs_scene *cow = NULL;
	double *pos = NULL;
	float *nrm = NULL;
	uint32_t ids[3], cow_mat;
	enum rs_status st = add_static(scene, ids, err);

	if (st == RS_OK)
		st = add_mirror(scene, -tau * t / MIRROR_PERIOD, ids[2], err);
	if (st == RS_OK)
		st = sg_load_cow(cow_path, &cow, &pos, &nrm, err);
	if (st == RS_OK)
		st = sg_material(scene, &sg_cow_material, &cow_mat, err);
	/* two walkers half a lap apart, facing along the circle (yaw = angle: +x tangent) */
	for (int w = 0; st == RS_OK && w < 2; w++) {
		double a = tau * t / WALK_PERIOD + RS_PI * w;
		st = sg_add_cow(scene, cow, a, WALK_R * sin(a), WALK_R * cos(a), cow_mat, pos, nrm,
		                err);
	}
	if (st == RS_OK)
		st =
		    sg_add_cow(scene, cow, tau * t / SPIN_PERIOD, 0.0, 0.0, cow_mat, pos, nrm, err);
	free(pos);
	free(nrm);
	rs_scene_destroy(&cow);
	if (st != RS_OK)
		return st;
	const struct rs_bounds stage = {{-HALF, -0.5, -HALF}, {HALF, COLUMN_H, HALF}};
	if ((st = sg_frame_camera(scene, &stage, err)) != RS_OK)
		return st;
	return sg_finish(scene, k_lights, err);
}
