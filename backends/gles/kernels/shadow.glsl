// shadow.glsl: one face of a cube shadow map, fragment stage: the distance from the light
// to the nearest surface (the depth test keeps the nearest along each texel's direction).
// In:  v_q. Out: 0 distance (R32F).
in vec3 v_q;
layout(location = 0) out vec4 o_distance;

void main() { o_distance = vec4(length(v_q), 0.0, 0.0, 1.0); }
