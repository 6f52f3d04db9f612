// raster.glsl: rasterized primary hits, fragment stage. The raster proposes the triangle
// covering the pixel centre; the pixel's camera ray is then tested against it with the
// traced kernel's own triangle test, so t, u, v are the traced ones. Where that test says
// the ray misses it (the raster snaps vertices to a sub-pixel grid, so pixels within a
// hair of an edge can go to the neighbour), the ray is traced through the BVH instead.
// The depth written is t itself: the depth test orders surfaces as tracing does.
// In:  v_slot, common.glsl's textures, camera.glsl's uniforms, u_far.
// Out: 0 hit = (t, u, v, slot); depth = t / u_far.
uniform float u_far;
flat in int v_slot;
layout(location = 0) out vec4 o_hit;

void main()
{
	Ray r = Ray(u_eye, rs_camera_dir(gl_FragCoord.xy), RS_FAR, -1);
	Pre p = rs_prepare(r);
	vec3 tuv;
	Hit h;
	vec4 v0 = rs_tri(v_slot, 0);
	if (rs_triangle(v0.xyz, rs_tri(v_slot, 1).xyz, rs_tri(v_slot, 2).xyz, r, p, RS_FAR, tuv)) {
		h = Hit(tuv.x, tuv.y, tuv.z, v_slot, v0.w);
	} else {
		vec2 counts = vec2(0.0);
		if (!rs_traverse(r, false, h, counts))
			discard;
	}
	gl_FragDepth = clamp(h.t / u_far, 0.0, 1.0);
	o_hit = vec4(h.t, h.u, h.v, float(h.slot));
}
