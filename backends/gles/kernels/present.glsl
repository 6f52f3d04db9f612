// present.glsl: a frame into a window's default framebuffer (gles_display.c), scaled to
// the image rectangle with bilinear filtering done here (float targets are not filterable
// in GLES 3.0), then rounded by quantize.glsl's rs_quantize as every display value is: at
// scale 1 every pixel is exactly the byte a readback returns (display.glsl's, or the last
// fused pass's of a displayed frame).
// In: u_image (rgb: the float colour state, or an RGBA8 frame as k / 255), row 0 = top;
//     u_size (the image's texels used), u_origin (the rectangle's lower-left corner in
//     window pixels), u_scale (image texels per window pixel).
// Out: 0 the window's colour, alpha 1.
uniform sampler2D u_image;
uniform vec2 u_size, u_origin, u_scale;
layout(location = 0) out vec4 o_color;

vec3 texel(ivec2 p)
{
	p = clamp(p, ivec2(0), ivec2(u_size) - 1);
	vec3 c = texelFetch(u_image, p, 0).rgb;
	return mix(c, vec3(0.0), isnan(c));
}

void main()
{
	vec2 w = gl_FragCoord.xy - u_origin;
	w.y = u_size.y / u_scale.y - w.y; // window rows go up, image rows go down
	vec2 s = w * u_scale - 0.5;       // texel-centre coordinates: integers at scale 1
	vec2 f = s - floor(s);
	ivec2 i = ivec2(floor(s));
	vec3 c = mix(mix(texel(i), texel(i + ivec2(1, 0)), f.x),
	             mix(texel(i + ivec2(0, 1)), texel(i + ivec2(1, 1)), f.x), f.y);
	o_color = vec4(rs_quantize(c), 1.0);
}
