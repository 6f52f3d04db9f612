// nextray.glsl: the paper's next-ray kernel (RS_CHAIN_PAPER): for each ray still active
// after shading, the single continuation (reflected or refracted, with its weight) or the
// end of the path (state -3); the surface is rebuilt from the hit, as the shading kernel
// built it.
// In:  u_orig (origin, skip slot), u_dir (direction, throughput), u_acc (rgb, state),
//      u_hit (t, u, v, slot).
// Out: 0 orig, 1 dir, 2 acc (the next ray and its state; the colour is copied).
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
uniform sampler2D u_hit;
layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 orig = texelFetch(u_orig, px, 0), dir = texelFetch(u_dir, px, 0);
	vec4 acc = texelFetch(u_acc, px, 0);
	if (acc.w == RS_STATE_ACTIVE) {
		Hit h = rs_texel_hit(texelFetch(u_hit, px, 0));
		Surf s = rs_surface(Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w)), h);
		rs_path_next(orig, dir, acc, h, s);
	}
	o_orig = orig;
	o_dir = dir;
	o_acc = acc;
}
