// intersect.glsl: closest hit of each active ray through the packed BVH.
// In:  u_orig (origin, skip slot), u_dir (direction, throughput), u_acc (rgb, state),
//      u_cnt (counters, RS_COUNTERS).
// Out: 0 hit = (t, u, v, slot), slot -1: miss, -2: path already finished;
//      1 cnt += (1 segment, 0, box tests, triangle tests) with RS_COUNTERS.
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
#if RS_COUNTERS
uniform sampler2D u_cnt;
layout(location = 1) out vec4 o_cnt;
#endif
layout(location = 0) out vec4 o_hit;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	Hit h = Hit(RS_FAR, 0.0, 0.0, -2, -1.0);
	vec2 c = vec2(0.0);
	if (texelFetch(u_acc, px, 0).w == RS_STATE_ACTIVE) {
		vec4 o = texelFetch(u_orig, px, 0), d = texelFetch(u_dir, px, 0);
		h.slot = -1;
#if RS_GEOMETRY
#if RS_ENVMAP
		if (u_envmap_on == 0) // environment mapping: later passes are not traced
#endif
		rs_traverse(Ray(o.xyz, d.xyz, RS_FAR, int(o.w)), false, h, c);
#endif
	}
	o_hit = rs_hit_texel(h);
#if RS_COUNTERS
	o_cnt = texelFetch(u_cnt, px, 0) + (h.slot == -2 ? vec4(0.0) : vec4(1.0, 0.0, c));
#endif
}
