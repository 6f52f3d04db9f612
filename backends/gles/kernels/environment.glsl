// environment.glsl: the paper's environment kernel (RS_CHAIN_PAPER): an active ray that
// missed every triangle takes the environment's colour where it leaves the cube (or the
// captured map's, RS_ENVMAP) and ends with state -2; every other pixel is copied.
// In:  u_orig (origin, skip slot), u_dir (direction, throughput), u_acc (rgb, state),
//      u_hit (t, u, v, slot from intersect.glsl or raster.glsl).
// Out: 0 acc.
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
uniform sampler2D u_hit;
layout(location = 0) out vec4 o_acc;

void main()
{
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 acc = texelFetch(u_acc, px, 0);
	if (acc.w == RS_STATE_ACTIVE && texelFetch(u_hit, px, 0).w < 0.0)
		rs_path_environment(texelFetch(u_orig, px, 0), texelFetch(u_dir, px, 0), acc);
	o_acc = acc;
}
