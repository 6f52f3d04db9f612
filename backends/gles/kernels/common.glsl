// common.glsl: the ray rules every kernel shares, in fp32, copied from the CPU reference
// (lib/trace, docs/tracer.md): packed-texture access, slab and triangle tests, the
// stackless walk of the threaded BVH, surface data, environment cube, spawn rule.
// Inputs:  u_nodes (RGBA32UI compact or wide nodes, RGBA32F paper nodes), u_tris, u_normals,
//          u_materials (RGBA32F; layouts in rs_pack.h), u_node_count, u_tri_count,
//          u_material_count, u_spawn_scale (R5's S), u_grid_origin, u_grid_step (compact).
// With RS_TWO_LEVEL (an instanced scene, rs_pack_two_level): u_instances (RGBA32F, 2D or
//          with RS_SCENE_BUFFERS a buffer texture; RS_INSTANCE_TEXELS a instance,
//          RS_INSTANCE_ROW_ITEMS a 2D row), u_top_base,
//          u_top_count (the TLAS in the node texture), u_instance_count, u_proto_instances
//          (instances of prototypes, the loose one after them); the grid uniforms are the
//          TLAS's. Hits and skips then name scene triangle ids, not slots.
// Every position is in the packed frame (docs/tracer.md R1): the CPU moved the camera,
// lights and environment by rs_packed.origin in double before handing them over.
// With RS_SCENE_BUFFERS the four are buffer textures of the same texels in the same order
// (GLES 3.2 or an extension; the version line says which): texelFetch by element, no rows
// or levels to work out, cheaper on llvmpipe (docs/gles.md), same values bit for bit.
// Defines (gles_prelude.c, one table): RS_ROW_ITEMS, RS_ROW_SHIFT (log2 of it, -1 if not a
//          power of two), RS_WATERTIGHT, RS_LIGHTS, RS_COUNTERS, RS_OPTICS, RS_GEOMETRY,
//          RS_COMPACT_NODES, RS_WIDE_NODES, RS_WIDE_STACK, RS_NODE_ORDERS,
//          RS_SCENE_BUFFERS; the rules' constants
//          RS_BOX_K (R3), RS_GRID_BOX_E and RS_GRID_STEPS (R3 in grid units, the hits-only
//          kernel's), RS_PARALLEL_EPS (R2), RS_SPAWN_PULL_HEIGHT, RS_SPAWN_PULL (R5);
//          the paper's ray states RS_STATE_ACTIVE, _MISSED, _ENVIRONMENT, _DIFFUSE.
#if RS_SCENE_BUFFERS
#define RS_SCENE_SAMPLER highp samplerBuffer
#define RS_SCENE_USAMPLER highp usamplerBuffer
#else
#define RS_SCENE_SAMPLER highp sampler2D
#define RS_SCENE_USAMPLER highp usampler2D
#endif
#if RS_COMPACT_NODES || RS_WIDE_NODES
uniform RS_SCENE_USAMPLER u_nodes;
#else
uniform RS_SCENE_SAMPLER u_nodes;
#endif
// the compact grid (paper nodes: unused, but the two-level walk names it for either)
uniform vec3 u_grid_origin;
uniform vec3 u_grid_step;
uniform RS_SCENE_SAMPLER u_tris;
uniform RS_SCENE_SAMPLER u_normals;
uniform RS_SCENE_SAMPLER u_materials;
uniform int u_node_count;
uniform int u_tri_count;
uniform int u_material_count;
uniform float u_spawn_scale;
uniform float u_spawn_floor; // R5's F = max(R / 16, 2^-64), R the scene's half-size
#if RS_TWO_LEVEL
uniform RS_SCENE_SAMPLER u_instances; // buffer storage: a buffer texture too
uniform int u_top_base;
uniform int u_top_count;
uniform int u_instance_count;
uniform int u_proto_instances;
#endif

// "No hit yet" distance: far beyond any scene, finite so no kernel depends on how a GPU
// treats infinities.
const float RS_FAR = 1.0e38;
// Slab distances are widened outwards by RS_BOX_K = 2^-19, 16 fp32 ulps (docs/tracer.md R3;
// the double reference uses 16 double ulps).
const float RS_BOX_GROW = 1.0 + RS_BOX_K;
const float RS_BOX_SHRINK = 1.0 - RS_BOX_K;
// 1/d for a zero direction component (rs_box): finite, so (lo - o) * inv is never NaN.
const float RS_ZERO_INV = 1.0e30;
// The hi plane of a zero direction component's slab is moved out by eps = |o| * RS_ZERO_REL
// + RS_ZERO_ABS (rs_slab_hi_origin): 2^-20 |o| is 8 ulps of o, so o - eps != o; eps * 1e30
// (at least 2^-64 * 1e30 ~ 5e10) bounds the t of any box a ray lying in its hi face plane
// must enter.
const float RS_ZERO_REL = 9.5367431640625e-7; // 2^-20
const float RS_ZERO_ABS = 5.421010862427522e-20; // 2^-64

struct Ray {
	vec3 o;
	vec3 d;
	float tmax;
	int skip; // packed slot the ray leaves, -1: none
};

struct Hit {
	float t;
	float u;
	float v;
	int slot; // -1: miss; RS_TWO_LEVEL: the scene triangle id
	float id; // scene triangle id (the tie-break's key)
};

// A hit in a hit texture: (t, u, v, slot); the id is not stored (only the walk's tie-break
// reads it). Two levels: slot is the scene id, which shading decodes (rs_locate).
vec4 rs_hit_texel(Hit h) { return vec4(h.t, h.u, h.v, float(h.slot)); }
Hit rs_texel_hit(vec4 t) { return Hit(t.x, t.y, t.z, int(t.w), -1.0); }

#if RS_SCENE_BUFFERS
int rs_item(int item, int texels, int j) { return item * texels + j; }
#define rs_fetch(tex, at) texelFetch(tex, at)
#else
#define rs_fetch(tex, at) texelFetch(tex, at, 0)
ivec2 rs_item(int item, int texels, int j)
{
#if RS_ROW_SHIFT >= 0
	// RS_ROW_ITEMS = 1 << RS_ROW_SHIFT and items are >= 0: mask and shift, no division.
	return ivec2((item & (RS_ROW_ITEMS - 1)) * texels + j, item >> RS_ROW_SHIFT);
#else
	return ivec2((item % RS_ROW_ITEMS) * texels + j, item / RS_ROW_ITEMS);
#endif
}
#endif

vec4 rs_tri(int s, int j) { return rs_fetch(u_tris, rs_item(s, 3, j)); }
vec4 rs_normal(int s, int j) { return rs_fetch(u_normals, rs_item(s, 3, j)); }
vec4 rs_material(int m, int j) { return rs_fetch(u_materials, rs_item(m, 3, j)); }

float rs_maxabs(vec3 a) { return max(max(abs(a.x), abs(a.y)), abs(a.z)); }

// 1 / d, RS_ZERO_INV for a zero component (-0.0 included: equal() is true for it).
vec3 rs_inv(vec3 d) { return mix(1.0 / d, vec3(RS_ZERO_INV), equal(d, vec3(0.0))); }

// The origin the slab test subtracts from hi (rs_box; lo - o uses o): o, except on a zero
// direction component, where it is o - eps. There inv = RS_ZERO_INV: a ray lying in the
// slab gets near = (lo - o) * 1e30 <= 0 and far >= eps * 1e30, beyond any box's t, so the
// slab constrains nothing, as the reference's "inside iff lo <= o <= hi" (1/0 = inf) — in
// its hi face plane too, where (hi - o) * 1e30 = 0 would be a far of 0 and skip the box.
// A box whose hi is within eps below o is entered too: a box test more, never a lost hit.
// No arithmetic per box: the same subtractions.
vec3 rs_slab_hi_origin(vec3 o, vec3 d)
{
	return o - mix(vec3(0.0), abs(o) * RS_ZERO_REL + RS_ZERO_ABS, equal(d, vec3(0.0)));
}

// Per-ray values every box and triangle test reuses.
struct Pre {
	vec3 inv;
	vec3 ohi; // rs_slab_hi_origin
	bvec3 pos; // inv >= 0: near is the lo plane
	float dmax;
	ivec3 k;   // watertight: (kx, ky, kz)
	vec3 shear; // (sx, sy, sz)
};

Pre rs_prepare(Ray r)
{
	Pre p;
	p.inv = rs_inv(r.d);
	p.ohi = rs_slab_hi_origin(r.o, r.d);
	p.pos = greaterThanEqual(p.inv, vec3(0.0));
	p.dmax = rs_maxabs(r.d);
	int kz = 0;
	if (abs(r.d.y) > abs(r.d[kz]))
		kz = 1;
	if (abs(r.d.z) > abs(r.d[kz]))
		kz = 2;
	int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
	if (r.d[kz] < 0.0) {
		int t = kx;
		kx = ky;
		ky = t;
	}
	p.k = ivec3(kx, ky, kz);
	p.shear = vec3(r.d[kx] / r.d[kz], r.d[ky] / r.d[kz], 1.0 / r.d[kz]);
	return p;
}

// Slab test (R3), near/far picked by the direction's sign (an empty box stays empty), the
// nearest far and farthest near widened outwards once (widening is monotone, so this is
// widening every slab's). A zero direction component has inv = RS_ZERO_INV and its hi
// plane moved out by eps (rs_slab_hi_origin): lying in the slab, faces included, the slab
// constrains nothing; outside it the box is missed, unless closer than tf / 1e30 below lo
// or eps above hi, where it is entered (conservative: only a box test more, never a lost
// hit). No NaN: inv is finite, so no 0 * inf.
bool rs_box(vec3 lo, vec3 hi, Ray r, Pre p, float tmax)
{
	vec3 t0 = (lo - r.o) * p.inv, t1 = (hi - p.ohi) * p.inv;
	vec3 near = mix(t1, t0, p.pos);
	vec3 far = mix(t0, t1, p.pos);
	float tn = max(max(near.x, near.y), max(near.z, 0.0)) * RS_BOX_SHRINK;
	float tf = min(min(far.x, far.y), min(far.z, tmax));
	tf *= tf > 0.0 ? RS_BOX_GROW : RS_BOX_SHRINK;
	return tn <= tf;
}

// rs_box from the ray's origin, hi origin and 1 / d alone (the two-level walk's current ray).
bool rs_box_at(vec3 lo, vec3 hi, vec3 o, vec3 ohi, vec3 inv, float tmax)
{
	vec3 t0 = (lo - o) * inv, t1 = (hi - ohi) * inv;
	bvec3 pos = greaterThanEqual(inv, vec3(0.0));
	vec3 near = mix(t1, t0, pos);
	vec3 far = mix(t0, t1, pos);
	float tn = max(max(near.x, near.y), max(near.z, 0.0)) * RS_BOX_SHRINK;
	float tf = min(min(far.x, far.y), min(far.z, tmax));
	tf *= tf > 0.0 ? RS_BOX_GROW : RS_BOX_SHRINK;
	return tn <= tf;
}

#if RS_WATERTIGHT
vec3 rs_perm(vec3 a, ivec3 k) { return vec3(a[k.x], a[k.y], a[k.z]); }

// Woop, Benthin & Wald 2013, as lib/trace/intersect.c.
bool rs_triangle(vec3 v0, vec3 v1, vec3 v2, Ray r, Pre p, float tmax, out vec3 tuv)
{
	vec3 e1 = v1 - v0, e2 = v2 - v0;
	vec3 n = cross(e1, e2);
	float nm = rs_maxabs(n);
	if (nm == 0.0 || abs(dot(r.d, n)) <= RS_PARALLEL_EPS * p.dmax * nm)
		return false;
	vec3 a = rs_perm(v0 - r.o, p.k), b = rs_perm(v1 - r.o, p.k), c = rs_perm(v2 - r.o, p.k);
	float ax = a.x - p.shear.x * a.z, ay = a.y - p.shear.y * a.z;
	float bx = b.x - p.shear.x * b.z, by = b.y - p.shear.y * b.z;
	float cx = c.x - p.shear.x * c.z, cy = c.y - p.shear.y * c.z;
	float U = cx * by - cy * bx;
	float V = ax * cy - ay * cx;
	float W = bx * ay - by * ax;
	if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0))
		return false;
	float det = U + V + W;
	if (det == 0.0)
		return false;
	float sz = p.shear.z;
	float t = (U * sz * a.z + V * sz * b.z + W * sz * c.z) / det;
	if (!(t > 0.0 && t <= tmax))
		return false;
	tuv = vec3(t, V / det, W / det);
	return true;
}
#else
// Moller-Trumbore, as lib/trace/intersect.c: numerators compared against |det|.
bool rs_triangle(vec3 v0, vec3 v1, vec3 v2, Ray r, Pre p, float tmax, out vec3 tuv)
{
	vec3 e1 = v1 - v0, e2 = v2 - v0;
	vec3 pv = cross(r.d, e2);
	float det = dot(e1, pv);
	if (abs(det) <= RS_PARALLEL_EPS * p.dmax * rs_maxabs(e1) * rs_maxabs(e2))
		return false;
	float sgn = det > 0.0 ? 1.0 : -1.0, adet = abs(det);
	vec3 s = r.o - v0;
	float un = dot(s, pv) * sgn;
	if (un < 0.0 || un > adet)
		return false;
	vec3 q = cross(s, e1);
	float vn = dot(r.d, q) * sgn;
	if (vn < 0.0 || un + vn > adet)
		return false;
	float inv = 1.0 / det;
	float t = dot(e2, q) * inv;
	if (!(t > 0.0 && t <= tmax))
		return false;
	tuv = vec3(t, un * sgn * inv, vn * sgn * inv);
	return true;
}
#endif

// The closest-hit rule (R4): nearer wins, and on exactly equal t the lower scene triangle
// id, so the answer does not depend on the order the BVH visits triangles. The triangle
// test accepts t <= the bound passed; the ray's own tmax stays exclusive.
bool rs_better(float t, float id, Hit best, bool found, float tmax)
{
	return found ? t < best.t || (t == best.t && id < best.id) : t < tmax;
}

// The node order of a direction (rs_pack_node_order_of): eight orders by the octant, six by
// the major direction, else the one.
int rs_order(vec3 d)
{
#if RS_NODE_ORDERS == 8
	bvec3 neg = lessThan(d, vec3(0.0));
	return (neg.x ? 1 : 0) + (neg.y ? 2 : 0) + (neg.z ? 4 : 0);
#elif RS_NODE_ORDERS > 1
	vec3 ad = abs(d);
	int axis = ad.y > ad.x ? 1 : 0;
	if (ad.z > ad[axis])
		axis = 2;
	return 2 * axis + (d[axis] < 0.0 ? 1 : 0);
#else
	return 0;
#endif
}

#if !RS_WIDE_NODES
// Node i as both formats decode it (rs_pack_read_node): bounds, and `next` = the escape
// (the node after a miss, at least i + 1); `first` >= 0 for a leaf's first slot, else -1.
struct Node {
	vec3 lo;
	vec3 hi;
	vec3 qlo; // compact: the bounds' grid indices (rs_box_grid); paper: unused
	vec3 qhi;
	int next;
	int first;
};

// go, gs: the tree's compact grid (the scene's, or two levels: the TLAS's or a BLAS's).
Node rs_node_in(int i, vec3 go, vec3 gs)
{
	Node n;
#if RS_COMPACT_NODES
	// One fetch. Bounds = origin + q * step are exact in fp32 (power-of-two step).
	uvec4 q = rs_fetch(u_nodes, rs_item(i, 1, 0));
	n.qlo = vec3(uvec3(q.x & 0xffffu, q.x >> 16, q.y & 0xffffu));
	n.qhi = vec3(uvec3(q.y >> 16, q.z & 0xffffu, q.z >> 16));
	n.lo = go + n.qlo * gs;
	n.hi = go + n.qhi * gs;
	bool leaf = q.w >= 0x80000000u;
	n.next = leaf ? i + 1 : max(int(q.w), i + 1);
	n.first = leaf ? int(q.w & 0x7fffffffu) : -1;
#else
	vec4 n0 = rs_fetch(u_nodes, rs_item(i, 3, 0));
	vec4 n1 = rs_fetch(u_nodes, rs_item(i, 3, 1));
	n.lo = n0.xyz;
	n.hi = n1.xyz;
	n.qlo = n.qhi = vec3(0.0);
	n.next = max(int(n0.w), i + 1);
	vec2 slots = n1.w != 0.0 ? vec2(-1.0, 0.0) : rs_fetch(u_nodes, rs_item(i, 3, 2)).xy;
	n.first = slots.y > 0.0 ? int(slots.x) : -1; // an empty leaf tests nothing
#endif
	return n;
}

#if RS_COMPACT_NODES
Node rs_node(int i) { return rs_node_in(i, u_grid_origin, u_grid_step); }
#else
Node rs_node(int i) { return rs_node_in(i, vec3(0.0), vec3(0.0)); }
#endif
#endif

// The last closest hit's triangle texels as the walk read them, so shading does not fetch
// them again (a slot's texels never change, so a match by slot is always right; the
// separate chains, whose hits come from a texture, fetch). 3 % on Cow17, 2 passes.
int g_hit_slot = -1;
vec4 g_hit_v0, g_hit_v1, g_hit_v2;
#if RS_TWO_LEVEL
int g_hit_inst = -1; // two levels: the instance and the slot of the cached hit (g_hit_slot
int g_hit_blas = -1; // is its scene id); the texels are in the BLAS's frame
#endif

// A leaf's triangles from slot `first` to the one with the last flag, the closest-hit rule
// (R4) shrinking h.t; true when `stop` (a shadow feeler) may stop at the hit found.
bool rs_leaf(int first, Ray r, Pre p, bool stop, inout Hit h, inout bool found,
             inout vec2 counts)
{
	for (int s = first; s < u_tri_count; s++) {
		vec4 v0 = rs_tri(s, 0), v2 = rs_tri(s, 2);
		if (s != r.skip) {
			counts.y += 1.0;
			vec4 v1 = rs_tri(s, 1);
			vec3 tuv;
			if (rs_triangle(v0.xyz, v1.xyz, v2.xyz, r, p, h.t, tuv) &&
			    rs_better(tuv.x, v0.w, h, found, r.tmax)) {
				found = true;
				h = Hit(tuv.x, tuv.y, tuv.z, s, v0.w);
				if (stop)
					return true;
				g_hit_slot = s;
				g_hit_v0 = v0;
				g_hit_v1 = v1;
				g_hit_v2 = v2;
			}
		}
		if (v2.w != 0.0)
			break;
	}
	return false;
}

#if RS_WIDE_NODES
// Child c's bound in a wide node (rs_pack_read_wide): Q = o + (q << e) on the compact grid,
// bound = origin + Q * step, exact in fp32 (Q < 2^18) however the GPU rounds.
vec3 rs_wide_bound(uvec3 o, uvec3 e, uvec3 words, uint c, out ivec3 q)
{
	uvec3 qq = o + (((words >> (8u * c)) & 0xffu) << e);
	q = ivec3(qq);
	return u_grid_origin + vec3(qq) * u_grid_step;
}

// The wide walk (RS_PACK_NODES_WIDE4), step for step lib/trace/traverse.c traverse_wide: a
// stack of child words (a node index, or 0x80000000 | a leaf's first slot); at a node
// every child box is tested (one box test each, two texel fetches for four boxes) and the
// children hit are pushed farthest first in the ray's octant order, the integer key
// sum_a sign(d_a) (qlo_a + qhi_a), ties to the lower slot on top; the third texel (the
// child words) is fetched only when a box is hit. Packing refused any tree whose walk
// could need more than RS_WIDE_STACK entries. Two loops as the binary walk's: interior
// nodes until a leaf comes up, then its triangles.
bool rs_traverse(Ray r, bool stop, out Hit h, inout vec2 counts)
{
	Pre p = rs_prepare(r);
	h = Hit(r.tmax, 0.0, 0.0, -1, -1.0);
	bool found = false;
	if (u_node_count <= 0)
		return false;
	ivec3 sgn = ivec3(1) - 2 * ivec3(lessThan(r.d, vec3(0.0)));
	uint stack[RS_WIDE_STACK];
	int sp = 0;
	uint entry = 0u;
	while (true) {
		while (entry < 0x80000000u) {
			int k = int(entry);
			uvec4 t0 = rs_fetch(u_nodes, rs_item(k, 3, 0));
			uvec4 t1 = rs_fetch(u_nodes, rs_item(k, 3, 1));
			uint n = t1.w >> 28;
			uvec3 o = uvec3(t1.z & 0xffffu, t1.z >> 16, t1.w & 0xffffu);
			uvec3 e = (uvec3(t1.w) >> uvec3(16u, 20u, 24u)) & 0xfu;
			uvec3 wlo = t0.xyz, whi = uvec3(t0.w, t1.xy);
			ivec4 key = ivec4(0);
			bvec4 hit = bvec4(false);
			for (uint c = 0u; c < 4u; c++)
				if (c < n) {
					ivec3 qlo, qhi;
					vec3 lo = rs_wide_bound(o, e, wlo, c, qlo);
					vec3 hi = rs_wide_bound(o, e, whi, c, qhi);
					counts.x += 1.0;
					hit[c] = rs_box(lo, hi, r, p, h.t);
					ivec3 sk = sgn * (qlo + qhi);
					key[c] = sk.x + sk.y + sk.z;
				}
			if (hit.x || hit.y || hit.z || hit.w) {
				uvec4 words = rs_fetch(u_nodes, rs_item(k, 3, 2));
				for (int c = 0; c < 4; c++) {
					uint w = words[c];
					// corrupt data never reads outside: a child node above this one,
					// a leaf's slot below the triangle count
					bool ok = w >= 0x80000000u ? int(w & 0x7fffffffu) < u_tri_count
					                            : int(w) > k && int(w) < u_node_count;
					hit[c] = hit[c] && ok;
				}
				int pushed = 0;
				for (int c = 0; c < 4; c++)
					if (hit[c]) {
						int below = 0;
						for (int d = 0; d < 4; d++)
							if (hit[d] && (key[d] > key[c] || (key[d] == key[c] && d > c)))
								below++;
						if (sp + below < RS_WIDE_STACK)
							stack[sp + below] = words[c];
						pushed++;
					}
				sp = min(sp + pushed, RS_WIDE_STACK);
			}
			if (sp == 0)
				return found;
			entry = stack[--sp];
		}
		if (rs_leaf(int(entry & 0x7fffffffu), r, p, stop, h, found, counts))
			return true;
		if (sp == 0)
			return found;
		entry = stack[--sp];
	}
	return found;
}
#elif RS_TWO_LEVEL
// Texel j of instance i (RS_PACK_INSTANCE_TEXELS in rs_pack.h).
vec4 rs_instance(int i, int j)
{
#if RS_SCENE_BUFFERS
	return texelFetch(u_instances, i * RS_INSTANCE_TEXELS + j);
#else
	return texelFetch(u_instances,
	                  ivec2((i % RS_INSTANCE_ROW_ITEMS) * RS_INSTANCE_TEXELS + j,
	                        i / RS_INSTANCE_ROW_ITEMS),
	                  0);
#endif
}

// A BLAS leaf's triangles (rs_leaf with scene ids: first_tri + the local id in t0.w, and
// the loose BLAS's t0.w already the scene id with first_tri 0).
bool rs_leaf_blas(int first, Ray r, Pre p, bool stop, float first_tri, int inst, inout Hit h,
                  inout bool found, inout vec2 counts)
{
	for (int s = first; s < u_tri_count; s++) {
		vec4 v0 = rs_tri(s, 0), v2 = rs_tri(s, 2);
		float id = first_tri + v0.w;
		if (int(id) != r.skip) {
			counts.y += 1.0;
			vec4 v1 = rs_tri(s, 1);
			vec3 tuv;
			if (rs_triangle(v0.xyz, v1.xyz, v2.xyz, r, p, h.t, tuv) &&
			    rs_better(tuv.x, id, h, found, r.tmax)) {
				found = true;
				h = Hit(tuv.x, tuv.y, tuv.z, int(id), id);
				if (stop)
					return true;
				g_hit_slot = int(id);
				g_hit_inst = inst;
				g_hit_blas = s;
				g_hit_v0 = v0;
				g_hit_v1 = v1;
				g_hit_v2 = v2;
			}
		}
		if (v2.w != 0.0)
			break;
	}
	return false;
}

// The two-level walk (docs/bvh.md "Instances on the GPU"), step for step lib/trace
// traverse_instances.c: the TLAS's threaded order of the ray's direction; at a TLAS leaf
// each of its instances in turn: the ray into the instance's BLAS frame (to_object), the
// BLAS's threaded order of that direction from its base, its grid, boxes widened one float
// step as the CPU's; at the BLAS's end the next instance of the leaf, or back to the leaf's
// escape in the TLAS with the world ray. t is the same along both rays (affine map). Box
// tests count both levels, triangle tests the BLASes'.
bool rs_traverse(Ray r, bool any, out Hit h, inout vec2 counts)
{
	Pre pw = rs_prepare(r);
	h = Hit(r.tmax, 0.0, 0.0, -1, -1.0);
	bool found = false;
	int i = u_top_base + rs_order(r.d) * u_top_count;
	int top_end = i + u_top_count, end = top_end;
	int inst = -1, tslot = -1, ret = 0;
	float first_tri = 0.0;
	// The ray of the tree being walked (world, or a BLAS's object ray) as plain vectors:
	// a struct assigned inside the loop costs llvmpipe 4x per node (measured on cow1i).
	vec3 co = r.o, cd = r.d, cinv = pw.inv, cohi = pw.ohi;
	vec3 go = u_grid_origin, gs = u_grid_step;
	while (true) {
		// The inner loop is the node step alone, as the one-level walk's: llvmpipe runs
		// every block of a loop body whose condition differs between lanes for all lanes
		// (masked), so the entry (seven fetches) and exit of a BLAS must stay out of it:
		// inside it they cost every node step 3.4x (docs/gles.md "Instances").
		int first = -1;
		while (i < end) {
			Node n = rs_node_in(i, go, gs);
			counts.x += 1.0;
			if (inst >= 0) {
				// one float step outwards (traverse_instances.c, the edge slack's twin)
				n.lo -= abs(n.lo) * 1.1920929e-7 + 1.17549435e-38;
				n.hi += abs(n.hi) * 1.1920929e-7 + 1.17549435e-38;
			}
			if (!rs_box_at(n.lo, n.hi, co, cohi, cinv, h.t)) {
				i = n.next;
				continue;
			}
			if (n.first < 0) {
				i++;
				continue;
			}
			first = n.first;
			i = n.next;
			break;
		}
		// a BLAS leaf's triangles, a TLAS leaf's first instance, a BLAS's end (the leaf's
		// next instance or back to its escape in the TLAS), or the TLAS's end
		int enter = -1;
		if (first >= 0) {
			if (inst >= 0) {
				Ray o = Ray(co, cd, r.tmax, r.skip);
				if (rs_leaf_blas(first, o, rs_prepare(o), any, first_tri, inst, h, found,
				                 counts))
					return true;
			} else {
				ret = i;
				enter = first;
			}
		} else {
			if (inst < 0)
				break;
			inst = -1;
			if (rs_tri(tslot, 2).w == 0.0) { // more instances in this TLAS leaf
				enter = tslot + 1;
			} else {
				i = ret;
				end = top_end;
				go = u_grid_origin;
				gs = u_grid_step;
				co = r.o;
				cd = r.d;
				cinv = pw.inv;
				cohi = pw.ohi;
			}
		}
		if (enter >= 0) {
			tslot = enter;
			inst = int(rs_tri(tslot, 0).w);
			vec4 m0 = rs_instance(inst, 0), m1 = rs_instance(inst, 1), m2 = rs_instance(inst, 2);
			co = vec3(dot(m0.xyz, r.o) + m0.w, dot(m1.xyz, r.o) + m1.w, dot(m2.xyz, r.o) + m2.w);
			cd = vec3(dot(m0.xyz, r.d), dot(m1.xyz, r.d), dot(m2.xyz, r.d));
			cinv = rs_inv(cd);
			cohi = rs_slab_hi_origin(co, cd);
			vec4 g0 = rs_instance(inst, 9), g1 = rs_instance(inst, 10);
			go = g0.xyz;
			gs = g1.xyz;
			first_tri = rs_instance(inst, 6).w;
			int count = int(g1.w);
			i = int(g0.w) + rs_order(cd) * count;
			end = i + count;
		}
	}
	return found;
}

// A scene triangle id's instance and slot (hit texels carry the id): the prototypes'
// instances by a binary search of their first ids (ascending), else the loose instance,
// whose local id is found by a binary search of its scene ids; the slot from the normal
// texture's spare channel (rs_pack.h, RS_PACK_INSTANCE_TEXELS).
void rs_locate(int id, out int inst, out int slot)
{
	float f = float(id);
	int lo = 0, hi = u_proto_instances - 1;
	inst = -1;
	while (lo <= hi) {
		int mid = (lo + hi) / 2;
		if (f < rs_instance(mid, 6).w) {
			hi = mid - 1;
		} else {
			inst = mid;
			lo = mid + 1;
		}
	}
	if (inst >= 0) {
		vec4 t11 = rs_instance(inst, 11);
		float local = f - rs_instance(inst, 6).w;
		if (local < t11.x) {
			slot = int(rs_normal(int(t11.y + local), 0).w);
			return;
		}
	}
	inst = u_instance_count - 1;
	slot = -1;
	if (u_proto_instances == u_instance_count)
		return;
	vec4 t11 = rs_instance(inst, 11);
	int base = int(t11.y);
	lo = 0;
	hi = int(t11.x) - 1;
	while (lo <= hi) {
		int mid = (lo + hi) / 2;
		float m = rs_normal(base + mid, 1).w;
		if (m == f) {
			slot = int(rs_normal(base + mid, 0).w);
			return;
		}
		if (m < f)
			lo = mid + 1;
		else
			hi = mid - 1;
	}
}
#else
#if RS_COMPACT_NODES
// The hits-only kernel's box test (primary.glsl): in grid units, t = q * a + b for a plane
// at grid index q (a = step / d, b = (grid origin - o) / d, per ray), one multiply-add a
// plane instead of rs_node's decode and rs_box's subtract and multiply. Its rounding
// differs from R3's, so it is widened by its own bound instead of K: every plane of axis x
// has |t| <= RS_GRID_STEPS (65535) |a| + |b| = m, the rounding of a, b and the
// multiply-add is below 6 * 2^-24 * m, and the slack e = RS_GRID_BOX_E (2^-18) * m covers
// that and the triangle test's rounding of t with room (R3's K leaves 13 ulps for it,
// this over 50). So the box is conservative (never a lost hit: the hits are R4's, bit for
// bit) and at most 2^-18 of the grid's distance looser; its tests are not R3's, so a walk with it is never
// counted (the hits-only kernel has no counters). Where m is not below 1e37 (a zero
// direction component, 1/d = 1e30, in a scene of ~1e7 units: q * a + b could overflow)
// that axis constrains nothing (a = 0, b = -+3e38): every box entered, slower, never wrong.
struct Grid {
	vec3 a;
	vec3 bn; // b - e: the near planes' offset
	vec3 bf; // b + e
};

Grid rs_grid(Ray r, Pre p)
{
	Grid g;
	g.a = u_grid_step * p.inv;
	vec3 b = (u_grid_origin - r.o) * p.inv;
	vec3 m = RS_GRID_STEPS * abs(g.a) + abs(b);
	vec3 e = m * RS_GRID_BOX_E;
	// m too large (or not a number): every box of that axis entered, slack ample
	bvec3 ok = lessThan(m, vec3(1.0e37));
	g.a = mix(vec3(0.0), g.a, ok);
	g.bn = mix(vec3(-3.0e38), b - e, ok);
	g.bf = mix(vec3(3.0e38), b + e, ok);
	return g;
}

bool rs_box_grid(vec3 qlo, vec3 qhi, Pre p, Grid g, float tmax)
{
	vec3 near = mix(qhi, qlo, p.pos) * g.a + g.bn;
	vec3 far = mix(qlo, qhi, p.pos) * g.a + g.bf;
	float tn = max(max(near.x, near.y), max(near.z, 0.0));
	float tf = min(min(far.x, far.y), min(far.z, tmax));
	return tn <= tf;
}
#endif

// Stackless walk of the threaded BVH (pre-order, escape indices). `any`: stop at the first
// hit (shadow feelers). counts += (box tests, triangle tests), as the CPU counts them.
// Two loops, "while-while" (Aila & Laine 2009): the inner one walks boxes until this ray
// reaches a leaf its box test lets in, then the leaf's triangles are tested. On SIMD
// hardware that runs a group of pixels in lock step (llvmpipe: 8 lanes) the group meets the
// triangle loop together instead of once per lane that happens to sit at a leaf: 1.8x faster
// on Cow17 than one loop with the leaf inside (docs/benchmarks.md), same tests counted.
// `grid` (a constant at every call, so the compiler keeps one box test): rs_box_grid, the
// hits-only kernel's (compact nodes), else R3's rs_box.
bool rs_walk(Ray r, bool any, bool grid, out Hit h, inout vec2 counts)
{
	Pre p = rs_prepare(r);
#if RS_COMPACT_NODES
	Grid g = rs_grid(r, p);
#endif
	h = Hit(r.tmax, 0.0, 0.0, -1, -1.0);
	bool found = false;
	// The node order of the ray's direction (rs_pack_node_order_of): near boxes first.
	int i = rs_order(r.d) * u_node_count;
	int end = i + u_node_count;
	while (i < end) {
		int first = -1;
		while (i < end) {
			Node n = rs_node(i);
			counts.x += 1.0;
#if RS_COMPACT_NODES
			bool in_box = grid ? rs_box_grid(n.qlo, n.qhi, p, g, h.t)
			                   : rs_box(n.lo, n.hi, r, p, h.t);
#else
			bool in_box = rs_box(n.lo, n.hi, r, p, h.t);
#endif
			if (!in_box) {
				i = n.next;
				continue;
			}
			if (n.first < 0) {
				i++;
				continue;
			}
			first = n.first;
			i = n.next;
			break;
		}
		if (first < 0)
			break;
		if (rs_leaf(first, r, p, any, h, found, counts))
			return true;
	}
	return found;
}

bool rs_traverse(Ray r, bool any, out Hit h, inout vec2 counts)
{
	return rs_walk(r, any, false, h, counts);
}
#endif
