/*
 * Flat-shaded building blocks of the generated scenes. Every face gets its own vertices
 * with an explicit face normal: shared corners would give boxes and prisms smoothed,
 * wrong-looking normals under Phong interpolation.
 */
#include <math.h>
#include <string.h>

#include "raystream/rs_scene.h"
#include "private/rs_vec.h"
#include "scenegen_internal.h"

#define SG_MAX_VERTS 24
#define SG_MAX_TRIS 12

/* A small fixed-size mesh under construction. */
struct sg_mesh {
	double pos[SG_MAX_VERTS][3]; /* double: packing subtracts the centre before rounding */
	float nrm[SG_MAX_VERTS][3];
	uint32_t idx[SG_MAX_TRIS][3];
	size_t verts, tris;
};

/* A convex planar polygon (3 or 4 corners), wound so its normal faces `outward`. */
static void add_poly(struct sg_mesh *m, const double (*p)[3], size_t n, const double outward[3])
{
	double e1[3], e2[3], nrm[3], len;
	int flip;

	RS_ASSERT(n >= 3 && m->verts + n <= SG_MAX_VERTS && m->tris + n - 2 <= SG_MAX_TRIS);
	for (int k = 0; k < 3; k++) {
		e1[k] = p[1][k] - p[0][k];
		e2[k] = p[2][k] - p[0][k];
	}
	rs_v3_cross(e1, e2, nrm);
	flip = nrm[0] * outward[0] + nrm[1] * outward[1] + nrm[2] * outward[2] < 0.0;
	len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
	for (size_t i = 0; i < n; i++) {
		size_t src = flip ? n - 1 - i : i;

		for (int k = 0; k < 3; k++) {
			m->pos[m->verts + i][k] = p[src][k];
			m->nrm[m->verts + i][k] = (float)((flip ? -nrm[k] : nrm[k]) / len);
		}
	}
	for (size_t t = 0; t + 2 < n; t++) {
		m->idx[m->tris][0] = (uint32_t)m->verts;
		m->idx[m->tris][1] = (uint32_t)(m->verts + t + 1);
		m->idx[m->tris][2] = (uint32_t)(m->verts + t + 2);
		m->tris++;
	}
	m->verts += n;
}

static enum rs_status flush(struct rs_scene *scene, const struct sg_mesh *m, uint32_t material,
                            struct rs_error *err)
{
	struct rs_mesh_desc d;
	enum rs_status st;

	memset(&d, 0, sizeof(d));
	d.positions_f64 = &m->pos[0][0];
	d.vertex_count = m->verts;
	d.normals = &m->nrm[0][0];
	d.indices = &m->idx[0][0];
	d.triangle_count = m->tris;
	d.material = material;
	st = rs_scene_add_mesh(scene, &d, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "scene generator");
	return RS_OK;
}

enum rs_status sg_material(struct rs_scene *scene, const struct rs_material *m, uint32_t *out_id,
                           struct rs_error *err)
{
	enum rs_status st = rs_scene_add_material(scene, m, out_id, err);

	if (st != RS_OK)
		return rs_error_prefix(err, st, "scene generator");
	return RS_OK;
}

enum rs_status sg_add_box(struct rs_scene *scene, const double lo[3], const double hi[3],
                          double yaw_deg, uint32_t material, struct rs_error *err)
{
	struct sg_mesh m;
	double c[3], cs = cos(yaw_deg * RS_PI / 180.0), sn = sin(yaw_deg * RS_PI / 180.0);

	memset(&m, 0, sizeof(m));
	for (int k = 0; k < 3; k++)
		c[k] = 0.5 * (lo[k] + hi[k]);
	for (int axis = 0; axis < 3; axis++) {
		int u = (axis + 1) % 3, v = (axis + 2) % 3;

		for (int side = 0; side < 2; side++) {
			static const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
			double p[4][3], out[3] = {0.0, 0.0, 0.0}, r[3];

			for (int i = 0; i < 4; i++) {
				p[i][axis] = side ? hi[axis] : lo[axis];
				p[i][u] = corner[i][0] ? hi[u] : lo[u];
				p[i][v] = corner[i][1] ? hi[v] : lo[v];
				/* x' = x cos + z sin, z' = -x sin + z cos: +x turns towards -z. */
				r[0] = c[0] + (p[i][0] - c[0]) * cs + (p[i][2] - c[2]) * sn;
				r[2] = c[2] - (p[i][0] - c[0]) * sn + (p[i][2] - c[2]) * cs;
				p[i][0] = r[0];
				p[i][2] = r[2];
			}
			out[axis] = side ? 1.0 : -1.0;
			r[0] = out[0] * cs + out[2] * sn;
			r[2] = -out[0] * sn + out[2] * cs;
			out[0] = r[0];
			out[2] = r[2];
			add_poly(&m, (const double(*)[3])p, 4, out);
		}
	}
	return flush(scene, &m, material, err);
}

enum rs_status sg_add_prism(struct rs_scene *scene, const double base[3], double circumradius,
                            double height, uint32_t material, struct rs_error *err)
{
	struct sg_mesh m;
	double ring[2][3][3];
	static const double up[3] = {0.0, 1.0, 0.0}, down[3] = {0.0, -1.0, 0.0};

	memset(&m, 0, sizeof(m));
	for (int k = 0; k < 3; k++) {
		double a = k * 2.0 * RS_PI / 3.0; /* k = 0 points towards +z */

		for (int level = 0; level < 2; level++) {
			ring[level][k][0] = base[0] + circumradius * sin(a);
			ring[level][k][1] = base[1] + level * height;
			ring[level][k][2] = base[2] + circumradius * cos(a);
		}
	}
	add_poly(&m, (const double(*)[3])ring[0], 3, down);
	add_poly(&m, (const double(*)[3])ring[1], 3, up);
	for (int k = 0; k < 3; k++) {
		int j = (k + 1) % 3;
		double q[4][3], out[3];

		memcpy(q[0], ring[0][k], sizeof(q[0]));
		memcpy(q[1], ring[0][j], sizeof(q[1]));
		memcpy(q[2], ring[1][j], sizeof(q[2]));
		memcpy(q[3], ring[1][k], sizeof(q[3]));
		for (int c = 0; c < 3; c++)
			out[c] = 0.5 * (ring[0][k][c] + ring[0][j][c]) - base[c];
		out[1] = 0.0;
		add_poly(&m, (const double(*)[3])q, 4, out);
	}
	return flush(scene, &m, material, err);
}

enum rs_status sg_add_triangle(struct rs_scene *scene, const double a[3], const double b[3],
                               const double c[3], uint32_t material, struct rs_error *err)
{
	struct sg_mesh m;
	double p[3][3], e1[3], e2[3], n[3];

	memset(&m, 0, sizeof(m));
	memcpy(p[0], a, sizeof(p[0]));
	memcpy(p[1], b, sizeof(p[1]));
	memcpy(p[2], c, sizeof(p[2]));
	for (int k = 0; k < 3; k++) {
		e1[k] = b[k] - a[k];
		e2[k] = c[k] - a[k];
	}
	rs_v3_cross(e1, e2, n);
	add_poly(&m, (const double(*)[3])p, 3, n);
	return flush(scene, &m, material, err);
}

void sg_center(const struct rs_bounds *b, double out[3])
{
	for (int k = 0; k < 3; k++)
		out[k] = 0.5 * (b->lo[k] + b->hi[k]);
}

enum rs_status sg_frame_camera(struct rs_scene *scene, const struct rs_bounds *focus,
                               struct rs_error *err)
{
	struct rs_camera cam;
	enum rs_status st;

	memset(&cam, 0, sizeof(cam));
	cam.fov_y_deg = 45.0;
	cam.width = cam.height = 512;
	rs_camera_frame(focus, 30.0, &cam);
	st = rs_scene_set_camera(scene, &cam, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "scene generator: camera");
	return RS_OK;
}

enum rs_status sg_add_light(struct rs_scene *scene, const double pos[3], struct rs_error *err)
{
	struct rs_light l = {{pos[0], pos[1], pos[2]}, {1.0, 1.0, 1.0}};
	enum rs_status st = rs_scene_add_light(scene, &l, err);

	if (st != RS_OK)
		return rs_error_prefix(err, st, "scene generator: light");
	return RS_OK;
}

enum rs_status sg_set_environment(struct rs_scene *scene, struct rs_error *err)
{
	/* +x, -x, +y, -y, +z, -z: warm and cool hues far enough apart to tell faces apart in
	 * a reflection. */
	static const float faces[6][3] = {
	    {0.80f, 0.35f, 0.30f}, {0.30f, 0.65f, 0.35f}, {0.55f, 0.70f, 0.95f},
	    {0.40f, 0.33f, 0.25f}, {0.90f, 0.80f, 0.40f}, {0.55f, 0.40f, 0.80f},
	};
	struct rs_environment env;
	struct rs_bounds b;
	double extent = 0.0;
	enum rs_status st;

	rs_scene_bounds(scene, &b);
	memset(&env, 0, sizeof(env));
	sg_center(&b, env.center);
	for (int k = 0; k < 3; k++)
		extent = fmax(extent, b.hi[k] - b.lo[k]);
	env.half_size = 2.0 * extent; /* side 4x the largest extent */
	memcpy(env.face_color, faces, sizeof(faces));
	env.grid = 16;
	st = rs_scene_set_environment(scene, &env, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "scene generator: environment");
	return RS_OK;
}

enum rs_status sg_finish(struct rs_scene *scene, const double lights[4][3], struct rs_error *err)
{
	enum rs_status st;

	for (int l = 0; l < 4; l++)
		if ((st = sg_add_light(scene, lights[l], err)) != RS_OK)
			return st;
	if ((st = sg_set_environment(scene, err)) != RS_OK)
		return st;
	return rs_scene_set_ambient(scene, 0.1, err);
}
