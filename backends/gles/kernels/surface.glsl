// surface.glsl: what the shading and next-ray kernels know about a hit (lib/trace/shade.c
// in fp32): the surface record, and the rays that leave it (docs/tracer.md R5).
// Inputs: common.glsl's textures, u_spawn_scale and u_spawn_floor; RS_TWO_LEVEL: the
//         instance texture (h.slot is then a scene triangle id, rs_locate finds its
//         instance and slot).

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

#if RS_TWO_LEVEL
vec3 rs_unit(vec3 v)
{
	float l = length(v);
	return l > 0.0 ? v / l : v;
}
#endif

Surf rs_surface(Ray r, Hit h)
{
	Surf s;
	vec4 t0 = g_hit_v0, t1 = g_hit_v1, t2 = g_hit_v2; // common.glsl's cache
	int slot = h.slot;
#if RS_TWO_LEVEL
	int inst = g_hit_inst;
	slot = g_hit_blas;
	if (h.slot != g_hit_slot) {
		rs_locate(h.slot, inst, slot);
		t0 = rs_tri(slot, 0);
		t1 = rs_tri(slot, 1);
		t2 = rs_tri(slot, 2);
	}
	// the BLAS triangle into the TLAS frame (to_world), normals through to_world_normal
	vec4 a0 = rs_instance(inst, 3), a1 = rs_instance(inst, 4), a2 = rs_instance(inst, 5);
	vec3 nm0 = rs_instance(inst, 6).xyz, nm1 = rs_instance(inst, 7).xyz;
	vec3 nm2 = rs_instance(inst, 8).xyz;
	vec4 ov = rs_instance(inst, 7), mirror = rs_instance(inst, 8);
	mat3 to_world_normal = transpose(mat3(nm0, nm1, nm2));
	vec3 w0 = vec3(dot(a0.xyz, t0.xyz) + a0.w, dot(a1.xyz, t0.xyz) + a1.w,
	               dot(a2.xyz, t0.xyz) + a2.w);
	vec3 w1 = vec3(dot(a0.xyz, t1.xyz) + a0.w, dot(a1.xyz, t1.xyz) + a1.w,
	               dot(a2.xyz, t1.xyz) + a2.w);
	vec3 w2 = vec3(dot(a0.xyz, t2.xyz) + a0.w, dot(a1.xyz, t2.xyz) + a1.w,
	               dot(a2.xyz, t2.xyz) + a2.w);
	// unit, as the baked scene's vertex normals are (interpolation weights them)
	vec3 n0 = rs_unit(to_world_normal * rs_normal(slot, 0).xyz);
	vec3 n1 = rs_unit(to_world_normal * rs_normal(slot, 1).xyz);
	vec3 n2 = rs_unit(to_world_normal * rs_normal(slot, 2).xyz);
	float hu = h.u, hv = h.v;
	if (mirror.w != 0.0) { // rewound as the baked scene's mirrored instances are
		vec3 sw = w1;
		w1 = w2;
		w2 = sw;
		sw = n1;
		n1 = n2;
		n2 = sw;
		hu = h.v;
		hv = h.u;
	}
	float material = ov.w >= 0.0 ? ov.w : t1.w;
	t0 = vec4(w0, t0.w);
	t1 = vec4(w1, material);
	t2 = vec4(w2, t2.w);
#else
	if (h.slot != g_hit_slot) {
		t0 = rs_tri(h.slot, 0);
		t1 = rs_tri(h.slot, 1);
		t2 = rs_tri(h.slot, 2);
	}
	vec3 n0 = rs_normal(slot, 0).xyz, n1 = rs_normal(slot, 1).xyz, n2 = rs_normal(slot, 2).xyz;
	float hu = h.u, hv = h.v;
#endif
	vec3 e1 = t1.xyz - t0.xyz, e2 = t2.xyz - t0.xyz;
	vec3 g = cross(e1, e2);
	// |g| = twice the area squares the scene's size, and length() squares it again: beyond
	// ~4e9 units of edge that is past the float range (inf), under ~1e-10 it flushes to 0
	// (either way a lost normal). A power of two scales such a g exactly (k = 1 everywhere
	// else, so those bits are unchanged); the heights below divide by the edges scaled alike.
	float gm = rs_maxabs(g);
	float k = gm > 1.0e18 ? RS_ZERO_ABS : (gm < 1.0e-18 ? 1.0 / RS_ZERO_ABS : 1.0); // 2^-+64
	g *= k;
	float gl = length(g);
	// R5: pulled at least ~4 delta away from every edge (small triangles: the centroid),
	// so the point lies in front of every neighbour's plane at a concave edge.
	vec3 m3 = max(max(abs(t0.xyz), abs(t1.xyz)), abs(t2.xyz));
	s.delta = u_spawn_scale * max(max(max(m3.x, m3.y), m3.z), u_spawn_floor);
	vec3 edge = vec3(length(t2.xyz - t1.xyz), length(t0.xyz - t2.xyz), length(e1));
	vec3 b = vec3(1.0 - hu - hv, hu, hv);
	for (int i = 0; i < 3; i++) {
		float hi = edge[i] > 0.0 ? gl / (edge[i] * k) : 0.0;
		b[i] = max(b[i], hi > RS_SPAWN_PULL_HEIGHT * s.delta ? RS_SPAWN_PULL * s.delta / hi
		                                                  : 1.0 / 3.0);
	}
	float bs = b.x + b.y + b.z;
	s.p = t0.xyz + (b.y / bs) * e1 + (b.z / bs) * e2;
	g = gl > 0.0 ? g / gl : -r.d;
	float dg = dot(r.d, g);
	s.entering = dg < 0.0;
	s.ng = dg < 0.0 ? g : -g;
	vec3 n = (1.0 - hu - hv) * n0 + hu * n1 + hv * n2;
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
