// shadow_vertex.glsl (vertex): one face of a light's cube shadow map (paper: shadow maps
// for point lights). Vertex i is corner i % 3 of packed slot i / 3 (no vertex buffer).
// Face f looks along axis a = f / 2 with sign s (+x, -x, +y, -y, +z, -z); a point q
// relative to the light lands at (q[a+1], q[a+2]) / (s q[a]), the coordinates the shading
// kernel looks it up with (surface.glsl, rs_shadow_lit).
// In:  common.glsl's u_tris, u_light (position), u_axis, u_sign, u_near, u_far.
// Out: v_q: the point relative to the light.
uniform vec3 u_light;
uniform int u_axis;
uniform float u_sign;
uniform float u_near;
uniform float u_far;
out vec3 v_q;

void main()
{
	int slot = gl_VertexID / 3;
	vec3 q = rs_tri(slot, gl_VertexID - 3 * slot).xyz - u_light;
	float depth = u_sign * q[u_axis];
	float z = (depth * (u_far + u_near) - 2.0 * u_far * u_near) / (u_far - u_near);
	gl_Position = vec4(q[(u_axis + 1) % 3], q[(u_axis + 2) % 3], z, depth);
	v_q = q;
}
