// camera.glsl: the pinhole camera of lib/trace/camera_rays.c (basis built in double on
// the CPU), shared by ray generation and the raster pass. Image row y is GL row y.
// Inputs: u_eye, u_fwd, u_right, u_up (camera basis), u_size (W, H), u_tan (tan fov_y/2),
//         u_shift (lens shift), u_jitter (the frame's sub-pixel sample offset in pixels,
//         rs_trace_view.pixel_offset: 0 except while a still pose refines).
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec2 u_size;
uniform float u_tan;
uniform vec2 u_shift;
uniform vec2 u_jitter;

// Unit direction of the primary ray through image position px (pixel centres at +0.5)
// moved by the frame's sample offset.
vec3 rs_camera_dir(vec2 px)
{
	px += u_jitter;
	float sx = ((2.0 * px.x / u_size.x - 1.0) * (u_size.x / u_size.y) + u_shift.x) * u_tan;
	float sy = ((1.0 - 2.0 * px.y / u_size.y) + u_shift.y) * u_tan;
	return normalize(u_fwd + sx * u_right + sy * u_up);
}
