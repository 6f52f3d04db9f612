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
// With RS_COMPUTE (rs_render_desc.kernels compute; gles_state.c rs_gles_dispatch) the same
// kernel is a GLES 3.1 compute program: 8x8 pixels a work group, the four outputs RGBA32F
// images 0-3 stored where bit k of u_stores is set (no u_display: the display pass runs),
// the pass's pixels u_extent; each pixel computes exactly what the fragment pass would.
#if RS_FIRST_PASS
uniform float u_near;
#else
uniform sampler2D u_orig;
uniform sampler2D u_dir;
uniform sampler2D u_acc;
#endif
#if RS_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in; // GROUP_SIDE in gles_state.c
layout(rgba32f, binding = 0) writeonly uniform highp image2D i_orig;
layout(rgba32f, binding = 1) writeonly uniform highp image2D i_dir;
layout(rgba32f, binding = 2) writeonly uniform highp image2D i_acc;
layout(rgba32f, binding = 3) writeonly uniform highp image2D i_hit;
uniform vec2 u_extent;
uniform int u_stores;
vec4 o_orig, o_dir, o_acc, o_hit;

// The group's pixel of this invocation: every 8 consecutive invocations a 4x2 block, as a
// fragment quad pair, so a SIMD group of 8 (llvmpipe) or 32 (an 8x4 block) walks
// neighbouring rays (row-major 8x1 runs measured 1.1-1.2x slower on llvmpipe).
ivec2 rs_pixel()
{
	uint l = gl_LocalInvocationIndex, block = l >> 3u, lane = l & 7u;
	uvec2 in_group = uvec2((block & 1u) * 4u + (lane & 3u), (block >> 1u) * 2u + (lane >> 2u));
	return ivec2(gl_WorkGroupID.xy * 8u + in_group);
}
#define RS_FRAG_XY (vec2(rs_pixel()) + 0.5)
#else
uniform int u_display;
layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;
layout(location = 3) out vec4 o_hit;
#define RS_FRAG_XY gl_FragCoord.xy
#endif

void rs_fused()
{
#if RS_FIRST_PASS
	vec3 d = rs_camera_dir(RS_FRAG_XY);
	vec4 orig = vec4(u_eye + u_near * d, -1.0), dir = vec4(d, 1.0), acc = vec4(0.0);
#else
	// A finished path keeps only its colour: its ray is never read again (written as 0).
	ivec2 px = ivec2(RS_FRAG_XY);
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
		h = rs_visible_hit(RS_FRAG_XY);
#elif RS_GEOMETRY
		rs_traverse(Ray(orig.xyz, dir.xyz, RS_FAR, int(orig.w)), false, h, c);
#endif
		rs_path_step(orig, dir, acc, h, cnt);
#if RS_ENVMAP
		if (u_envmap_after != 0 && acc.w == RS_STATE_ACTIVE)
			rs_path_environment_from(orig, dir, acc, true);
#endif
	}
#if RS_COMPUTE
	o_orig = orig;
#else
	o_orig = u_display != 0 ? vec4(rs_quantize(acc.rgb), 1.0) : orig;
#endif
	o_dir = dir;
	o_acc = acc;
	o_hit = rs_hit_texel(h);
}

void main()
{
#if RS_COMPUTE
	ivec2 px = rs_pixel();
	if (float(px.x) >= u_extent.x || float(px.y) >= u_extent.y)
		return;
	rs_fused();
	if ((u_stores & 1) != 0)
		imageStore(i_orig, px, o_orig);
	if ((u_stores & 2) != 0)
		imageStore(i_dir, px, o_dir);
	if ((u_stores & 4) != 0)
		imageStore(i_acc, px, o_acc);
	if ((u_stores & 8) != 0)
		imageStore(i_hit, px, o_hit);
#else
	rs_fused();
#endif
}
