// primary.glsl: the primary hits only (rs_render_desc.hits_only): each pixel's camera ray,
// made here as raygen.glsl makes it (camera.glsl, u_near), walked closest-hit through the
// packed BVH. No ray texture is read or written and nothing is shaded: the closest-hit walk
// on its own, as a picking pass or a benchmark against other tracers' primary rays needs.
// With compact nodes in one level its boxes are tested in grid units (common.glsl
// rs_box_grid: fewer operations a box, conservative by its own bound, the same hits).
// In:  camera.glsl's uniforms, u_near, common.glsl's textures.
// Out: 0 hit = (t, u, v, slot), slot -1 and t = RS_FAR: miss.
uniform float u_near;
layout(location = 0) out vec4 o_hit;

void main()
{
	vec3 d = rs_camera_dir(gl_FragCoord.xy);
	Hit h = Hit(RS_FAR, 0.0, 0.0, -1, -1.0);
#if RS_GEOMETRY
	vec2 c = vec2(0.0);
	Ray r = Ray(u_eye + u_near * d, d, RS_FAR, -1);
#if RS_COMPACT_NODES && !RS_TWO_LEVEL && !RS_WIDE_NODES
	rs_walk(r, false, true, h, c); // boxes in grid units (common.glsl rs_box_grid)
#else
	rs_traverse(r, false, h, c);
#endif
#endif
	o_hit = rs_hit_texel(h);
}
