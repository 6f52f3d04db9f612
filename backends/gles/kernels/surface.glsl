// surface.glsl: what the shading and next-ray kernels know about a hit (lib/trace/shade.c
// in fp32): the surface record, and the rays that leave it (docs/tracer.md R5).
// Inputs: common.glsl's textures, u_spawn_scale and u_spawn_floor.

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
