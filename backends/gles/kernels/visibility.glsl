// visibility.glsl: a rasterized primary hit made exact, shared by resolve.glsl and the fused
// chain's rasterized first pass. The visibility pass (raster.glsl) proposes the triangle
// covering the pixel centre; the pixel's camera ray is tested against it with the traced
// kernel's own triangle test, so t, u, v are the traced ones. Where that test says the ray
// misses it (the raster snaps vertices to a sub-pixel grid, so pixels within a hair of an
// edge can go to the neighbour), the ray is traced through the BVH instead.
// In:  u_vis (raster.glsl's visibility: slot in w, -1 where nothing was rasterized),
//      common.glsl's textures, camera.glsl's uniforms.
uniform sampler2D u_vis;

// The primary hit of pixel position `frag` (gl_FragCoord.xy); slot -1 and t = RS_FAR where
// nothing was rasterized or the fallback walk finds nothing.
Hit rs_visible_hit(vec2 frag)
{
	int slot = int(texelFetch(u_vis, ivec2(frag), 0).w);
	Hit h = Hit(RS_FAR, 0.0, 0.0, -1, -1.0);
	if (slot >= 0 && slot < u_tri_count) {
		Ray r = Ray(u_eye, rs_camera_dir(frag), RS_FAR, -1);
		Pre p = rs_prepare(r);
		vec3 tuv;
		vec4 v0 = rs_tri(slot, 0);
		if (rs_triangle(v0.xyz, rs_tri(slot, 1).xyz, rs_tri(slot, 2).xyz, r, p, RS_FAR, tuv)) {
			h = Hit(tuv.x, tuv.y, tuv.z, slot, v0.w);
		} else {
			vec2 counts = vec2(0.0);
			if (!rs_traverse(r, false, h, counts))
				h = Hit(RS_FAR, 0.0, 0.0, -1, -1.0);
		}
	}
	return h;
}
