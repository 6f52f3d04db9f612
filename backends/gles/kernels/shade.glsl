// shade.glsl: the environment, shading and next-ray kernels of one pass, fused (they read
// and write the same per-pixel state, so splitting them would only add texture traffic).
// In:  u_orig, u_dir, u_acc, u_hit (from intersect.glsl), u_cnt (RS_COUNTERS).
// Out: 0 orig, 1 dir, 2 acc (next ray and colour so far), 3 cnt with RS_COUNTERS.
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
uniform sampler2D u_hit;
#if RS_COUNTERS
uniform sampler2D u_cnt;
layout(location = 3) out vec4 o_cnt;
#endif
layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 orig = texelFetch(u_orig, px, 0), dir = texelFetch(u_dir, px, 0);
	vec4 acc = texelFetch(u_acc, px, 0), hit = texelFetch(u_hit, px, 0);
	vec4 cnt = vec4(0.0);
#if RS_COUNTERS
	cnt = texelFetch(u_cnt, px, 0);
#endif
	if (acc.w == RS_STATE_ACTIVE)
		rs_path_step(orig, dir, acc, rs_texel_hit(hit), cnt);
	o_orig = orig;
	o_dir = dir;
	o_acc = acc;
#if RS_COUNTERS
	o_cnt = cnt;
#endif
}
