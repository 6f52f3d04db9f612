// cubemaps.glsl: captured cube maps that stand in for traced rays from the second pass on
// (RS_ENVMAP: the classic map from the scene's centre; RS_INTERREFLECT: one map per mirror
// object, found through the ray's skip slot).
// Inputs: u_envmap, u_envmap_on, u_envmap_after; with RS_INTERREFLECT u_objects, u_objmap0..3, u_objmap_on.

#if RS_ENVMAP
uniform samplerCube u_envmap; // RS_REFLECT_ENVMAP: the cube map captured at the centre
uniform int u_envmap_on;      // 1 from the second pass on: misses read u_envmap
uniform int u_envmap_after;   // 1: the rays this pass leaves read the maps at its end (the
                              // fused chain's only pass; no later pass is run)
#endif
#if RS_INTERREFLECT
uniform sampler2D u_objects;   // scene triangle id -> mirror object (-1: none), rows of 2048
uniform samplerCube u_objmap0; // the objects' maps (GLSL ES 3.00 indexes sampler arrays
uniform samplerCube u_objmap1; // by constants only, hence one uniform each)
uniform samplerCube u_objmap2;
uniform samplerCube u_objmap3;
uniform int u_objmap_on; // 1 once a bounce is captured

// What a ray leaving triangle slot `slot` along d sees: its mirror object's own map, or
// the classic map when it left no mirror object (or none is captured yet).
vec3 rs_mapped(int slot, vec3 d)
{
	int o = -1;
	if (slot >= 0 && u_objmap_on != 0) {
		int id = int(rs_tri(slot, 0).w);
		o = int(texelFetch(u_objects, ivec2(id % 2048, id / 2048), 0).r);
	}
	if (o == 0)
		return textureLod(u_objmap0, d, 0.0).rgb;
	if (o == 1)
		return textureLod(u_objmap1, d, 0.0).rgb;
	if (o == 2)
		return textureLod(u_objmap2, d, 0.0).rgb;
	if (o == 3)
		return textureLod(u_objmap3, d, 0.0).rgb;
	return textureLod(u_envmap, d, 0.0).rgb;
}
#endif

