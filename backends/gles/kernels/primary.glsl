// primary.glsl: the primary hits only (rs_render_desc.hits_only): each pixel's camera ray,
// made here as raygen.glsl makes it (camera.glsl, u_near), walked closest-hit through the
// packed BVH. No ray texture is read or written and nothing is shaded: the closest-hit walk
// on its own, as a picking pass or a benchmark against other tracers' primary rays needs.
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
	rs_traverse(Ray(u_eye + u_near * d, d, RS_FAR, -1), false, h, c);
#endif
	o_hit = rs_hit_texel(h);
}
