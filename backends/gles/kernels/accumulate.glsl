// accumulate.glsl: still-pose refinement's running mean (gles_display.c), in float, of the
// frames of one camera at sub-pixel samples 0, 1, 2, ... (rs_camera.sample): m_k =
// m_{k-1} + (x_k - m_{k-1}) * u_weight with u_weight = 1 / (k + 1), so sample 0 (weight 1)
// starts it again. The same rule as apps/common/app_refine.c's C mean of byte frames, of
// the same values: each frame's colour clamped to [0, 1].
// In:  u_frame (rgb: this frame's float colour, the plan's result), u_prev (rgb: the mean so
//      far; not read at weight 1), u_weight.
// Out: 0 the new mean (rgb), alpha 1.
uniform sampler2D u_frame;
uniform sampler2D u_prev;
uniform float u_weight;
layout(location = 0) out vec4 o_mean;

void main()
{
	ivec2 p = ivec2(gl_FragCoord.xy);
	vec3 x = texelFetch(u_frame, p, 0).rgb;
	// what the frame shows, [0, 1], is averaged (a highlight brighter than white must not
	// bleed over an edge; byte frames can only be averaged that way); a NaN would stay
	// in the mean for good
	x = clamp(mix(x, vec3(0.0), isnan(x)), 0.0, 1.0);
	vec3 m = u_weight >= 1.0 ? x : texelFetch(u_prev, p, 0).rgb;
	o_mean = vec4(m + (x - m) * u_weight, 1.0);
}
