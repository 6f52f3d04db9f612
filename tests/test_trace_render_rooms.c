/* rs_trace, spawn rule (docs/tracer.md R5): closed rooms seen from inside, with rays that
 * land on edges, vertices and corners to within an ulp. Every point that sees the light is
 * lit, and no path ever leaves a closed room, at several scales and offsets. About 2.4
 * million rays over this file (primary, reflected and shadow feelers). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "test_trace_render_fixture.h"

/* The reproducer: a 12-triangle room, x and y in +-255/512, z in +-1, walls wound
 * inwards, mirror walls, eye at the origin looking down -z, 90 degrees, 512 x 512. Pixel
 * centres on the image diagonals look exactly into the room's edges. */
static void room(struct fx *fx, float kd, float reflectance)
{
	fx->scene = fx_scene();
	struct rs_material m = {.diffuse = {kd, kd, kd}, .reflectance = reflectance};
	uint32_t mat = fx_material(fx->scene, m);
	const double h = 255.0 / 512.0;
	fx_rect(fx->scene, 0, -h, -h, h, -1, 1, 0, mat); /* normals point inwards */
	fx_rect(fx->scene, 0, h, -h, h, -1, 1, 1, mat);
	fx_rect(fx->scene, 1, -h, -1, 1, -h, h, 0, mat);
	fx_rect(fx->scene, 1, h, -1, 1, -h, h, 1, mat);
	fx_rect(fx->scene, 2, -1, -h, h, -h, h, 0, mat);
	fx_rect(fx->scene, 2, 1, -h, h, -h, h, 1, mat);
	struct rs_camera c = {.target = {0, 0, -1}, .up = {0, 1, 0}, .fov_y_deg = 90};
	c.width = c.height = 512;
	assert_int_equal(rs_scene_set_camera(fx->scene, &c, NULL), RS_OK);
	fx_light(fx->scene, 0.1, 0.2, -0.3, 1, 1, 1);
	struct rs_environment env = {.half_size = 4};
	for (int f = 0; f < 6; ++f) {
		env.face_color[f][0] = env.face_color[f][2] = 1.0f; /* magenta */
	}
	assert_int_equal(rs_scene_set_environment(fx->scene, &env, NULL), RS_OK);
	fx_pack(fx, RS_BVH_SAH);
}

#define ROOM 512
static float room_rgb[ROOM * ROOM * 3];

static void room_edges_are_lit_and_hold_every_path(void **state)
{
	struct fx fx;
	room(&fx, 0.8f, 0.9f);
	/* 1 pass: every wall point sees the light (convex room, light inside); the dimmest
	 * point gets N.L > 0.1, so lit means above ambient 0.1 * 0.8 + 0.8 * 0.1. */
	struct rs_trace_desc d = {.passes = 1, .triangle_test = RS_TRIANGLE_WATERTIGHT};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, room_rgb, NULL, NULL, NULL),
	                 RS_OK);
	size_t dark = 0;
	for (size_t i = 0; i < (size_t)ROOM * ROOM; ++i)
		dark += !(room_rgb[3 * i + 1] > 0.08f + 0.08f);
	if (dark)
		fail_msg("1 pass: %zu pixels at ambient only", dark);
	/* 2 passes: no path leaves the closed room. The walls are grey and the light white,
	 * so in-room colours have r == g; the magenta environment adds r, not g. (Longer
	 * mirror paths: the boxes below.) */
	for (uint32_t passes = 2; passes <= 2; ++passes) {
		d.passes = passes;
		assert_int_equal(
		    rs_trace_render(fx.scene, &fx.packed, &d, room_rgb, NULL, NULL, NULL), RS_OK);
		size_t out = 0;
		for (size_t i = 0; i < (size_t)ROOM * ROOM; ++i)
			out += fabsf(room_rgb[3 * i] - room_rgb[3 * i + 1]) > 1e-5f;
		if (out)
			fail_msg("%u passes: %zu paths left the room", passes, out);
	}
	fx_free(&fx);
}

/* R5 evaluated in fp32, as the GLES kernels will: for every pixel of the reproducer (whose
 * diagonals look exactly into the room's edges), the spawned origin lies inside all six
 * walls by at least 8 fp32 ulps of the room's half-size, and off its own wall by at least
 * half of delta. (The fp32 intersection tests are the GLES backend's to check.) */
static void spawn_rule_holds_in_fp32(void **state)
{
	struct fx fx;
	room(&fx, 0.8f, 0.9f);
	const float h = 255.0f / 512.0f, half_size = 1.0f; /* R: half the largest side */
	const float floor_m = half_size / 16.0f, scale = 0x1p-16f;
	const float margin = 8.0f * 0x1p-24f; /* 8 ulps of numbers in [0.5, 1) */
	struct rs_camera cam;
	rs_camera_resolve(rs_scene_camera(fx.scene), &cam);
	size_t bad = 0;
	for (uint32_t y = 0; y < ROOM; ++y)
		for (uint32_t x = 0; x < ROOM; ++x) {
			struct rs_ray ray;
			struct rs_hit hit;
			rs_trace_camera_ray(&cam, ROOM, ROOM, x + 0.5, y + 0.5, &ray);
			assert_true(
			    rs_trace_closest(&fx.packed, RS_TRIANGLE_WATERTIGHT, &ray, &hit, NULL));
			float v[3][3], e1[3], e2[3], c[3], g[3], len[3], b[3], p[3], o[3];
			float m = floor_m;
			for (uint32_t k = 0; k < 3; ++k)
				for (int a = 0; a < 3; ++a) {
					v[k][a] =
					    rs_pack_texel(&fx.packed.triangles,
					                  RS_PACK_TRIANGLE_TEXELS, hit.slot, k)[a];
					m = fmaxf(m, fabsf(v[k][a]));
				}
			float delta = scale * m;
			for (int a = 0; a < 3; ++a) {
				e1[a] = v[1][a] - v[0][a];
				e2[a] = v[2][a] - v[0][a];
			}
			c[0] = e1[1] * e2[2] - e1[2] * e2[1];
			c[1] = e1[2] * e2[0] - e1[0] * e2[2];
			c[2] = e1[0] * e2[1] - e1[1] * e2[0];
			float a2 = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
			for (int k = 0; k < 3; ++k) {
				const float *s0 = v[(k + 1) % 3], *s1 = v[(k + 2) % 3];
				len[k] = sqrtf((s1[0] - s0[0]) * (s1[0] - s0[0]) +
				               (s1[1] - s0[1]) * (s1[1] - s0[1]) +
				               (s1[2] - s0[2]) * (s1[2] - s0[2]));
			}
			b[0] = 1.0f - (float)hit.u - (float)hit.v;
			b[1] = (float)hit.u;
			b[2] = (float)hit.v;
			float sum = 0.0f;
			for (int k = 0; k < 3; ++k) {
				float hk = len[k] > 0.0f ? a2 / len[k] : 0.0f;
				b[k] = fmaxf(b[k],
				             hk > 12.0f * delta ? 4.0f * delta / hk : 1.0f / 3.0f);
				sum += b[k];
			}
			for (int a = 0; a < 3; ++a) {
				g[a] = c[a] / a2;
				if (g[a] * (float)ray.dir[a] > 0.0f) /* face the incoming ray */
					g[a] = -g[a];
				p[a] = v[0][a] + (b[1] / sum) * e1[a] + (b[2] / sum) * e2[a];
				o[a] = p[a] + delta * g[a]; /* leaving into the room */
			}
			const float lim[3] = {h, h, 1.0f};
			for (int a = 0; a < 3; ++a)
				bad += !(lim[a] - fabsf(o[a]) >= margin);
			/* off its own wall: the wall's axis is the one g points along */
			int w = fabsf(g[0]) > 0.5f ? 0 : fabsf(g[1]) > 0.5f ? 1 : 2;
			bad += !(lim[w] - fabsf(o[w]) >= 0.5f * delta);
		}
	if (bad)
		fail_msg("%zu fp32 spawn origins too close to a wall", bad);
	fx_free(&fx);
}

/* ---- subdivided boxes at several scales, offsets and orientations ------------------ */

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}

#define GRID 8 /* each face: GRID x GRID quads, 2 triangles each: 768 triangles */

struct box_room {
	double half[3], offset[3], rot[3][3]; /* world = offset + rot * local */
	bool f64;                             /* hand positions in as doubles */
};

/* Face f: axis f/2, side -1 (f even) or +1; local grid point (i, j) in [0, GRID]^2. Every
 * world coordinate is computed by one formula from (axis, side, i, j) mapped back to the
 * box's lattice, so a point shared by two faces rounds to the same float in both. */
static void lattice_point(const struct box_room *b, const int q[3], double out[3])
{
	double local[3];
	for (int a = 0; a < 3; ++a)
		local[a] = b->half[a] * (2.0 * q[a] / GRID - 1.0);
	for (int r = 0; r < 3; ++r) {
		out[r] = b->offset[r] + b->rot[r][0] * local[0] + b->rot[r][1] * local[1] +
		         b->rot[r][2] * local[2];
		if (!b->f64)
			out[r] = (float)out[r];
	}
}

static void face_lattice(int f, int i, int j, int q[3])
{
	int axis = f / 2, a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
	q[axis] = f % 2 ? GRID : 0;
	q[a1] = i;
	q[a2] = j;
}

static void box_room_build(struct fx *fx, struct box_room *b, float reflectance)
{
	fx->scene = fx_scene();
	struct rs_material m = {.diffuse = {0.8f, 0.8f, 0.8f}, .reflectance = reflectance};
	uint32_t mat = fx_material(fx->scene, m);
	const int n = GRID + 1;
	static double pos[(GRID + 1) * (GRID + 1) * 3];
	static float fpos[(GRID + 1) * (GRID + 1) * 3];
	static uint32_t idx[GRID * GRID * 6];
	for (int f = 0; f < 6; ++f) {
		for (int i = 0; i < n; ++i)
			for (int j = 0; j < n; ++j) {
				int q[3];
				face_lattice(f, i, j, q);
				lattice_point(b, q, &pos[3 * (i * n + j)]);
				for (int a = 0; a < 3; ++a)
					fpos[3 * (i * n + j) + a] = (float)pos[3 * (i * n + j) + a];
			}
		/* (a1, a2, axis) is right-handed: i x j = +axis. Inwards = -axis on the
		 * + side, so the + side is wound (i, j) clockwise. */
		for (int i = 0; i < GRID; ++i)
			for (int j = 0; j < GRID; ++j) {
				uint32_t v00 = (uint32_t)(i * n + j), v10 = v00 + (uint32_t)n;
				uint32_t v01 = v00 + 1, v11 = v10 + 1,
				         *t = &idx[6 * (i * GRID + j)];
				uint32_t in[6] = {v00, v10, v11, v00, v11, v01};
				uint32_t out[6] = {v00, v11, v10, v00, v01, v11};
				memcpy(t, f % 2 ? out : in, sizeof in);
			}
		struct rs_mesh_desc d = {.positions = b->f64 ? NULL : fpos,
		                         .positions_f64 = b->f64 ? pos : NULL,
		                         .vertex_count = (size_t)n * n,
		                         .indices = idx,
		                         .triangle_count = GRID * GRID * 2,
		                         .material = mat};
		assert_int_equal(rs_scene_add_mesh(fx->scene, &d, NULL), RS_OK);
	}
}

/* A random point strictly inside the box, within `share` of its half-sizes. */
static void inside(const struct box_room *b, double share, double out[3])
{
	double local[3];
	for (int a = 0; a < 3; ++a)
		local[a] = b->half[a] * share * (2.0 * rnd() - 1.0);
	for (int r = 0; r < 3; ++r)
		out[r] = b->offset[r] + b->rot[r][0] * local[0] + b->rot[r][1] * local[1] +
		         b->rot[r][2] * local[2];
}

/* A target on the box's float geometry: a lattice vertex (corners included), or a point
 * on a lattice edge between two neighbouring vertices (so on a triangle edge, to within an
 * ulp of the double interpolation). */
static void surface_target(const struct box_room *b, double out[3])
{
	int f = (int)(rnd() * 6), q[3], q2[3];
	face_lattice(f, (int)(rnd() * (GRID + 1)), (int)(rnd() * (GRID + 1)), q);
	double p[3], p2[3];
	lattice_point(b, q, p);
	double kind = rnd();
	if (kind < 0.3) {
		for (int a = 0; a < 3; ++a)
			out[a] = p[a];
		return;
	}
	/* a neighbour along one of the face's two lattice axes or the quad diagonal */
	memcpy(q2, q, sizeof q);
	int axis = f / 2, a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
	int step = kind < 0.55 ? a1 : a2;
	q2[step] += q2[step] < GRID ? 1 : -1;
	if (kind > 0.8) /* the diagonal both triangles of a quad share */
		q2[step == a1 ? a2 : a1] += q[step == a1 ? a2 : a1] < GRID ? 1 : -1;
	lattice_point(b, q2, p2);
	double s = rnd();
	for (int a = 0; a < 3; ++a)
		out[a] = p[a] + s * (p2[a] - p[a]);
}

static void rotation(double yaw, double pitch, double m[3][3])
{
	double cy = cos(yaw), sy = sin(yaw), cp = cos(pitch), sp = sin(pitch);
	double r[3][3] = {{cy, -sy * cp, sy * sp}, {sy, cy * cp, -cy * sp}, {0, sp, cp}};
	memcpy(m, r, sizeof r);
}

struct room_counts {
	size_t rays, dark, escaped;
};

/* `lit_paths` one-pass paths (primary + feeler) and `mirror_paths` paths of 6 passes on
 * mirror walls, all from random inside points aimed at edges, vertices and corners. */
static void run_box_room(struct box_room *b, size_t lit_paths, size_t mirror_paths,
                         struct room_counts *c)
{
	for (int mirror = 0; mirror < 2; ++mirror) {
		struct fx fx;
		box_room_build(&fx, b, mirror ? 0.9f : 0.0f);
		double light[3];
		inside(b, 0.5, light);
		fx_light(fx.scene, light[0], light[1], light[2], 1, 1, 1);
		fx_pack(&fx, RS_BVH_SAH);
		struct rs_trace_desc d = {.passes = mirror ? 6 : 1,
		                          .triangle_test = RS_TRIANGLE_WATERTIGHT};
		size_t paths = mirror ? mirror_paths : lit_paths;
		for (size_t k = 0; k < paths; ++k) {
			double eye[3], target[3];
			inside(b, 0.9, eye);
			surface_target(b, target);
			struct rs_ray ray = {
			    .origin = {eye[0], eye[1], eye[2]},
			    .dir = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]},
			    .tmax = INFINITY,
			    .skip_slot = RS_NO_SLOT};
			struct rs_trace_path p;
			assert_int_equal(
			    rs_trace_ray_path(fx.scene, &fx.packed, &d, &ray, &p, NULL, NULL),
			    RS_OK);
			c->rays += p.segments + p.shadow_rays;
			c->escaped += p.state == RS_RAY_ENVIRONMENT;
			/* A wall point sees the inner-half light at N.L > 0.05 for these box
			 * proportions: lit = above ambient 0.08 by at least 0.8 * 0.05. */
			if (!mirror)
				c->dark += !(p.rgb[0] > 0.08 + 0.04);
		}
		fx_free(&fx);
	}
}

static void subdivided_boxes_at_scales_and_offsets(void **state)
{
	const double scales[3] = {1e-3, 1.0, 1e3};
	const double offsets[4][3] = {
	    {0, 0, 0}, {3.7, -1.3, 12.9}, {1000, 1000, -1000}, {1e6, -1e6, 1e6}};
	struct room_counts c = {0};
	for (int s = 0; s < 3; ++s)
		for (int o = 0; o < 4; ++o) {
			struct box_room b = {
			    .half = {1.0 * scales[s], 0.75 * scales[s], 1.25 * scales[s]}};
			for (int a = 0; a < 3; ++a)
				b.offset[a] = offsets[o][a] * scales[s];
			/* axis-aligned except for the last two offsets, which are also turned;
			 * the farthest is handed in as doubles (docs/tracer.md R1, R6) */
			rotation(o >= 2 ? 0.6 : 0.0, o >= 2 ? 0.35 : 0.0, b.rot);
			b.f64 = o == 3;
			run_box_room(&b, 10000, 6000, &c);
		}
	if (c.dark || c.escaped)
		fail_msg("%zu rays: %zu lit points dark, %zu paths escaped", c.rays, c.dark,
		         c.escaped);
	print_message("subdivided boxes: %zu rays\n", c.rays);
	assert_true(c.rays >= 1000000);
}

/* A closed prism room whose cross-section is a 30-60-90 triangle: concave edges of 30, 60
 * and 90 degrees (R5's pull covers interior angles above ~27 degrees). Rays from inside
 * aimed at edge points and corners; lit and never escaping, as in the boxes. */
static void prism_room_with_acute_edges(void **state)
{
	const double xy[3][2] = {{-0.4, -0.5}, {0.6, -0.5}, {-0.4, -0.5 + 1.7320508075688772}};
	const double z0 = -0.8, z1 = 0.9;
	float pos[6][3];
	for (int k = 0; k < 6; ++k) {
		pos[k][0] = (float)xy[k % 3][0];
		pos[k][1] = (float)xy[k % 3][1];
		pos[k][2] = (float)(k < 3 ? z0 : z1);
	}
	/* wound so every face's normal points into the prism */
	const uint32_t idx[8][3] = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3},
	                            {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
	const int edges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
	                         {5, 3}, {0, 3}, {1, 4}, {2, 5}};
	struct room_counts c = {0};
	for (int mirror = 0; mirror < 2; ++mirror) {
		struct fx fx = {.scene = fx_scene()};
		struct rs_material m = {.diffuse = {0.8f, 0.8f, 0.8f},
		                        .reflectance = mirror ? 0.9f : 0.0f};
		fx_mesh(fx.scene, &pos[0][0], 6, &idx[0][0], 8, NULL, fx_material(fx.scene, m));
		fx_light(fx.scene, -0.1, 0.0, 0.05, 1, 1, 1);
		fx_pack(&fx, RS_BVH_SAH);
		struct rs_trace_desc d = {.passes = mirror ? 6 : 1};
		for (int k = 0; k < 20000; ++k) {
			/* eye: a random point of the inner third of the prism */
			double w[3] = {rnd() + 1.0, rnd() + 1.0, rnd() + 1.0},
			       sum = w[0] + w[1] + w[2];
			double eye[3] = {0, 0, z0 + (0.33 + 0.33 * rnd()) * (z1 - z0)}, target[3];
			for (int v = 0; v < 3; ++v)
				for (int a = 0; a < 2; ++a)
					eye[a] += w[v] / sum * xy[v][a];
			const int *e = edges[(int)(rnd() * 9)];
			double t = rnd() < 0.2 ? 0.0 : rnd();
			for (int a = 0; a < 3; ++a)
				target[a] = (double)pos[e[0]][a] +
				            t * ((double)pos[e[1]][a] - (double)pos[e[0]][a]);
			struct rs_ray ray = {
			    .origin = {eye[0], eye[1], eye[2]},
			    .dir = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]},
			    .tmax = INFINITY,
			    .skip_slot = RS_NO_SLOT};
			struct rs_trace_path p;
			assert_int_equal(
			    rs_trace_ray_path(fx.scene, &fx.packed, &d, &ray, &p, NULL, NULL),
			    RS_OK);
			c.rays += p.segments + p.shadow_rays;
			c.escaped += p.state == RS_RAY_ENVIRONMENT;
			/* N.L > 0.1 everywhere for this light: lit = above 0.08 + 0.8 * 0.1 */
			if (!mirror)
				c.dark += !(p.rgb[0] > 0.08 + 0.08);
		}
		fx_free(&fx);
	}
	if (c.dark || c.escaped)
		fail_msg("%zu rays: %zu lit points dark, %zu paths escaped", c.rays, c.dark,
		         c.escaped);
}

/* docs/tracer.md R2: a zero descriptor means the watertight test. From inside the closed
 * box, rays aimed at edges and vertices never miss with it; the paper's Moller-Trumbore
 * lets some through (which is why it is no longer the default). */
static void default_triangle_test_is_watertight(void **state)
{
	struct box_room b = {.half = {1.0, 0.75, 1.25}};
	rotation(0.0, 0.0, b.rot);
	struct fx fx;
	box_room_build(&fx, &b, 0.0f);
	fx_pack(&fx, RS_BVH_SAH);
	const struct rs_trace_desc zero = {0};
	size_t miss_default = 0, miss_mt = 0;
	for (int k = 0; k < 50000; ++k) {
		double eye[3], target[3];
		inside(&b, 0.9, eye);
		surface_target(&b, target);
		struct rs_ray ray = {
		    .origin = {eye[0], eye[1], eye[2]},
		    .dir = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]},
		    .tmax = INFINITY,
		    .skip_slot = RS_NO_SLOT};
		struct rs_hit h;
		miss_default += !rs_trace_closest(&fx.packed, zero.triangle_test, &ray, &h, NULL);
		miss_mt +=
		    !rs_trace_closest(&fx.packed, RS_TRIANGLE_MOLLER_TRUMBORE, &ray, &h, NULL);
	}
	assert_int_equal(miss_default, 0);
	assert_true(miss_mt > 0);
	fx_free(&fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(room_edges_are_lit_and_hold_every_path),
	    cmocka_unit_test(spawn_rule_holds_in_fp32),
	    cmocka_unit_test(subdivided_boxes_at_scales_and_offsets),
	    cmocka_unit_test(prism_room_with_acute_edges),
	    cmocka_unit_test(default_triangle_test_is_watertight),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
