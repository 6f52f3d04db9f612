// envcube.glsl: the environment cube (lib/trace/environment.c in fp32): a ray that leaves
// the scene takes the colour of the cube where it crosses it.
// Inputs: u_env_center, u_env_half, u_env_color[6], u_env_grid, u_env_line_width,
//         u_env_line_scale (rs_trace_frame.env, resolved once on the CPU).

uniform vec3 u_env_center;
uniform float u_env_half;
uniform vec3 u_env_color[6];
uniform float u_env_grid;
uniform float u_env_line_width;
uniform float u_env_line_scale;

bool rs_grid_line(float pos)
{
	float g = pos * u_env_grid;
	float frac = g - floor(g);
	return min(frac, 1.0 - frac) < 0.5 * u_env_line_width;
}

// Environment cube colour where the ray leaves it (exit point, not direction: no parallax).
vec3 rs_environment(vec3 o, vec3 d)
{
	int axis = -1;
	float best = RS_FAR;
	for (int a = 0; a < 3; a++) {
		if (d[a] == 0.0)
			continue;
		float plane = u_env_center[a] + (d[a] > 0.0 ? u_env_half : -u_env_half);
		float t = (plane - o[a]) / d[a];
		if (t < best) {
			best = t;
			axis = a;
		}
	}
	vec3 p = u_env_center;
	int face = 0;
	if (axis < 0) {
		axis = 0;
		p.x += u_env_half;
	} else {
		p = o + best * d;
		p[axis] = u_env_center[axis] + (d[axis] > 0.0 ? u_env_half : -u_env_half);
		face = 2 * axis + (d[axis] > 0.0 ? 0 : 1);
	}
	int as = (axis + 1) % 3, at = (axis + 2) % 3;
	float fs = clamp(0.5 * ((p[as] - u_env_center[as]) / u_env_half + 1.0), 0.0, 1.0);
	float ft = clamp(0.5 * ((p[at] - u_env_center[at]) / u_env_half + 1.0), 0.0, 1.0);
	bool line = rs_grid_line(fs) || rs_grid_line(ft);
	return u_env_color[face] * (line ? u_env_line_scale : 1.0);
}

