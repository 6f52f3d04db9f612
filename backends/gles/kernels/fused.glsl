// fused.glsl: intersection, environment, shading and next ray of one pass in one kernel
// (RS_CHAIN_FUSED: no hit texture round trip). Without counters only: the fourth render
// target GLES 3.0 guarantees carries the hit (pass 0's gives the depth).
// In:  u_orig, u_dir, u_acc; with RS_FIRST_PASS (the first pass of the fused chain) the
//      primary ray of camera.glsl instead, as raygen.glsl makes it (u_near included): one
//      full-screen pass and three float targets fewer per frame. With RS_RASTER_FIRST too
//      (rasterized primaries) the first hit is visibility.glsl's, not a walk: the resolve,
//      ray generation and shading passes of the separate chain in one.
// With RS_ENVMAP and u_envmap_after (cubemaps.glsl) the rays this pass leaves read the
// captured maps at its end, as the separate chain's second pass does without tracing: the
// classic method's whole frame is this one pass.
// With u_display (the last pass of a frame shown as RGBA8: rs_gles_step.display, chosen
// per frame by gles_renderer.c) target 0, whose ray nothing reads after the last pass, is
// the RGBA8 display target and takes the colour as display.glsl would write it
// (quantize.glsl); the display pass and its read of the colour are then not run.
// Out: 0 orig (u_display: RGBA8 colour, alpha 1), 1 dir, 2 acc, 3 hit = (t, u, v, slot).
#if RS_FIRST_PASS
uniform float u_near;
#else
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
#endif
uniform int u_display;
layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;
layout(location = 3) out vec4 o_hit;

void main()
{
#if RS_FIRST_PASS
	vec3 d = rs_camera_dir(gl_FragCoord.xy);
	vec4 orig = vec4(u_eye + u_near * d, -1.0), dir = vec4(d, 1.0), acc = vec4(0.0);
#else
	// A finished path keeps only its colour: its ray is never read again (written as 0).
	ivec2 px = ivec2(gl_FragCoord.xy);
	vec4 acc = texelFetch(u_acc, px, 0), orig = vec4(0.0), dir = vec4(0.0);
	if (acc.w == RS_STATE_ACTIVE) {
		orig = texelFetch(u_orig, px, 0);
		dir = texelFetch(u_dir, px, 0);
	}
#endif
	Hit h = Hit(RS_FAR, 0.0, 0.0, -2, -1.0);
	if (acc.w == RS_STATE_ACTIVE) {
		h.slot = -1;
		vec2 c = vec2(0.0);
		vec4 cnt = vec4(0.0);
#if RS_GEOMETRY && RS_RASTER_FIRST
		h = rs_visible_hit(gl_FragCoord.xy);
#elif RS_GEOMETRY
		rs_traverse(Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w)), false, h, c);
#endif
		rs_path_step(orig, dir, acc, h, cnt);
#if RS_ENVMAP
		if (u_envmap_after != 0 && acc.w == RS_STATE_ACTIVE)
			rs_path_environment_from(orig, dir, acc, true);
#endif
	}
	o_orig = u_display != 0 ? vec4(rs_quantize(acc.rgb), 1.0) : orig;
	o_dir = dir;
	o_acc = acc;
	o_hit = rs_hit_texel(h);
}
