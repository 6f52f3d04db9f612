// path.glsl: the paper's environment, shading and next-ray kernels as functions over the
// per-pixel state, and all three in one (rs_path_step) for the fused and separate chains.
// orig = (origin, skip slot), dir = (direction, throughput), acc = (rgb, state),
// cnt = (segments, shadow rays, box tests, triangle tests).

// The paper's environment kernel: a missed ray (h.slot < 0) takes the environment's
// colour where it leaves the cube, or a captured map's where `mapped` (RS_ENVMAP), and
// ends (state -2). orig = (origin, skip slot), dir = (direction, throughput), acc = (rgb,
// state). The map is read at level 0 explicitly: this runs in per-pixel (non-uniform)
// control flow, where GLSL ES 3.00 leaves implicit derivatives, and so texture()'s level,
// undefined (section 8.9); the map has one level, so the texels are the same.
void rs_path_environment_from(vec4 orig, vec4 dir, inout vec4 acc, bool mapped)
{
	Ray r = Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w));
	float throughput = dir.w;
#if RS_ENVMAP
#if RS_INTERREFLECT
	acc.rgb += throughput * (mapped ? rs_mapped(r.skip, r.d) : rs_environment(r.o, r.d));
#else
	acc.rgb += throughput * (mapped ? textureLod(u_envmap, r.d, 0.0).rgb : rs_environment(r.o, r.d));
#endif
#else
	acc.rgb += throughput * rs_environment(r.o, r.d);
#endif
	acc.w = RS_STATE_ENVIRONMENT;
}

// As above, the maps read from the second pass on (u_envmap_on).
void rs_path_environment(vec4 orig, vec4 dir, inout vec4 acc)
{
#if RS_ENVMAP
	rs_path_environment_from(orig, dir, acc, u_envmap_on != 0);
#else
	rs_path_environment_from(orig, dir, acc, false);
#endif
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
