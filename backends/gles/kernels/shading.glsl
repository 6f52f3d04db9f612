// shading.glsl: the paper's shading kernel (RS_CHAIN_PAPER): Phong at the hit of each ray
// still active after the environment kernel (so every one has a hit), several point lights,
// shadow feelers or shadow maps, added to the colour with the ray's throughput.
// In:  u_orig (origin, skip slot), u_dir (direction, throughput), u_acc (rgb, state),
//      u_hit (t, u, v, slot), u_cnt (counters, RS_COUNTERS).
// Out: 0 acc; 1 cnt += (0, shadow rays, box tests, triangle tests) with RS_COUNTERS.
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
uniform sampler2D u_hit;
#if RS_COUNTERS
uniform sampler2D u_cnt;
layout(location = 1) out vec4 o_cnt;
#endif
layout(location = 0) out vec4 o_acc;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 acc = texelFetch(u_acc, px, 0);
	vec4 cnt = vec4(0.0);
#if RS_COUNTERS
	cnt = texelFetch(u_cnt, px, 0);
#endif
	if (acc.w == RS_STATE_ACTIVE) {
		vec4 orig = texelFetch(u_orig, px, 0), dir = texelFetch(u_dir, px, 0);
		Hit h = rs_texel_hit(texelFetch(u_hit, px, 0));
		Surf s = rs_surface(Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w)), h);
		rs_path_shading(orig, dir, acc, h, s, cnt);
	}
	o_acc = acc;
#if RS_COUNTERS
	o_cnt = cnt;
#endif
}
