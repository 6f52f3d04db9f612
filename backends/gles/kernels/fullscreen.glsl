// fullscreen.glsl (vertex): one triangle covering the viewport; every kernel is a
// fragment pass over it, one fragment per pixel (ray). No inputs, no outputs.
void main()
{
	vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1));
	gl_Position = vec4(p - 1.0, 0.0, 1.0);
}
