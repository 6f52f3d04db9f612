/*
 * Box (shared/SCENES.md): a closed Cornell-style room seen from inside, 153 triangles =
 * 12 boxes x 12 + glass prism 8 + sail 1. The contents are placed first; the camera rule
 * is applied to their bounds and the room is then sized around contents and camera, so
 * the eye is always inside the closed room.
 */
#include <math.h>
#include <string.h>

#include "raystream/rs_scenegen.h"
#include "scenegen_internal.h"

#define WALL 0.2       /* thickness of floor, ceiling and walls */
#define MARGIN 1.5     /* room clearance beyond camera and contents */
#define LIGHT_DROP 0.3 /* lights hang this far under the ceiling (below the light panel) */

enum { M_WHITE, M_RED, M_GREEN, M_MIRROR, M_LAMP, M_CUBE, M_PLINTH, M_GLASS, M_SAIL, M_COUNT };

static const struct rs_material k_mats[M_COUNT] = {
    [M_WHITE] = {.diffuse = {0.73f, 0.73f, 0.73f}},
    [M_RED] = {.diffuse = {0.63f, 0.065f, 0.05f}},
    [M_GREEN] = {.diffuse = {0.14f, 0.45f, 0.091f}},
    [M_MIRROR] = {.diffuse = {0.1f, 0.1f, 0.1f}, .reflectance = 0.9f},
    [M_LAMP] = {.diffuse = {1.0f, 1.0f, 1.0f}},
    [M_CUBE] = {.diffuse = {0.8f, 0.7f, 0.2f}, .specular = 0.5f, .shininess = 64.0f},
    [M_PLINTH] = {.diffuse = {0.5f, 0.5f, 0.5f}},
    [M_GLASS] = {.transmittance = 0.9f, .ior = 1.5f},
    [M_SAIL] = {.diffuse = {0.2f, 0.4f, 0.8f}},
};

/* A box standing on y = y0, footprint centred on (x, z), turned by yaw. */
static enum rs_status standing_box(struct rs_scene *scene, double x, double y0, double z, double sx,
                                   double sy, double sz, double yaw, uint32_t mat,
                                   struct rs_error *err)
{
	const double lo[3] = {x - 0.5 * sx, y0, z - 0.5 * sz};
	const double hi[3] = {x + 0.5 * sx, y0 + sy, z + 0.5 * sz};

	return sg_add_box(scene, lo, hi, yaw, mat, err);
}

static enum rs_status add_contents(struct rs_scene *scene, const uint32_t *id, struct rs_error *err)
{
	const double lean = 30.0 * RS_PI / 180.0;
	const double prism_base[3] = {1.8, 0.6 + SG_GLASS_GAP, -2.2}; /* see SG_GLASS_GAP */
	const double sa[3] = {-2.6, 3.2, 0.4}, sb[3] = {-0.4, 3.2, 0.4};
	const double apex[3] = {-1.5, 3.2 + 1.6 * cos(lean), 0.4 - 1.6 * sin(lean)};
	enum rs_status st;

	if ((st = standing_box(scene, -1.5, 0.0, -1.2, 1.6, 3.4, 1.6, 17.0, id[M_WHITE], err)) ||
	    (st = standing_box(scene, 1.6, 0.0, 0.6, 1.8, 1.6, 1.8, -18.0, id[M_WHITE], err)) ||
	    (st = standing_box(scene, 1.6, 1.6, 0.6, 0.7, 0.7, 0.7, 30.0, id[M_CUBE], err)) ||
	    (st = standing_box(scene, 1.8, 0.0, -2.2, 1.4, 0.6, 1.4, 0.0, id[M_PLINTH], err)) ||
	    (st = sg_add_prism(scene, prism_base, 0.55, 1.6, id[M_GLASS], err)) ||
	    (st = sg_add_triangle(scene, sa, sb, apex, id[M_SAIL], err)))
		return st;
	return RS_OK;
}

enum rs_status sg_build_box(struct rs_scene *scene, struct rs_error *err)
{
	uint32_t id[M_COUNT];
	struct rs_bounds contents;
	const struct rs_camera *cam;
	double c[3], x0, x1, z0, z1, h, half;
	enum rs_status st;

	for (int m = 0; m < M_COUNT; m++)
		if ((st = sg_material(scene, &k_mats[m], &id[m], err)) != RS_OK)
			return st;
	if ((st = add_contents(scene, id, err)) != RS_OK)
		return st;
	rs_scene_bounds(scene, &contents);
	sg_center(&contents, c);
	if ((st = sg_frame_camera(scene, &contents, err)) != RS_OK)
		return st;
	cam = rs_scene_camera(scene);
	half = fmax(0.5 * (contents.hi[0] - contents.lo[0]) + 2.5, 5.0);
	x0 = c[0] - half;
	x1 = c[0] + half;
	z0 = contents.lo[2] - 2.5;
	z1 = cam->eye[2] + MARGIN;
	h = fmax(cam->eye[1], contents.hi[1]) + MARGIN;
	{
		const double cx = c[0], cz = 0.5 * (z0 + z1);
		/* floor, ceiling, left (red), right (green), back, front */
		const double shell[6][2][3] = {
		    {{x0 - WALL, -WALL, z0 - WALL}, {x1 + WALL, 0.0, z1 + WALL}},
		    {{x0 - WALL, h, z0 - WALL}, {x1 + WALL, h + WALL, z1 + WALL}},
		    {{x0 - WALL, 0.0, z0}, {x0, h, z1}},
		    {{x1, 0.0, z0}, {x1 + WALL, h, z1}},
		    {{x0, 0.0, z0 - WALL}, {x1, h, z0}},
		    {{x0, 0.0, z1}, {x1, h, z1 + WALL}},
		};
		const uint32_t shell_mat[6] = {id[M_WHITE], id[M_WHITE], id[M_RED],
		                               id[M_GREEN], id[M_WHITE], id[M_WHITE]};
		/* Mirror panel against the back wall; light panel flush under the ceiling. */
		const double mlo[3] = {cx - 2.5, 0.8, z0}, mhi[3] = {cx + 2.5, 4.8, z0 + 0.1};
		const double llo[3] = {cx - 1.0, h - 0.05, cz - 1.0};
		const double lhi[3] = {cx + 1.0, h, cz + 1.0};
		/* L1 at the ceiling centre, then three more spread under the ceiling. */
		const double lights[4][3] = {
		    {cx, h - LIGHT_DROP, cz},
		    {x0 + 0.25 * (x1 - x0), h - LIGHT_DROP, z0 + 0.75 * (z1 - z0)},
		    {x0 + 0.75 * (x1 - x0), h - LIGHT_DROP, z0 + 0.75 * (z1 - z0)},
		    {cx, h - LIGHT_DROP, z0 + 0.2 * (z1 - z0)},
		};

		for (int i = 0; i < 6; i++)
			if ((st = sg_add_box(scene, shell[i][0], shell[i][1], 0.0, shell_mat[i],
			                     err)) != RS_OK)
				return st;
		if ((st = sg_add_box(scene, mlo, mhi, 0.0, id[M_MIRROR], err)) != RS_OK ||
		    (st = sg_add_box(scene, llo, lhi, 0.0, id[M_LAMP], err)) != RS_OK)
			return st;
		return sg_finish(scene, lights, err);
	}
}
