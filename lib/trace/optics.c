/* Next-ray kernel of the reference renderer: mirror reflection, Snell refraction, Schlick
 * Fresnel, and the single-path rule that picks ONE continuation per hit (the GLES chain
 * traces one ray per pixel per pass, so there is no ray tree). */
#include "trace_internal.h"

void rs_trace_reflect(const double dir[3], const double normal[3], double out_dir[3])
{
	double k = 2.0 * rs_v3_dot(dir, normal);
	for (int a = 0; a < 3; ++a)
		out_dir[a] = dir[a] - k * normal[a];
}

bool rs_trace_refract(const double dir[3], const double normal[3], double eta, double out_dir[3])
{
	double cos_i = -rs_v3_dot(dir, normal);
	double sin2_t = eta * eta * fmax(0.0, 1.0 - cos_i * cos_i);
	if (sin2_t >= 1.0)
		return false;
	double cos_t = sqrt(1.0 - sin2_t);
	double t[3];
	for (int a = 0; a < 3; ++a)
		t[a] = eta * dir[a] + (eta * cos_i - cos_t) * normal[a];
	if (rs_v3_normalize(t) == 0.0)
		return false;
	for (int a = 0; a < 3; ++a)
		out_dir[a] = t[a];
	return true;
}

double rs_trace_fresnel_schlick(double cos_i, double n_from, double n_to)
{
	/* no interface, no reflection (plain Schlick would still give (1 - c)^5) */
	if (!(n_from > 0.0) || !(n_to > 0.0) || n_from == n_to)
		return 0.0;
	double c = fmin(fmax(fabs(cos_i), 0.0), 1.0);
	if (n_from > n_to) {
		/* going into the thinner medium: Schlick needs the transmitted angle */
		double eta = n_from / n_to;
		double sin2_t = eta * eta * (1.0 - c * c);
		if (sin2_t >= 1.0)
			return 1.0;
		c = sqrt(1.0 - sin2_t);
	}
	double r0 = (n_from - n_to) / (n_from + n_to);
	r0 *= r0;
	double m = 1.0 - c;
	double f = r0 + (1.0 - r0) * m * m * m * m * m;
	return fmin(fmax(f, 0.0), 1.0);
}

/* A direction computed with the interpolated normal can end up on the wrong side of the
 * real surface; then the geometric normal is used instead (always on the right side). */
static void reflect_dir(const double d[3], const struct rs_surface *s, double out[3])
{
	rs_trace_reflect(d, s->n, out);
	if (rs_v3_dot(out, s->ng) <= 0.0)
		rs_trace_reflect(d, s->ng, out);
	if (rs_v3_normalize(out) == 0.0)
		for (int a = 0; a < 3; ++a)
			out[a] = s->ng[a];
}

static bool refract_dir(const double d[3], const struct rs_surface *s, double eta, double out[3])
{
	if (rs_trace_refract(d, s->n, eta, out) && rs_v3_dot(out, s->ng) < 0.0)
		return true;
	return rs_trace_refract(d, s->ng, eta, out) && rs_v3_dot(out, s->ng) < 0.0;
}

enum rs_ray_state rs_trace_next_ray(const struct rs_trace_frame *frame, const struct rs_ray *ray,
                                    const struct rs_hit *hit, const struct rs_surface *s,
                                    struct rs_ray *next, double *out_weight)
{
	double wr = s->reflectance > 0.0f ? s->reflectance : 0.0;
	double wt = s->transmittance > 0.0f ? s->transmittance : 0.0;
	*out_weight = 0.0;
	if (wr <= 0.0 && wt <= 0.0)
		return RS_RAY_DIFFUSE;

	double ior = s->ior > 0.0f ? s->ior : 1.0;
	double n_from = s->entering ? 1.0 : ior;
	double n_to = s->entering ? ior : 1.0;
	double tdir[3] = {0.0, 0.0, 0.0};
	bool can_refract = wt > 0.0 && refract_dir(ray->dir, s, n_from / n_to, tdir);
	if (s->flags & RS_MATERIAL_FRESNEL) {
		double cos_i = -rs_v3_dot(ray->dir, s->n);
		double f = rs_trace_fresnel_schlick(cos_i, n_from, n_to);
		wr *= f;
		wt *= 1.0 - f;
	}
	if (wt > 0.0 && !can_refract) {
		/* total internal reflection: the transmitted share is reflected */
		wr += wt;
		wt = 0.0;
	}
	double dir[3];
	if (wt > wr) {
		for (int a = 0; a < 3; ++a)
			dir[a] = tdir[a];
		*out_weight = wt;
	} else {
		if (wr <= 0.0)
			return RS_RAY_DIFFUSE;
		reflect_dir(ray->dir, s, dir);
		*out_weight = wr;
	}
	rs_trace_spawn(s, dir, s->skip, next);
	return RS_RAY_ACTIVE;
}
