/* Shading kernel of the reference renderer: surface data at a hit (read from the packed
 * textures, as the GLES kernel reads them), Phong lighting with shadow feelers, and the
 * self-hit rule for rays leaving a surface. */
#include <string.h>

#include "intersect_internal.h"
#include "trace_internal.h"

static void texel3(const float *t, double out[3])
{
	out[0] = t[0];
	out[1] = t[1];
	out[2] = t[2];
}

void rs_trace_spawn(const struct rs_surface *s, const double dir[3], uint32_t slot,
                    struct rs_ray *out)
{
	/* Off the own plane to the side the ray leaves on; the pull in rs_trace_surface()
	 * already keeps the point off the neighbours' planes. The skip slot is exact and free:
	 * a ray leaving a flat triangle can never hit it again. */
	double side = rs_v3_dot(dir, s->ng) >= 0.0 ? s->delta : -s->delta;
	rs_v3_madd(s->point, side, s->ng, out->origin);
	for (int a = 0; a < 3; ++a)
		out->dir[a] = dir[a];
	out->tmin = 0.0;
	out->tmax = INFINITY;
	out->skip_slot = slot;
}

static double max2(double a, double b)
{
	return a > b ? a : b; /* no NaN here: the packed vertices are finite */
}

static double maxabs9(const double v0[3], const double v1[3], const double v2[3])
{
	double m = 0.0;
	for (int a = 0; a < 3; ++a)
		m = max2(m, max2(fabs(v0[a]), max2(fabs(v1[a]), fabs(v2[a]))));
	return m;
}

static double dist3(const double a[3], const double b[3])
{
	double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
	return sqrt(rs_v3_dot(d, d));
}

/* docs/tracer.md R5: the hit point from the barycentrics, pulled at least ~4 delta away from
 * every edge (small triangles: to the centroid), so that it lies inside the triangle by
 * more than rounding and thus in front of every neighbour's plane at a concave edge. */
static void spawn_point(const double v0[3], const double v1[3], const double v2[3], double u,
                        double v, const struct rs_trace_frame *frame, struct rs_surface *out)
{
	double e1[3], e2[3], c[3];
	for (int a = 0; a < 3; ++a) {
		e1[a] = v1[a] - v0[a];
		e2[a] = v2[a] - v0[a];
	}
	rs_v3_cross(e1, e2, c);
	double a2 = sqrt(rs_v3_dot(c, c));
	/* The floor: near the frame's centre a triangle's own coordinates are small, but its
	 * neighbours' planes are only known to the rounding of theirs (fp32 kernels). */
	double delta = frame->spawn_scale * max2(maxabs9(v0, v1, v2), frame->spawn_floor);
	double edge[3] = {dist3(v2, v1), dist3(v0, v2), dist3(v1, v0)};
	double b[3] = {1.0 - u - v, u, v}, sum = 0.0;
	for (int i = 0; i < 3; ++i) {
		double h = edge[i] > 0.0 ? a2 / edge[i] : 0.0;
		double floor_i = h > frame->rules.spawn_pull_height * delta
		                     ? frame->rules.spawn_pull * delta / h
		                     : 1.0 / 3.0;
		b[i] = max2(b[i], floor_i);
		sum += b[i];
	}
	for (int a = 0; a < 3; ++a)
		out->point[a] = v0[a] + (b[1] / sum) * e1[a] + (b[2] / sum) * e2[a];
	out->delta = delta;
}

/* The hit triangle as shading reads it: vertices (packed frame) and vertex normals, the
 * barycentrics and the material. A two-level hit's object-space triangle goes through its
 * instance's to_world and to_world_normal (instance texture, as the kernels read them); a
 * mirrored instance's is rewound (v1 <-> v2, u <-> v) as the baked scene's is. */
struct hit_triangle {
	double v[3][3], n[3][3], u, w;
	float material;
};

static void read_hit_triangle(const struct rs_trace_frame *frame, const struct rs_hit *hit,
                              struct hit_triangle *h)
{
	const struct rs_packed *p = frame->packed;
	for (uint32_t k = 0; k < 3; k++) {
		texel3(rs_pack_texel(&p->triangles, RS_PACK_TRIANGLE_TEXELS, hit->slot, k),
		       h->v[k]);
		texel3(rs_pack_texel(&p->normals, RS_PACK_NORMAL_TEXELS, hit->slot, k), h->n[k]);
	}
	h->material = rs_pack_texel(&p->triangles, RS_PACK_TRIANGLE_TEXELS, hit->slot, 1)[3];
	h->u = hit->u;
	h->w = hit->v;
	const struct rs_packed_two_level *two = frame->two_level;
	if (!two || hit->instance >= two->instance_count)
		return;
	const float *t = rs_pack_texel(&two->instances, RS_PACK_INSTANCE_TEXELS, hit->instance, 0);
	for (uint32_t k = 0; k < 3; k++) {
		double v[3], n[3];
		memcpy(v, h->v[k], sizeof v);
		memcpy(n, h->n[k], sizeof n);
		for (int r = 0; r < 3; r++) {
			const float *a = t + 4 * (3 + r), *m = t + 4 * (6 + r);
			h->v[k][r] = a[0] * v[0] + a[1] * v[1] + a[2] * v[2] + a[3];
			h->n[k][r] = m[0] * n[0] + m[1] * n[1] + m[2] * n[2];
		}
		/* unit, as the baked scene's vertex normals are (interpolation weights them) */
		rs_v3_normalize(h->n[k]);
	}
	if (t[4 * 7 + 3] >= 0.0f)
		h->material = t[4 * 7 + 3];
	if (t[4 * 8 + 3] != 0.0f) {
		double s[3];
		memcpy(s, h->v[1], sizeof s);
		memcpy(h->v[1], h->v[2], sizeof s);
		memcpy(h->v[2], s, sizeof s);
		memcpy(s, h->n[1], sizeof s);
		memcpy(h->n[1], h->n[2], sizeof s);
		memcpy(h->n[2], s, sizeof s);
		h->u = hit->v;
		h->w = hit->u;
	}
}

void rs_trace_surface(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                      const struct rs_hit *hit, struct rs_surface *out)
{
	const struct rs_packed *p = frame->packed;
	struct hit_triangle h;
	read_hit_triangle(frame, hit, &h);
	double *v0 = h.v[0], *v1 = h.v[1], *v2 = h.v[2], e1[3], e2[3], g[3];
	float material_f = h.material;
	out->skip = frame->two_level ? hit->triangle : hit->slot;

	spawn_point(v0, v1, v2, h.u, h.w, frame, out);
	for (int a = 0; a < 3; ++a) {
		e1[a] = v1[a] - v0[a];
		e2[a] = v2[a] - v0[a];
	}
	rs_v3_cross(e1, e2, g);
	if (rs_v3_normalize(g) == 0.0) {
		/* (near-)zero area: no plane to speak of, face the ray */
		for (int a = 0; a < 3; ++a)
			g[a] = -ray->dir[a];
	}
	double dg = rs_v3_dot(ray->dir, g);
	out->entering = dg < 0.0;
	for (int a = 0; a < 3; ++a)
		out->ng[a] = dg < 0.0 ? g[a] : -g[a];

	/* Phong normal: the hit's barycentric u, v weight n1, n2 (n0 gets 1 - u - v). The
	 * surface is double-sided: the normal is turned to the geometric side facing the ray. */
	double w0 = 1.0 - h.u - h.w, *n0 = h.n[0], *n1 = h.n[1], *n2 = h.n[2];
	for (int a = 0; a < 3; ++a)
		out->n[a] = w0 * n0[a] + h.u * n1[a] + h.w * n2[a];
	if (rs_v3_normalize(out->n) == 0.0)
		memcpy(out->n, out->ng, sizeof out->n);
	else if (rs_v3_dot(out->n, out->ng) < 0.0)
		for (int a = 0; a < 3; ++a)
			out->n[a] = -out->n[a];

	memset(out->diffuse, 0, sizeof out->diffuse);
	out->specular = out->reflectance = out->transmittance = 0.0f;
	out->shininess = out->ior = 1.0f;
	out->flags = 0;
	if (material_f >= 0.0f && material_f < (float)p->material_count) {
		uint32_t m = (uint32_t)material_f;
		const float *t0 = rs_pack_texel(&p->materials, RS_PACK_MATERIAL_TEXELS, m, 0);
		const float *t1 = rs_pack_texel(&p->materials, RS_PACK_MATERIAL_TEXELS, m, 1);
		const float *t2 = rs_pack_texel(&p->materials, RS_PACK_MATERIAL_TEXELS, m, 2);
		memcpy(out->diffuse, t0, sizeof out->diffuse);
		out->specular = t0[3];
		out->shininess = t1[0] > 0.0f ? t1[0] : 1.0f;
		out->reflectance = t1[1];
		out->transmittance = t1[2];
		out->ior = t1[3] > 0.0f ? t1[3] : 1.0f;
		out->flags = t2[0] >= 0.0f && t2[0] < 4294967296.0f ? (uint32_t)t2[0] : 0u;
	}
}

/* Whether the light at lp (unit direction l from the surface) reaches s: one exact shadow
 * feeler from the spawned point to the light, counted in path. */
static bool lit_by(const struct rs_trace_frame *frame, const struct rs_surface *s,
                   const double l[3], const double lp[3], struct rs_trace_path *path)
{
	struct rs_ray feeler;
	rs_trace_spawn(s, l, s->skip, &feeler);
	for (int a = 0; a < 3; ++a)
		feeler.dir[a] = lp[a] - feeler.origin[a];
	feeler.tmax = rs_v3_normalize(feeler.dir);
	if (feeler.tmax == 0.0)
		return false;
	path->shadow_rays++;
	return !(frame->has_geometry && rs_trace_frame_occluded(frame, &feeler, &path->counters));
}

void rs_trace_shade(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                    const struct rs_hit *hit, const struct rs_surface *s, double throughput,
                    double rgb[3], struct rs_trace_path *path)
{
	double local[3];
	for (int c = 0; c < 3; ++c)
		local[c] = frame->ambient * s->diffuse[c];
	double view[3] = {-ray->dir[0], -ray->dir[1], -ray->dir[2]};

	for (uint32_t i = 0; i < frame->light_count; ++i) {
		const struct rs_light *light = &frame->lights[i];
		double lp[3];
		rs_trace_frame_light(frame, i, lp);
		double l[3] = {lp[0] - s->point[0], lp[1] - s->point[1], lp[2] - s->point[2]};
		if (rs_v3_normalize(l) == 0.0)
			continue;
		/* A light behind the surface (geometrically, or for the Phong normal) adds
		 * nothing, and no feeler is traced for it. */
		double n_dot_l = rs_v3_dot(s->n, l);
		if (rs_v3_dot(s->ng, l) <= 0.0 || n_dot_l <= 0.0)
			continue;
		if (!frame->unshadowed && !lit_by(frame, s, l, lp, path))
			continue;
		double spec = 0.0;
		if (s->specular > 0.0f) {
			double r[3];
			for (int a = 0; a < 3; ++a)
				r[a] = 2.0 * n_dot_l * s->n[a] - l[a];
			double r_dot_v = rs_v3_dot(r, view);
			if (r_dot_v > 0.0)
				spec = s->specular * pow(fmin(r_dot_v, 1.0), s->shininess);
		}
		for (int c = 0; c < 3; ++c)
			local[c] += light->color[c] * (s->diffuse[c] * n_dot_l + spec);
	}
	for (int c = 0; c < 3; ++c)
		rgb[c] += throughput * local[c];
}
