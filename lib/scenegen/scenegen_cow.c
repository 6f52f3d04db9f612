/*
 * CowN (shared/SCENES.md): a herd of N turned copies of the cow on a 33-triangle stage.
 * All placement arithmetic is done in double and rounded to float once per coordinate.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scenegen.h"
#include "scenegen_internal.h"

#define COW_TURN_DEG 37.0
#define COW_LIFT 3.637
#define GRID_DX 12.0
#define GRID_DZ 8.0

/* Light offsets from the herd centre: L1..L4. */
static const double k_lights[4][3] = {
    {-10.0, 25.0, 20.0}, {15.0, 20.0, 10.0}, {0.0, 30.0, -15.0}, {-20.0, 12.0, -5.0}};

static void grid_shape(uint32_t n, uint32_t *cols, uint32_t *rows)
{
	uint32_t c = 1;

	while (c * c < n) /* ceil(sqrt(n)) without floating point */
		c++;
	*cols = c;
	*rows = (n + c - 1) / c;
}

enum rs_status sg_add_cow(struct rs_scene *scene, const struct rs_scene *cow, double yaw, double gx,
                          double gz, uint32_t mat, double *pos, float *nrm, struct rs_error *err)
{
	const float *p = rs_scene_positions(cow), *q = rs_scene_normals(cow);
	size_t verts = rs_scene_vertex_count(cow);
	struct rs_bounds b;
	struct rs_mesh_desc d;
	double cs = cos(yaw), sn = sin(yaw);
	double c[3];

	rs_scene_bounds(cow, &b);
	sg_center(&b, c);
	for (size_t v = 0; v < verts; v++) {
		double x = p[3 * v] - c[0], z = p[3 * v + 2] - c[2];

		/* Right-handed turn about +y (+x towards -z), pivot on the grid point. */
		/* kept in double: packing subtracts the scene centre before rounding */
		pos[3 * v] = gx + x * cs + z * sn;
		pos[3 * v + 1] = p[3 * v + 1] + COW_LIFT;
		pos[3 * v + 2] = gz - x * sn + z * cs;
		nrm[3 * v] = (float)(q[3 * v] * cs + q[3 * v + 2] * sn);
		nrm[3 * v + 1] = q[3 * v + 1];
		nrm[3 * v + 2] = (float)(-q[3 * v] * sn + q[3 * v + 2] * cs);
	}
	memset(&d, 0, sizeof(d));
	d.positions_f64 = pos;
	d.vertex_count = verts;
	d.normals = nrm;
	d.indices = rs_scene_indices(cow);
	d.triangle_count = rs_scene_triangle_count(cow);
	d.material = mat;
	return rs_scene_add_mesh(scene, &d, err);
}

/* The walk of the moving cow of an animated CowN (rs_scenegen_desc.frame): a sway of
 * +-1.5 along z and +-25 degrees of yaw, period 4 s, zero at frame 0. */
static void sway(uint32_t frame, uint32_t fps, double *dz, double *dyaw)
{
	double s = sin(2.0 * RS_PI * ((double)frame / (double)fps) / 4.0);
	*dz = 1.5 * s;
	*dyaw = 25.0 * RS_PI / 180.0 * s;
}

/* Adds copy i of the cow (positions/normals from `cow`) with material `mat`; copy n / 2
 * sways when frame > 0 (the others stand still). */
static enum rs_status add_copy(struct rs_scene *scene, const struct rs_scene *cow, uint32_t i,
                               uint32_t n, uint32_t mat, uint32_t frame, uint32_t fps, double *pos,
                               float *nrm, struct rs_error *err)
{
	uint32_t cols, rows;
	double a = (double)i * COW_TURN_DEG * RS_PI / 180.0, gx, gz, dz = 0.0, dyaw = 0.0;
	enum rs_status st;

	grid_shape(n, &cols, &rows);
	gx = ((double)(i % cols) - 0.5 * (double)(cols - 1)) * GRID_DX;
	gz = ((double)(i / cols) - 0.5 * (double)(rows - 1)) * GRID_DZ;
	if (frame > 0 && i == n / 2)
		sway(frame, fps, &dz, &dyaw);
	st = sg_add_cow(scene, cow, a + dyaw, gx, gz + dz, mat, pos, nrm, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "cow copy %u", i);
	return RS_OK;
}

enum rs_status sg_load_cow(const char *cow_path, struct rs_scene **out, double **pos, float **nrm,
                           struct rs_error *err)
{
	enum rs_status st;

	*out = NULL;
	*pos = NULL;
	*nrm = NULL;
	if (cow_path == NULL)
		return rs_error_set(err, RS_ERR_INVALID, "cow scene: no cow model path given");
	st = rs_scene_create(NULL, out, err);
	if (st == RS_OK)
		st = rs_load_mesh_file(NULL, cow_path, *out, err);
	if (st == RS_OK) {
		*pos = malloc(rs_scene_vertex_count(*out) * 3 * sizeof(**pos));
		*nrm = malloc(rs_scene_vertex_count(*out) * 3 * sizeof(**nrm));
		if (*pos == NULL || *nrm == NULL)
			st = rs_error_set(err, RS_ERR_NO_MEMORY, "cow scene: out of memory");
	}
	if (st != RS_OK) {
		free(*pos);
		free(*nrm);
		*pos = NULL;
		*nrm = NULL;
		rs_scene_destroy(out);
	}
	return st;
}

/* Instance i of the prototype cow: add_copy's turn, placement and sway as a transform. */
static enum rs_status add_instance(struct rs_scene *scene, const struct rs_scene *cow,
                                   uint32_t proto, uint32_t i, uint32_t n, uint32_t frame,
                                   uint32_t fps, struct rs_error *err)
{
	struct rs_bounds b;
	uint32_t cols, rows;
	double dz = 0.0, dyaw = 0.0;
	if (frame > 0 && i == n / 2)
		sway(frame, fps, &dz, &dyaw);
	double a = (double)i * COW_TURN_DEG * RS_PI / 180.0 + dyaw, cs = cos(a), sn = sin(a), c[3];

	grid_shape(n, &cols, &rows);
	double gx = ((double)(i % cols) - 0.5 * (double)(cols - 1)) * GRID_DX;
	double gz = ((double)(i / cols) - 0.5 * (double)(rows - 1)) * GRID_DZ + dz;
	rs_scene_bounds(cow, &b);
	sg_center(&b, c);
	struct rs_instance_desc d = {.mesh = proto,
	                             .transform = {{cs, 0.0, sn, gx - cs * c[0] - sn * c[2]},
	                                           {0.0, 1.0, 0.0, COW_LIFT},
	                                           {-sn, 0.0, cs, gz + sn * c[0] - cs * c[2]}}};
	enum rs_status st = rs_scene_add_instance(scene, &d, NULL, err);
	return st == RS_OK ? RS_OK : rs_error_prefix(err, st, "cow instance %u", i);
}

static enum rs_status add_herd(struct rs_scene *scene, const char *cow_path, uint32_t n,
                               uint32_t frame, uint32_t fps, bool instanced, struct rs_error *err)
{
	struct rs_scene *cow = NULL;
	float *buf = NULL;
	double *pos = NULL;
	uint32_t mat;
	enum rs_status st = sg_load_cow(cow_path, &cow, &pos, &buf, err);

	if (st == RS_OK)
		st = sg_material(scene, &sg_cow_material, &mat, err);
	uint32_t proto = 0;
	if (st == RS_OK && instanced) {
		struct rs_mesh_desc d = {.positions = rs_scene_positions(cow),
		                         .vertex_count = rs_scene_vertex_count(cow),
		                         .normals = rs_scene_normals(cow),
		                         .indices = rs_scene_indices(cow),
		                         .triangle_count = rs_scene_triangle_count(cow),
		                         .material = mat};
		st = rs_scene_add_prototype(scene, &d, &proto, err);
	}
	for (uint32_t i = 0; st == RS_OK && i < n; i++)
		st = instanced ? add_instance(scene, cow, proto, i, n, frame, fps, err)
		               : add_copy(scene, cow, i, n, mat, frame, fps, pos, buf, err);
	free(pos);
	free(buf);
	rs_scene_destroy(&cow);
	return st;
}

/* Floor slab, mirror panel, glass prism and sail around the herd bounds `h`. */
static enum rs_status add_stage(struct rs_scene *scene, const struct rs_bounds *h,
                                struct rs_error *err)
{
	static const struct rs_material floor_m = {.diffuse = {0.8f, 0.8f, 0.8f}};
	static const struct rs_material mirror_m = {.diffuse = {0.1f, 0.1f, 0.1f},
	                                            .reflectance = 0.9f};
	static const struct rs_material prism_m = {.transmittance = 0.9f, .ior = 1.5f};
	static const struct rs_material sail_m = {.diffuse = {0.2f, 0.4f, 0.8f}};
	const double lean = 30.0 * RS_PI / 180.0;
	const double sail_x = h->lo[0] + 0.125 * (h->hi[0] - h->lo[0]), sail_y = h->hi[1] + 1.0;
	const double cx = 0.5 * (h->lo[0] + h->hi[0]), cz = 0.5 * (h->lo[2] + h->hi[2]);
	/* Floor: top at y = 0, 0.5 thick, 4 larger than the herd on every side. */
	const double lo[3] = {h->lo[0] - 4.0, -0.5, h->lo[2] - 4.0};
	const double hi[3] = {h->hi[0] + 4.0, 0.0, h->hi[2] + 4.0};
	/* Mirror: on the floor's back (-z) edge, as wide as the floor, y 0..8, 0.3 thick. */
	const double mlo[3] = {lo[0], 0.0, lo[2]}, mhi[3] = {hi[0], 8.0, lo[2] + 0.3};
	/* Prism: at the herd's x centre, 2 beyond its front (+z), standing on the floor. It
	 * floats SG_GLASS_GAP above it: a glass face coplanar with the floor makes the nearer
	 * of two equal hits a matter of rounding, which no GPU backend could reproduce. */
	const double base[3] = {cx, SG_GLASS_GAP, h->hi[2] + 2.0};
	/* Sail, 5 x 3.5: lowest edge 1 above the herd, centred over its left (-x) quarter at
	 * the herd's centre z, leaning back 30 degrees so it faces the camera. */
	const double a[3] = {sail_x - 2.5, sail_y, cz}, b[3] = {sail_x + 2.5, sail_y, cz};
	const double apex[3] = {sail_x, sail_y + 3.5 * cos(lean), cz - 3.5 * sin(lean)};
	uint32_t floor_id, mirror_id, prism_id, sail_id;
	enum rs_status st;

	if ((st = sg_material(scene, &floor_m, &floor_id, err)) != RS_OK ||
	    (st = sg_material(scene, &mirror_m, &mirror_id, err)) != RS_OK ||
	    (st = sg_material(scene, &prism_m, &prism_id, err)) != RS_OK ||
	    (st = sg_material(scene, &sail_m, &sail_id, err)) != RS_OK)
		return st;
	if ((st = sg_add_box(scene, lo, hi, 0.0, floor_id, err)) != RS_OK ||
	    (st = sg_add_box(scene, mlo, mhi, 0.0, mirror_id, err)) != RS_OK ||
	    (st = sg_add_prism(scene, base, 1.2, 3.0, prism_id, err)) != RS_OK ||
	    (st = sg_add_triangle(scene, a, b, apex, sail_id, err)) != RS_OK)
		return st;
	return RS_OK;
}

const struct rs_material sg_cow_material = {
    .diffuse = {0.55f, 0.40f, 0.30f}, .specular = 0.3f, .shininess = 32.0f, .reflectance = 0.25f};

/* The herd's bounds at rest (frame 0): the stage, camera, lights and environment of an
 * animated CowN stay where frame 0 has them, so every frame has the same topology and
 * only the moving cow's vertices differ (CowNi: its transform; the stage is the same to the
 * bit, from the same instanced herd, so its plain triangles never move). */
static enum rs_status rest_bounds(const char *cow_path, uint32_t n, bool instanced,
                                  struct rs_bounds *out, struct rs_error *err)
{
	struct rs_scene *rest = NULL;
	enum rs_status st = rs_scene_create(NULL, &rest, err);

	if (st == RS_OK)
		st = add_herd(rest, cow_path, n, 0, 1, instanced, err);
	if (st == RS_OK)
		rs_scene_bounds(rest, out);
	rs_scene_destroy(&rest);
	return st;
}

enum rs_status sg_build_cows(struct rs_scene *scene, const char *cow_path, uint32_t n,
                             uint32_t frame, uint32_t fps, bool instanced, struct rs_error *err)
{
	struct rs_bounds herd;
	double c[3];
	enum rs_status st = add_herd(scene, cow_path, n, frame, fps, instanced, err);

	if (st != RS_OK)
		return st;
	if (frame == 0)
		rs_scene_bounds(scene, &herd);
	else if ((st = rest_bounds(cow_path, n, instanced, &herd, err)) != RS_OK)
		return st;
	sg_center(&herd, c);
	if ((st = add_stage(scene, &herd, err)) != RS_OK ||
	    (st = sg_frame_camera(scene, &herd, err)) != RS_OK)
		return st;
	for (int l = 0; l < 4; l++) {
		double p[3] = {c[0] + k_lights[l][0], c[1] + k_lights[l][1], c[2] + k_lights[l][2]};

		if ((st = sg_add_light(scene, p, err)) != RS_OK)
			return st;
	}
	if ((st = sg_set_environment(scene, err)) != RS_OK)
		return st;
	if (frame > 0) {
		/* the environment cube sits on the whole scene's bounds, which the swaying cow
		 * may push out: frame 0's cube, so every frame has the same environment */
		struct rs_scene *rest = NULL;
		struct rs_environment env;
		st = rs_scene_create(NULL, &rest, err);
		if (st == RS_OK)
			st = sg_build_cows(rest, cow_path, n, 0, fps, instanced, err);
		if (st == RS_OK) {
			rs_scene_environment(rest, &env);
			st = rs_scene_set_environment(scene, &env, err);
		}
		rs_scene_destroy(&rest);
		if (st != RS_OK)
			return st;
	}
	return rs_scene_set_ambient(scene, 0.1, err);
}
