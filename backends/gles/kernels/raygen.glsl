// raygen.glsl: primary rays (lib/trace/camera_rays.c). Image row y is GL row y, so a
// glReadPixels of any target gives row 0 = top, as rs_frame wants.
// In:  u_eye, u_fwd, u_right, u_up (camera basis), u_size (W, H), u_tan (tan fov_y/2),
//      u_shift (lens shift).
// Out: 0 orig = (eye, -1), 1 dir = (unit direction, throughput 1), 2 acc = (0, state 0),
//      3 cnt = (1 segment, 0, 0, 0) with RS_COUNTERS.
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec2 u_size;
uniform float u_tan;
uniform vec2 u_shift;

layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;
#if RS_COUNTERS
layout(location = 3) out vec4 o_cnt;
#endif

void main()
{
	vec2 px = gl_FragCoord.xy;
	float sx = ((2.0 * px.x / u_size.x - 1.0) * (u_size.x / u_size.y) + u_shift.x) * u_tan;
	float sy = ((1.0 - 2.0 * px.y / u_size.y) + u_shift.y) * u_tan;
	o_orig = vec4(u_eye, -1.0);
	o_dir = vec4(normalize(u_fwd + sx * u_right + sy * u_up), 1.0);
	o_acc = vec4(0.0);
#if RS_COUNTERS
	o_cnt = vec4(0.0);
#endif
}
