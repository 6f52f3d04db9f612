// raster_vertex.glsl (vertex): rasterized primary hits (paper 3.2.1), vertex stage. Draws
// triangle_count * 3 vertices with no vertex buffer: vertex i is corner i % 3 of packed
// slot i / 3, read from the triangle texture. The projection is the camera's own pinhole
// (camera.glsl: fov, aspect, lens shift, sample offset), so a pixel centre is covered by the triangle
// its primary ray meets; image row y lands on GL row y.
// In:  common.glsl's u_tris, camera.glsl's uniforms, u_near, u_far (clip planes).
// Out: v_slot (flat): the packed slot; v_rel: the vertex relative to the eye.
uniform float u_near;
uniform float u_far;
flat out int v_slot;
out vec3 v_rel;

void main()
{
	int slot = gl_VertexID / 3;
	vec3 p = rs_tri(slot, gl_VertexID - 3 * slot).xyz - u_eye;
	vec3 q = vec3(dot(p, u_right), dot(p, u_up), dot(p, u_fwd));
	float aspect = u_size.x / u_size.y;
	// the sample offset as a lens shift: a pixel centre then sees what camera.glsl's ray
	// through the moved position sees (+x right, +y down in image rows)
	vec2 shift = u_shift + vec2(2.0, -2.0) * u_jitter / u_size.y;
	float x = (q.x / u_tan - shift.x * q.z) / aspect;
	float y = shift.y * q.z - q.y / u_tan;
	float z = (q.z * (u_far + u_near) - 2.0 * u_far * u_near) / (u_far - u_near);
	gl_Position = vec4(x, y, z, q.z);
	v_slot = slot;
	v_rel = p;
}
