// raster.glsl: rasterized primary hits, fragment stage: the visibility pass. Each fragment
// writes the slot of the triangle the raster gives the pixel and its distance from the
// eye, interpolated (perspective-correct) from the vertices; the depth test keeps the
// nearest by that distance, as tracing orders surfaces. The fragment does no texture fetch,
// which matters on a software rasterizer: a tiny triangle still shades a whole 4x4 block.
// resolve.glsl then tests each pixel's camera ray against its triangle exactly.
// In:  v_slot, v_rel (vertex - eye), u_far.
// Out: 0 visibility = (distance, 0, 0, slot); depth = distance / u_far.
uniform float u_far;
flat in int v_slot;
in vec3 v_rel;
layout(location = 0) out vec4 o_vis;

void main()
{
	float t = length(v_rel);
	gl_FragDepth = clamp(t / u_far, 0.0, 1.0);
	o_vis = vec4(t, 0.0, 0.0, float(v_slot));
}
