// raygen.glsl: primary rays (lib/trace/camera_rays.c), through camera.glsl.
// In:  camera.glsl's uniforms.
// Out: 0 orig = (eye, -1), 1 dir = (unit direction, throughput 1), 2 acc = (0, state 0),
//      3 cnt = 0 with RS_COUNTERS.
// u_near: where the rays start along their direction (0; inter-reflection captures: just
// outside the capturing object's bounding sphere, so the object does not see itself).
uniform float u_near;
layout(location = 0) out vec4 o_orig;
layout(location = 1) out vec4 o_dir;
layout(location = 2) out vec4 o_acc;
#if RS_COUNTERS
layout(location = 3) out vec4 o_cnt;
#endif

void main()
{
	vec3 d = rs_camera_dir(gl_FragCoord.xy);
	o_orig = vec4(u_eye + u_near * d, -1.0);
	o_dir = vec4(d, 1.0);
	o_acc = vec4(0.0);
#if RS_COUNTERS
	o_cnt = vec4(0.0);
#endif
}
