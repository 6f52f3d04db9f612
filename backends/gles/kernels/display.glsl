// display.glsl: linear colour to RGBA8 exactly as rs_image_quantize_value() rounds:
// round(clamp(c, 0, 1) * 255); the stored k / 255 converts back to k exactly.
// In: u_acc (rgb, state). Out: 0 RGBA8 colour, alpha 1.
uniform sampler2D u_acc;
layout(location = 0) out vec4 o_color;

void main()
{
	vec3 c = texelFetch(u_acc, ivec2(gl_FragCoord.xy), 0).rgb;
	c = mix(c, vec3(0.0), isnan(c));
	o_color = vec4(floor(clamp(c, 0.0, 1.0) * 255.0 + 0.5) / 255.0, 1.0);
}
