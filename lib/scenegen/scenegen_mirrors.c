/*
 * Mirrors: the scene of the paper's Table 3 (environment mapping against ray tracing),
 * which the paper only sizes (25,254 triangles). Three mirror spheres and an upright
 * mirror torus on a floor, ringed by nine coloured pillars: the spheres reflect each other
 * and the torus (inter-reflection), the torus's inner side reflects itself
 * (self-reflection), and the pillars and lights make parallax and shadows visible.
 * Triangles: floor 12 + pillars 9 x 12 + spheres 3 x 6,272 + torus 6,318 = 25,254.
 */
#include <math.h>
#include <stdlib.h>

#include "raystream/rs_scenegen.h"
#include "scenegen_internal.h"

#define SPHERE_SLICES 64u
#define SPHERE_RINGS 50u /* 2 * 64 * (50 - 1) = 6,272 triangles */
#define TORUS_AROUND 81u
#define TORUS_TUBE 39u /* 2 * 81 * 39 = 6,318 triangles */
#define PILLARS 9u

/* A smooth mesh: vertex grid of (a + 1) x (b + 1), so seams have their own vertices. */
struct grid {
	double *pos;
	float *nrm;
	uint32_t *idx;
	size_t verts, tris;
};

static enum rs_status grid_alloc(struct grid *g, uint32_t a, uint32_t b, struct rs_error *err)
{
	size_t v = (size_t)(a + 1) * (b + 1), t = (size_t)2 * a * b;
	g->pos = malloc(v * 3 * sizeof(*g->pos));
	g->nrm = malloc(v * 3 * sizeof(*g->nrm));
	g->idx = malloc(t * 3 * sizeof(*g->idx));
	g->verts = g->tris = 0;
	if (!g->pos || !g->nrm || !g->idx)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "mirrors scene: out of memory");
	return RS_OK;
}

static void grid_free(struct grid *g)
{
	free(g->pos);
	free(g->nrm);
	free(g->idx);
}

static void grid_vertex(struct grid *g, const double p[3], const double n[3])
{
	for (int k = 0; k < 3; k++) {
		g->pos[g->verts * 3 + k] = p[k];
		g->nrm[g->verts * 3 + k] = (float)n[k];
	}
	g->verts++;
}

static void grid_tri(struct grid *g, uint32_t a, uint32_t b, uint32_t c)
{
	g->idx[g->tris * 3 + 0] = a;
	g->idx[g->tris * 3 + 1] = b;
	g->idx[g->tris * 3 + 2] = c;
	g->tris++;
}

static enum rs_status grid_flush(struct rs_scene *scene, const struct grid *g, uint32_t material,
                                 struct rs_error *err)
{
	struct rs_mesh_desc d = {.positions_f64 = g->pos,
	                         .vertex_count = g->verts,
	                         .normals = g->nrm,
	                         .indices = g->idx,
	                         .triangle_count = g->tris,
	                         .material = material};
	enum rs_status st = rs_scene_add_mesh(scene, &d, err);
	return st == RS_OK ? RS_OK : rs_error_prefix(err, st, "mirrors scene");
}

/* UV sphere, outward winding; the pole rows are fans (one triangle per slice), so a sphere
 * is 2 * slices * (rings - 1) triangles with no degenerate ones. */
static enum rs_status add_sphere(struct rs_scene *scene, const double c[3], double r,
                                 uint32_t material, struct rs_error *err)
{
	const uint32_t s = SPHERE_SLICES, rings = SPHERE_RINGS;
	struct grid g;
	enum rs_status st = grid_alloc(&g, s, rings, err);
	for (uint32_t i = 0; st == RS_OK && i <= rings; i++) {
		double th = RS_PI * i / rings;
		for (uint32_t j = 0; j <= s; j++) {
			double ph = 2.0 * RS_PI * j / s;
			double n[3] = {sin(th) * cos(ph), cos(th), -sin(th) * sin(ph)};
			double p[3] = {c[0] + r * n[0], c[1] + r * n[1], c[2] + r * n[2]};
			grid_vertex(&g, p, n);
		}
	}
	for (uint32_t i = 0; st == RS_OK && i < rings; i++)
		for (uint32_t j = 0; j < s; j++) {
			uint32_t a = i * (s + 1) + j, b = a + s + 1;
			if (i != 0)
				grid_tri(&g, a, b, a + 1);
			if (i != rings - 1)
				grid_tri(&g, a + 1, b, b + 1);
		}
	if (st == RS_OK)
		st = grid_flush(scene, &g, material, err);
	grid_free(&g);
	return st;
}

/* Torus standing upright (axis along z) around c: major radius R, tube radius r. */
static enum rs_status add_torus(struct rs_scene *scene, const double c[3], double R, double r,
                                uint32_t material, struct rs_error *err)
{
	const uint32_t u = TORUS_AROUND, v = TORUS_TUBE;
	struct grid g;
	enum rs_status st = grid_alloc(&g, u, v, err);
	for (uint32_t i = 0; st == RS_OK && i <= u; i++) {
		double a = 2.0 * RS_PI * i / u;
		for (uint32_t j = 0; j <= v; j++) {
			double b = 2.0 * RS_PI * j / v;
			double n[3] = {cos(b) * cos(a), cos(b) * sin(a), sin(b)};
			double p[3] = {c[0] + (R + r * cos(b)) * cos(a),
			               c[1] + (R + r * cos(b)) * sin(a), c[2] + r * sin(b)};
			grid_vertex(&g, p, n);
		}
	}
	for (uint32_t i = 0; st == RS_OK && i < u; i++)
		for (uint32_t j = 0; j < v; j++) {
			uint32_t a = i * (v + 1) + j, b = a + v + 1;
			grid_tri(&g, a, b, a + 1);
			grid_tri(&g, a + 1, b, b + 1);
		}
	if (st == RS_OK)
		st = grid_flush(scene, &g, material, err);
	grid_free(&g);
	return st;
}

enum { M_FLOOR, M_MIRROR, M_GOLD, M_RED, M_GREEN, M_BLUE, M_COUNT };

static const struct rs_material k_mats[M_COUNT] = {
    [M_FLOOR] = {.diffuse = {0.75f, 0.75f, 0.75f}},
    [M_MIRROR] = {.diffuse = {0.05f, 0.05f, 0.05f}, .reflectance = 0.9f},
    [M_GOLD] = {.diffuse = {0.15f, 0.10f, 0.02f},
                .specular = 0.4f,
                .shininess = 64.0f,
                .reflectance = 0.8f},
    [M_RED] = {.diffuse = {0.70f, 0.10f, 0.08f}},
    [M_GREEN] = {.diffuse = {0.15f, 0.55f, 0.12f}},
    [M_BLUE] = {.diffuse = {0.15f, 0.25f, 0.75f}},
};

enum rs_status sg_build_mirrors(struct rs_scene *scene, struct rs_error *err)
{
	static const double lights[4][3] = {
	    {-6.0, 12.0, 8.0}, {7.0, 10.0, 5.0}, {0.0, 14.0, -7.0}, {-9.0, 6.0, -3.0}};
	/* Spheres rest SG_GLASS_GAP above the floor: a pole vertex on the floor plane would
	 * make the nearer of two equal hits a matter of rounding. */
	const double gap = SG_GLASS_GAP, r = 1.1;
	const double spheres[3][3] = {
	    {-2.0, r + gap, 0.9}, {2.0, r + gap, 0.9}, {0.0, r + gap, 3.0}};
	const double torus[3] = {0.0, 1.3 + 0.4 + gap, -2.2};
	const double floor_lo[3] = {-8.0, -0.5, -8.0}, floor_hi[3] = {8.0, 0.0, 8.0};
	uint32_t id[M_COUNT];
	struct rs_bounds all;
	enum rs_status st = RS_OK;

	for (int m = 0; m < M_COUNT && st == RS_OK; m++)
		st = sg_material(scene, &k_mats[m], &id[m], err);
	if (st == RS_OK)
		st = sg_add_box(scene, floor_lo, floor_hi, 0.0, id[M_FLOOR], err);
	/* Pillars on a circle of radius 6, red, green, blue in turn. */
	for (uint32_t p = 0; p < PILLARS && st == RS_OK; p++) {
		double a = 2.0 * RS_PI * (p + 0.5) / PILLARS;
		double lo[3] = {6.0 * cos(a) - 0.35, 0.0, 6.0 * sin(a) - 0.35};
		double hi[3] = {lo[0] + 0.7, 2.5 + 0.5 * (p % 3), lo[2] + 0.7};
		st = sg_add_box(scene, lo, hi, 360.0 * p / PILLARS, id[M_RED + p % 3], err);
	}
	for (int s = 0; s < 3 && st == RS_OK; s++)
		st = add_sphere(scene, spheres[s], r, id[M_MIRROR], err);
	if (st == RS_OK)
		st = add_torus(scene, torus, 1.3, 0.4, id[M_GOLD], err);
	if (st != RS_OK)
		return st;
	/* Frame the mirrors and the near pillars, not the whole floor. */
	all = (struct rs_bounds){{-4.0, 0.0, -3.5}, {4.0, 3.5, 4.5}};
	if ((st = sg_frame_camera(scene, &all, err)) != RS_OK)
		return st;
	return sg_finish(scene, lights, err);
}
