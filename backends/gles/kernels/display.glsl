// display.glsl: linear colour to RGBA8 (quantize.glsl's rs_quantize: as
// rs_image_quantize_value() rounds, NaN to 0). The display pass of a frame whose last trace
// pass does not write the RGBA8 colour itself (rs_gles_step.display, gles_renderer.c).
// In: u_acc (rgb, state). Out: 0 RGBA8 colour, alpha 1.
uniform sampler2D u_acc;
layout(location = 0) out vec4 o_color;

void main()
{
	o_color = vec4(rs_quantize(texelFetch(u_acc, ivec2(gl_FragCoord.xy), 0).rgb), 1.0);
}
