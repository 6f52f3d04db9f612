// surface.glsl: what the shading and next-ray kernels know about a hit, and the rays that
// leave it (lib/trace/shade.c, optics.c, environment.c in fp32).
// Inputs: u_ambient, u_light_pos[], u_light_color[] (RS_LIGHT_SLOTS >= RS_LIGHTS), the environment
//         cube (u_env_*), and common.glsl's textures.

uniform float u_ambient;
uniform vec3 u_light_pos[RS_LIGHT_SLOTS];
uniform vec3 u_light_color[RS_LIGHT_SLOTS];
uniform vec3 u_env_center;
uniform float u_env_half;
uniform vec3 u_env_color[6];
uniform float u_env_grid;
uniform float u_env_line_width;
uniform float u_env_line_scale;

const int RS_FRESNEL = 1;

struct Surf {
	vec3 p;      // R5's point: from the barycentrics, pulled into the triangle
	float delta; // R5's offset for rays leaving here
	vec3 ng; // unit geometric normal facing the ray
	vec3 n;  // unit shading normal on ng's side
	bool entering;
	vec3 diffuse;
	float specular, shininess, reflectance, transmittance, ior;
	int flags;
};

Surf rs_surface(Ray r, Hit h)
{
	Surf s;
	vec4 t0 = g_hit_v0, t1 = g_hit_v1, t2 = g_hit_v2; // common.glsl's cache
	if (h.slot != g_hit_slot) {
		t0 = rs_tri(h.slot, 0);
		t1 = rs_tri(h.slot, 1);
		t2 = rs_tri(h.slot, 2);
	}
	vec3 e1 = t1.xyz - t0.xyz, e2 = t2.xyz - t0.xyz;
	vec3 g = cross(e1, e2);
	float gl = length(g);
	// R5: pulled at least ~4 delta away from every edge (small triangles: the centroid),
	// so the point lies in front of every neighbour's plane at a concave edge.
	vec3 m3 = max(max(abs(t0.xyz), abs(t1.xyz)), abs(t2.xyz));
	s.delta = u_spawn_scale * max(max(max(m3.x, m3.y), m3.z), u_spawn_floor);
	vec3 edge = vec3(length(t2.xyz - t1.xyz), length(t0.xyz - t2.xyz), length(e1));
	vec3 b = vec3(1.0 - h.u - h.v, h.u, h.v);
	for (int i = 0; i < 3; i++) {
		float hi = edge[i] > 0.0 ? gl / edge[i] : 0.0;
		b[i] = max(b[i], hi > RS_SPAWN_PULL_HEIGHT * s.delta ? RS_SPAWN_PULL * s.delta / hi
		                                                  : 1.0 / 3.0);
	}
	float bs = b.x + b.y + b.z;
	s.p = t0.xyz + (b.y / bs) * e1 + (b.z / bs) * e2;
	g = gl > 0.0 ? g / gl : -r.d;
	float dg = dot(r.d, g);
	s.entering = dg < 0.0;
	s.ng = dg < 0.0 ? g : -g;
	vec3 n = (1.0 - h.u - h.v) * rs_normal(h.slot, 0).xyz + h.u * rs_normal(h.slot, 1).xyz +
	         h.v * rs_normal(h.slot, 2).xyz;
	float nl = length(n);
	s.n = nl > 0.0 && nl < RS_FAR ? n / nl : s.ng;
	if (dot(s.n, s.ng) < 0.0)
		s.n = -s.n;
	s.diffuse = vec3(0.0);
	s.specular = s.reflectance = s.transmittance = 0.0;
	s.shininess = s.ior = 1.0;
	s.flags = 0;
	if (t1.w >= 0.0 && t1.w < float(u_material_count)) {
		int m = int(t1.w);
		vec4 m0 = rs_material(m, 0), m1 = rs_material(m, 1), m2 = rs_material(m, 2);
		s.diffuse = m0.rgb;
		s.specular = m0.a;
		s.shininess = m1.x > 0.0 ? m1.x : 1.0;
		s.reflectance = m1.y;
		s.transmittance = m1.z;
		s.ior = m1.w > 0.0 ? m1.w : 1.0;
		s.flags = m2.x >= 0.0 ? int(m2.x) : 0;
	}
	return s;
}

// A ray leaving the surface (R5): from the pulled-in point, delta off the own plane to the
// side it leaves on, never the same triangle again.
Ray rs_spawn(Surf s, vec3 dir, int slot)
{
	float side = dot(dir, s.ng) >= 0.0 ? s.delta : -s.delta;
	return Ray(s.p + side * s.ng, dir, RS_FAR, slot);
}

bool rs_grid_line(float pos)
{
	float g = pos * u_env_grid;
	float frac = g - floor(g);
	return min(frac, 1.0 - frac) < 0.5 * u_env_line_width;
}

// Environment cube colour where the ray leaves it (exit point, not direction: no parallax).
vec3 rs_environment(vec3 o, vec3 d)
{
	int axis = -1;
	float best = RS_FAR;
	for (int a = 0; a < 3; a++) {
		if (d[a] == 0.0)
			continue;
		float plane = u_env_center[a] + (d[a] > 0.0 ? u_env_half : -u_env_half);
		float t = (plane - o[a]) / d[a];
		if (t < best) {
			best = t;
			axis = a;
		}
	}
	vec3 p = u_env_center;
	int face = 0;
	if (axis < 0) {
		axis = 0;
		p.x += u_env_half;
	} else {
		p = o + best * d;
		p[axis] = u_env_center[axis] + (d[axis] > 0.0 ? u_env_half : -u_env_half);
		face = 2 * axis + (d[axis] > 0.0 ? 0 : 1);
	}
	int as = (axis + 1) % 3, at = (axis + 2) % 3;
	float fs = clamp(0.5 * ((p[as] - u_env_center[as]) / u_env_half + 1.0), 0.0, 1.0);
	float ft = clamp(0.5 * ((p[at] - u_env_center[at]) / u_env_half + 1.0), 0.0, 1.0);
	bool line = rs_grid_line(fs) || rs_grid_line(ft);
	return u_env_color[face] * (line ? u_env_line_scale : 1.0);
}

#if RS_SHADOW_MAP
uniform sampler2DArray u_shadow; // layer 6 light + face: distance to the nearest surface
uniform int u_shadow_size;
uniform int u_shadow_filter; // box filter side in texels

// The cube face (0..5: +x, -x, +y, -y, +z, -z) a direction q from the light falls on (its
// major axis) and q's texel there: (q[a+1], q[a+2]) / |q[a]| as shadow_vertex.glsl
// projects. q must not be 0.
ivec3 rs_shadow_texel(vec3 q)
{
	vec3 aq = abs(q);
	int axis = aq.x >= aq.y && aq.x >= aq.z ? 0 : (aq.y >= aq.z ? 1 : 2);
	vec2 uv = vec2(q[(axis + 1) % 3], q[(axis + 2) % 3]) / aq[axis];
	float size = float(u_shadow_size);
	ivec2 t = ivec2(clamp(floor((uv * 0.5 + 0.5) * size), 0.0, size - 1.0));
	return ivec3(t, 2 * axis + (q[axis] > 0.0 ? 0 : 1));
}

// Share of the box-filtered cube map texels around the direction light -> p that see p
// (paper: shadow maps with a box filter). The box is seamless: a tap that falls off p's
// face is turned back into the direction through its texel centre (the face's axis and
// its (s, t) beyond +-1) and read on the face that direction falls on, so a point near a
// face edge gets the same centred box as anywhere else. The bias grows with the filter's
// reach and the slope (cos_l = Ng . L): a texel k steps away samples the surface up to k
// footprints / cos_l nearer the light, which must not shadow p itself.
float rs_shadow_lit(int light, vec3 p, float cos_l)
{
	vec3 q = p - u_light_pos[light];
	if (!(max(max(abs(q.x), abs(q.y)), abs(q.z)) > 0.0))
		return 1.0;
	ivec3 c = rs_shadow_texel(q);
	int axis = c.z / 2;
	float side = c.z % 2 == 0 ? 1.0 : -1.0;
	float size = float(u_shadow_size);
	float dist = length(q);
	int half_width = u_shadow_filter / 2;
	float footprint = 2.0 * dist / size;
	float bias = footprint * (1.5 + float(half_width)) / max(cos_l, 0.05);
	float lit = 0.0, n = 0.0;
	for (int dy = 0; dy < u_shadow_filter; dy++)
		for (int dx = 0; dx < u_shadow_filter; dx++) {
			ivec3 t = ivec3(c.xy + ivec2(dx, dy) - half_width, c.z);
			if (any(lessThan(t.xy, ivec2(0))) ||
			    any(greaterThanEqual(t.xy, ivec2(u_shadow_size)))) {
				vec2 st = (vec2(t.xy) + 0.5) / size * 2.0 - 1.0;
				vec3 d;
				d[axis] = side;
				d[(axis + 1) % 3] = st.x;
				d[(axis + 2) % 3] = st.y;
				t = rs_shadow_texel(d);
			}
			float stored = texelFetch(u_shadow, ivec3(t.xy, 6 * light + t.z), 0).x;
			lit += dist - bias <= stored ? 1.0 : 0.0;
			n += 1.0;
		}
	return lit / n;
}
#endif

// Phong with exact shadow feelers (any-hit) or shadow maps; counts += (shadow rays, box,
// triangle tests).
vec3 rs_shade(Ray r, Hit h, Surf s, inout vec3 counts)
{
	vec3 local = u_ambient * s.diffuse;
	for (int i = 0; i < RS_LIGHTS; i++) {
		vec3 l = u_light_pos[i] - s.p;
		float ll = length(l);
		if (!(ll > 0.0))
			continue;
		l /= ll;
		float ndl = dot(s.n, l);
		if (dot(s.ng, l) <= 0.0 || ndl <= 0.0)
			continue;
		float lit = 1.0;
#if RS_SHADOW_MAP
		lit = rs_shadow_lit(i, s.p, dot(s.ng, l));
		if (lit <= 0.0)
			continue;
#else
		Ray f = rs_spawn(s, l, h.slot);
		vec3 fd = u_light_pos[i] - f.o;
		f.tmax = length(fd);
		if (!(f.tmax > 0.0))
			continue;
		f.d = fd / f.tmax;
		counts.x += 1.0;
#if RS_GEOMETRY
		Hit any;
		vec2 c = vec2(0.0);
		bool blocked = rs_traverse(f, true, any, c);
		counts.yz += c;
		if (blocked)
			continue;
#endif
#endif
		float spec = 0.0;
		if (s.specular > 0.0) {
			float rdv = dot(2.0 * ndl * s.n - l, -r.d);
			if (rdv > 0.0)
				spec = s.specular * pow(min(rdv, 1.0), s.shininess);
		}
		local += lit * u_light_color[i] * (s.diffuse * ndl + spec);
	}
	return local;
}

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

#if RS_ENVMAP
uniform samplerCube u_envmap; // RS_REFLECT_ENVMAP: the cube map captured at the centre
uniform int u_envmap_on;      // 1 from the second pass on: misses read u_envmap
#endif
#if RS_INTERREFLECT
uniform sampler2D u_objects;   // scene triangle id -> mirror object (-1: none), rows of 2048
uniform samplerCube u_objmap0; // the objects' maps (GLSL ES 3.00 indexes sampler arrays
uniform samplerCube u_objmap1; // by constants only, hence one uniform each)
uniform samplerCube u_objmap2;
uniform samplerCube u_objmap3;
uniform int u_objmap_on; // 1 once a bounce is captured

// What a ray leaving triangle slot `slot` along d sees: its mirror object's own map, or
// the classic map when it left no mirror object (or none is captured yet).
vec3 rs_mapped(int slot, vec3 d)
{
	int o = -1;
	if (slot >= 0 && u_objmap_on != 0) {
		int id = int(rs_tri(slot, 0).w);
		o = int(texelFetch(u_objects, ivec2(id % 2048, id / 2048), 0).r);
	}
	if (o == 0)
		return textureLod(u_objmap0, d, 0.0).rgb;
	if (o == 1)
		return textureLod(u_objmap1, d, 0.0).rgb;
	if (o == 2)
		return textureLod(u_objmap2, d, 0.0).rgb;
	if (o == 3)
		return textureLod(u_objmap3, d, 0.0).rgb;
	return textureLod(u_envmap, d, 0.0).rgb;
}
#endif

// The paper's environment kernel: a missed ray (h.slot < 0) takes the environment's
// colour where it leaves the cube (or a captured map's) and ends (state -2).
// orig = (origin, skip slot), dir = (direction, throughput), acc = (rgb, state).
void rs_path_environment(vec4 orig, vec4 dir, inout vec4 acc)
{
	Ray r = Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w));
	float throughput = dir.w;
#if RS_ENVMAP
#if RS_INTERREFLECT
	acc.rgb += throughput *
	           (u_envmap_on != 0 ? rs_mapped(r.skip, r.d) : rs_environment(r.o, r.d));
#else
	acc.rgb += throughput *
	           (u_envmap_on != 0 ? texture(u_envmap, r.d).rgb : rs_environment(r.o, r.d));
#endif
#else
	acc.rgb += throughput * rs_environment(r.o, r.d);
#endif
	acc.w = RS_STATE_ENVIRONMENT;
}

// The paper's shading kernel: local Phong at the hit (surface s), weighted by the
// throughput; cnt += (0, shadow rays, box, triangle tests).
void rs_path_shading(vec4 orig, vec4 dir, inout vec4 acc, Hit h, Surf s, inout vec4 cnt)
{
	Ray r = Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w));
	vec3 c = vec3(0.0);
	acc.rgb += dir.w * rs_shade(r, h, s, c);
	cnt.yzw += c;
}

// The paper's next-ray kernel: the state after the hit (-3 diffuse end, or 0 with the
// reflected or refracted ray and its throughput in orig and dir).
void rs_path_next(inout vec4 orig, inout vec4 dir, inout vec4 acc, Hit h, Surf s)
{
	Ray r = Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w));
	Ray next;
	float weight;
	acc.w = rs_next_ray(r, h, s, next, weight);
	if (acc.w == RS_STATE_ACTIVE) {
		orig = vec4(next.o, float(next.skip));
		dir = vec4(next.d, dir.w * weight);
	}
}

// One path step after the intersection, the three kernels above in one: environment for a
// miss, else local shading and the next ray. cnt += (0, shadow rays, box, triangle tests).
void rs_path_step(inout vec4 orig, inout vec4 dir, inout vec4 acc, Hit h, inout vec4 cnt)
{
	if (h.slot < 0) {
		rs_path_environment(orig, dir, acc);
		return;
	}
	Surf s = rs_surface(Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w)), h);
	rs_path_shading(orig, dir, acc, h, s, cnt);
	rs_path_next(orig, dir, acc, h, s);
}
