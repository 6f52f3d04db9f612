// optics.glsl: the next ray after a hit (lib/trace/optics.c in fp32): reflection,
// refraction with Schlick's Fresnel and total internal reflection, and the single-path rule
// that keeps ONE continuation. Without RS_OPTICS every path ends at its first hit (-3).

#if RS_OPTICS
bool rs_refract(vec3 d, vec3 n, float eta, out vec3 t)
{
	float ci = -dot(d, n);
	float s2 = eta * eta * max(0.0, 1.0 - ci * ci);
	if (s2 >= 1.0)
		return false;
	vec3 tt = eta * d + (eta * ci - sqrt(1.0 - s2)) * n;
	float tl = length(tt);
	if (!(tl > 0.0))
		return false;
	t = tt / tl;
	return true;
}

float rs_fresnel(float cos_i, float n_from, float n_to)
{
	if (!(n_from > 0.0) || !(n_to > 0.0) || n_from == n_to)
		return 0.0;
	float c = clamp(abs(cos_i), 0.0, 1.0);
	if (n_from > n_to) {
		float eta = n_from / n_to;
		float s2 = eta * eta * (1.0 - c * c);
		if (s2 >= 1.0)
			return 1.0;
		c = sqrt(1.0 - s2);
	}
	float r0 = (n_from - n_to) / (n_from + n_to);
	r0 *= r0;
	float m = 1.0 - c;
	return clamp(r0 + (1.0 - r0) * m * m * m * m * m, 0.0, 1.0);
}

// The single-path rule: ONE continuation (reflected or refracted) with its weight.
float rs_next_ray(Ray r, Hit h, Surf s, out Ray next, out float weight)
{
	float wr = max(s.reflectance, 0.0), wt = max(s.transmittance, 0.0);
	weight = 0.0;
	if (wr <= 0.0 && wt <= 0.0)
		return RS_STATE_DIFFUSE;
	float n_from = s.entering ? 1.0 : s.ior, n_to = s.entering ? s.ior : 1.0;
	vec3 tdir = vec3(0.0);
	bool can_refract = false;
	if (wt > 0.0) {
		float eta = n_from / n_to;
		can_refract = (rs_refract(r.d, s.n, eta, tdir) && dot(tdir, s.ng) < 0.0) ||
		              (rs_refract(r.d, s.ng, eta, tdir) && dot(tdir, s.ng) < 0.0);
	}
	if ((s.flags & RS_FRESNEL) != 0) {
		float f = rs_fresnel(-dot(r.d, s.n), n_from, n_to);
		wr *= f;
		wt *= 1.0 - f;
	}
	if (wt > 0.0 && !can_refract) {
		wr += wt;
		wt = 0.0;
	}
	vec3 dir;
	if (wt > wr) {
		dir = tdir;
		weight = wt;
	} else {
		if (wr <= 0.0)
			return RS_STATE_DIFFUSE;
		dir = reflect(r.d, s.n);
		if (dot(dir, s.ng) <= 0.0)
			dir = reflect(r.d, s.ng);
		float dl = length(dir);
		dir = dl > 0.0 ? dir / dl : s.ng;
		weight = wr;
	}
	next = rs_spawn(s, dir, h.slot);
	return RS_STATE_ACTIVE;
}
#else
float rs_next_ray(Ray r, Hit h, Surf s, out Ray next, out float weight)
{
	next = r;
	weight = 0.0;
	return RS_STATE_DIFFUSE;
}
#endif

