// resolve.glsl: rasterized primary hits, second pass (full screen) of the separate and the
// paper's chains: each pixel's exact hit from the visibility pass (visibility.glsl).
// In:  visibility.glsl's u_vis, common.glsl's textures, camera.glsl's uniforms.
// Out: 0 hit = (t, u, v, slot); slot -1 and t = RS_FAR where nothing was rasterized.
layout(location = 0) out vec4 o_hit;

void main()
{
	Hit h = rs_visible_hit(gl_FragCoord.xy);
	o_hit = rs_hit_texel(h);
}
