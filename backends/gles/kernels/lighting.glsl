// lighting.glsl: local shading at a surface point (lib/trace/shade.c in fp32): ambient, then
// Phong per light seen through an exact shadow feeler (any-hit walk), a cube shadow map, or
// (RS_SHADOW_NONE, shadows=none) every light in front of the surface, unshadowed.
// Inputs: u_ambient, u_light_pos[], u_light_color[] (RS_LIGHT_SLOTS >= RS_LIGHTS, packed
//         frame); with RS_SHADOW_MAP u_shadow, u_shadow_size, u_shadow_filter.

uniform float u_ambient;
uniform vec3 u_light_pos[RS_LIGHT_SLOTS];
uniform vec3 u_light_color[RS_LIGHT_SLOTS];

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

// Phong with exact shadow feelers (any-hit), shadow maps or none; counts += (shadow rays,
// box, triangle tests): nothing without feelers.
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
#elif !RS_SHADOW_NONE
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

