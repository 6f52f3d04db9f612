// quantize.glsl: (library) linear colour to its RGBA8 display value exactly as
// rs_image_quantize_value() rounds: round(clamp(c, 0, 1) * 255), NaN to 0; the k / 255 it
// returns is stored in an RGBA8 target as k exactly. One copy for every kernel that makes
// display bytes (display.glsl, fused.glsl's last pass of a displayed frame, present.glsl),
// so every path shows the same bytes.
// In: c (linear rgb). Out: rs_quantize(c), rgb as k / 255.
vec3 rs_quantize(vec3 c)
{
	c = mix(c, vec3(0.0), isnan(c));
	return floor(clamp(c, 0.0, 1.0) * 255.0 + 0.5) / 255.0;
}
