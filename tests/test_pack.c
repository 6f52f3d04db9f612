/* rs_pack: texture sizes within the texture size limit at any row width, the refusals (2^24,
 * the limit), and an exact round trip of every node, triangle, normal and material field
 * through the float texels, read both as the CPU does and at the kernels' (x, y). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "contract.h"
#include "raystream/rs_pack.h"

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double rnd(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

struct fixture {
	struct rs_scene *scene;
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t node_count;
	struct rs_packed packed;
};

/* A scene of `tris` random triangles split over two meshes with different materials, packed
 * `row_items` per row (0: the default). */
/* Where the random triangles lie: scaled, shifted, or all in the plane z = shift. */
struct shape {
	double scale;
	double shift;
	bool flat;
};

static struct fixture make_shaped(size_t tris, enum rs_bvh_builder builder, uint32_t row_items,
                                  struct rs_pack_desc pd, struct shape sh)
{
	struct fixture f = {0};
	struct rs_error err;
	assert_int_equal(rs_scene_create(NULL, &f.scene, &err), RS_OK);
	uint32_t mat[2];
	struct rs_material m0 = {.diffuse = {0.5f, 0.25f, 0.125f},
	                         .specular = 0.3f,
	                         .shininess = 32.0f,
	                         .reflectance = 0.25f,
	                         .flags = RS_MATERIAL_FRESNEL};
	struct rs_material m1 = {.diffuse = {0.8f, 0.8f, 0.8f}, .transmittance = 0.9f, .ior = 1.5f};
	assert_int_equal(rs_scene_add_material(f.scene, &m0, &mat[0], NULL), RS_OK);
	assert_int_equal(rs_scene_add_material(f.scene, &m1, &mat[1], NULL), RS_OK);
	size_t half = tris / 2;
	for (int part = 0; part < 2; part++) {
		size_t n = part ? tris - half : half;
		if (n == 0)
			continue;
		float *pos = malloc(9 * n * sizeof(float));
		uint32_t *idx = malloc(3 * n * sizeof(uint32_t));
		for (size_t i = 0; i < 9 * n; i++) {
			double v = rnd() * 50.0 + (i % 3 == 0 ? 0.0 : (double)(i / 9));
			v = sh.flat && i % 3 == 2 ? 0.0 : v * sh.scale;
			pos[i] = (float)(v + sh.shift);
		}
		for (size_t i = 0; i < 3 * n; i++)
			idx[i] = (uint32_t)i;
		struct rs_mesh_desc md = {.positions = pos,
		                          .vertex_count = 3 * n,
		                          .indices = idx,
		                          .triangle_count = n,
		                          .material = mat[part]};
		assert_int_equal(rs_scene_add_mesh(f.scene, &md, NULL), RS_OK);
		free(pos);
		free(idx);
	}
	struct rs_bvh_desc d = {.builder = builder};
	size_t cap = rs_bvh_node_bound(&d, tris);
	f.nodes = malloc(cap * sizeof *f.nodes);
	f.order = malloc(tris * sizeof *f.order);
	assert_int_equal(rs_bvh_build(&d, rs_scene_positions(f.scene),
	                              rs_scene_vertex_count(f.scene), rs_scene_indices(f.scene),
	                              tris, f.nodes, cap, f.order, &f.node_count, &err),
	                 RS_OK);
	pd.row_items = row_items;
	assert_int_equal(rs_pack_layout(&pd, f.node_count, tris, 2, &f.packed, &err), RS_OK);
	assert_int_equal(rs_pack_alloc(&f.packed, &err), RS_OK);
	enum rs_status s = rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &f.packed, &err);
	if (s != RS_OK)
		fail_msg("pack: %s", err.message);
	return f;
}

static struct fixture make_rows(size_t tris, enum rs_bvh_builder builder, uint32_t row_items)
{
	/* the paper's layout: three float texels, the builder's one order */
	struct rs_pack_desc paper = {.nodes = RS_PACK_NODES_PAPER, .orders = RS_PACK_ORDERS_SINGLE};
	return make_shaped(tris, builder, row_items, paper, (struct shape){1.0, 0.0, false});
}

static struct fixture make(size_t tris, enum rs_bvh_builder builder)
{
	return make_rows(tris, builder, 0);
}

static void release(struct fixture *f)
{
	rs_pack_free(&f->packed);
	free(f->nodes);
	free(f->order);
	rs_scene_destroy(&f->scene);
}

static void texture_size_follows_the_row_width(void **state)
{
	uint32_t w, h;
	rs_pack_texture_size(1, 3, 512, &w, &h);
	assert_int_equal(w, 3);
	assert_int_equal(h, 1);
	rs_pack_texture_size(682, 3, 682, &w, &h);
	assert_int_equal(w, 2046);
	assert_int_equal(h, 1);
	rs_pack_texture_size(683, 3, 682, &w, &h);
	assert_int_equal(w, 2046);
	assert_int_equal(h, 2);
	rs_pack_texture_size(10, 3, 4, &w, &h);
	assert_int_equal(w, 12);
	assert_int_equal(h, 3);
	rs_pack_texture_size(0, 3, 682, &w, &h); /* never 0 x 0 */
	assert_int_equal(w, 3);
	assert_int_equal(h, 1);
}

/* GLES 3.0 guarantees 2048 texels a side: by default no texture may be wider or taller, even
 * for a scene far larger than Cow17 (rows used to be 1024 items = 3072 texels wide). */
static void default_layout_fits_gles3_minimum(void **state)
{
	struct rs_packed p;
	struct rs_error err;
	assert_int_equal(rs_pack_layout(NULL, 600000, 300000, 40, &p, &err), RS_OK);
	assert_int_equal(p.max_texture_size, 2048);
	assert_int_equal(p.row_items, 512); /* a power of two: kernels mask and shift */
	const struct rs_texture *t[4] = {&p.nodes, &p.triangles, &p.normals, &p.materials};
	for (int i = 0; i < 4; i++) {
		assert_true(t[i]->width <= 2048);
		assert_true(t[i]->height <= 2048);
		assert_int_equal(t[i]->width % (i == 0 ? 1 : 3), 0);
	}
	assert_int_equal(p.node_format, RS_PACK_NODES_COMPACT); /* the default: one texel */
	assert_int_equal(p.nodes.format, RS_TEXEL_RGBA32UI);
	assert_int_equal(p.nodes.width, 512);
	/* six orders of 600000 nodes would need 7032 rows: one order is packed instead */
	assert_int_equal(p.node_orders, 1);
	assert_int_equal(p.nodes.height, (600000 + 511) / 512);
	assert_int_equal(rs_pack_layout(NULL, 100000, 50000, 4, &p, &err), RS_OK);
	assert_int_equal(p.node_orders, 6);
	assert_int_equal(p.nodes.height, (6 * 100000 + 511) / 512);
	/* eight octant orders of 100000 nodes fit 1563 rows; of 150000 (2344 rows) they do not,
	 * where six (1758 rows) would: one order then, as for six */
	struct rs_pack_desc octant = {.orders = RS_PACK_ORDERS_OCTANT};
	assert_int_equal(rs_pack_layout(&octant, 100000, 50000, 4, &p, &err), RS_OK);
	assert_int_equal(p.node_orders, 8);
	assert_int_equal(p.nodes.height, (8 * 100000 + 511) / 512);
	assert_int_equal(rs_pack_layout(&octant, 150000, 50000, 4, &p, &err), RS_OK);
	assert_int_equal(p.node_orders, 1);
	assert_int_equal(rs_pack_layout(NULL, 150000, 50000, 4, &p, &err), RS_OK);
	assert_int_equal(p.node_orders, 6);
	struct rs_pack_desc odd = {.max_texture_size = 3000}; /* 1000 fit: 512 */
	assert_int_equal(rs_pack_layout(&odd, 10, 10, 1, &p, &err), RS_OK);
	assert_int_equal(p.row_items, 512);
	struct rs_pack_desc exact = {.max_texture_size = 3072}; /* 1024 fit */
	assert_int_equal(rs_pack_layout(&exact, 10, 10, 1, &p, &err), RS_OK);
	assert_int_equal(p.row_items, 1024);
	/* A larger device limit widens the rows. */
	struct rs_pack_desc big = {.max_texture_size = 16384};
	assert_int_equal(rs_pack_layout(&big, 600000, 300000, 40, &p, &err), RS_OK);
	assert_int_equal(p.row_items, 4096);
	assert_int_equal(p.nodes.width, 4096);
	struct rs_pack_desc paper = {.max_texture_size = 16384,
	                             .nodes = RS_PACK_NODES_PAPER,
	                             .orders = RS_PACK_ORDERS_SINGLE};
	assert_int_equal(rs_pack_layout(&paper, 600000, 300000, 40, &p, &err), RS_OK);
	assert_int_equal(p.nodes.width, 4096 * 3);
	assert_int_equal(p.nodes.format, RS_TEXEL_RGBA32F);
}

static void scene_over_the_texture_limit_is_refused_naming_it(void **state)
{
	struct rs_packed p;
	struct rs_error err;
	/* 512 x 2048 items fit exactly; one more triangle does not. */
	assert_int_equal(rs_pack_layout(NULL, 10, 512u * 2048u, 1, &p, &err), RS_OK);
	assert_int_equal(p.triangles.height, 2048);
	assert_int_equal(rs_pack_layout(NULL, 10, 512u * 2048u + 1u, 1, &p, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "texture size limit of 2048"));
	assert_non_null(strstr(err.message, "triangles"));
	assert_int_equal(p.triangle_count, 0); /* nothing half laid out */
	struct rs_pack_desc small = {.max_texture_size = 64};
	assert_int_equal(rs_pack_layout(&small, 21u * 64u + 1u, 5, 1, &p, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "nodes"));
	assert_non_null(strstr(err.message, "texture size limit of 64"));
}

static void impossible_row_widths_are_invalid(void **state)
{
	struct rs_packed p;
	struct rs_error err;
	struct rs_pack_desc tiny = {.max_texture_size = 2};
	assert_int_equal(rs_pack_layout(&tiny, 1, 1, 1, &p, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "2 texels"));
	struct rs_pack_desc wide = {.row_items = 683};
	assert_int_equal(rs_pack_layout(&wide, 1, 1, 1, &p, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "limit of 2048"));
	struct rs_pack_desc one = {.max_texture_size = 3};
	assert_int_equal(rs_pack_layout(&one, 3, 3, 3, &p, &err), RS_OK);
	assert_int_equal(p.row_items, 1);
	assert_int_equal(p.nodes.width, 1);
	assert_int_equal(p.nodes.height, 3);
	struct rs_pack_desc bad = {.nodes = (enum rs_pack_nodes)7};
	assert_int_equal(rs_pack_layout(&bad, 3, 3, 3, &p, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "node format"));
	struct rs_pack_desc bad_orders = {.orders = (enum rs_pack_orders)9};
	assert_int_equal(rs_pack_layout(&bad_orders, 3, 3, 3, &p, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "node orders"));
}

static void layout_refuses_2_pow_24(void **state)
{
	struct rs_packed p;
	struct rs_error err;
	struct rs_pack_desc big = {.max_texture_size = 16384};
	assert_int_equal(rs_pack_layout(&big, RS_PACK_MAX_ITEMS, 1, 1, &p, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "2^24"));
	assert_int_equal(rs_pack_layout(&big, 1, RS_PACK_MAX_ITEMS, 1, &p, &err), RS_ERR_LIMIT);
	assert_int_equal(
	    rs_pack_layout(&big, RS_PACK_MAX_ITEMS - 1, RS_PACK_MAX_ITEMS - 1, 1, &p, &err), RS_OK);
	assert_int_equal(p.nodes.height, (RS_PACK_MAX_ITEMS - 1 + 4095) / 4096);
}

/* Every field read back through rs_pack_texel() equals the source exactly: indices are
 * below 2^24, so float conversion is exact (no tolerance). */
/* The texel the kernels fetch at rs_pack_texel_xy() is the one rs_pack_texel() returns. */
static void assert_xy_is_linear(const struct rs_texture *t, uint32_t row_items,
                                uint32_t texels_per_item, uint32_t items)
{
	for (uint32_t k = 0; k < items; k++) {
		for (uint32_t j = 0; j < texels_per_item; j++) {
			uint32_t x, y;
			rs_pack_texel_xy(row_items, texels_per_item, k, j, &x, &y);
			assert_true(x < t->width && y < t->height);
			assert_ptr_equal(t->texels + ((size_t)y * t->width + x) * 4u,
			                 rs_pack_texel(t, texels_per_item, k, j));
		}
	}
}

/* 1 when slot s ends a leaf (the triangle texture's last flag), else 0. */
static float last_of_leaf(const struct fixture *f, uint32_t s)
{
	for (size_t i = 0; i < f->node_count; i++)
		if (f->nodes[i].level == 0 && f->nodes[i].count > 0 &&
		    f->nodes[i].first + f->nodes[i].count - 1 == s)
			return 1.0f;
	return 0.0f;
}

static void round_trip_rows(enum rs_bvh_builder builder, size_t tris, uint32_t row_items)
{
	struct fixture f = make_rows(tris, builder, row_items);
	const struct rs_packed *p = &f.packed;
	assert_int_equal(rs_pack_check(p, NULL), RS_OK);
	assert_xy_is_linear(&p->nodes, p->row_items, RS_PACK_NODE_TEXELS, p->node_count);
	assert_xy_is_linear(&p->triangles, p->row_items, RS_PACK_TRIANGLE_TEXELS,
	                    p->triangle_count);
	assert_xy_is_linear(&p->normals, p->row_items, RS_PACK_NORMAL_TEXELS, p->triangle_count);
	assert_xy_is_linear(&p->materials, p->row_items, RS_PACK_MATERIAL_TEXELS,
	                    p->material_count);
	assert_int_equal(p->node_count, f.node_count);
	for (uint32_t i = 0; i < f.node_count; i++) {
		const struct rs_bvh_node *n = &f.nodes[i];
		const float *t0 = rs_pack_texel(&p->nodes, RS_PACK_NODE_TEXELS, i, 0);
		const float *t1 = rs_pack_texel(&p->nodes, RS_PACK_NODE_TEXELS, i, 1);
		const float *t2 = rs_pack_texel(&p->nodes, RS_PACK_NODE_TEXELS, i, 2);
		/* tight bounds of the packed vertices of every leaf in the subtree */
		float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
		for (uint32_t j = i; j < n->escape; j++)
			for (uint32_t s = f.nodes[j].first;
			     f.nodes[j].level == 0 && s < f.nodes[j].first + f.nodes[j].count; s++)
				for (uint32_t k = 0; k < 3; k++)
					for (int a = 0; a < 3; a++) {
						float v =
						    rs_pack_texel(&p->triangles,
						                  RS_PACK_TRIANGLE_TEXELS, s, k)[a];
						lo[a] = fminf(lo[a], v);
						hi[a] = fmaxf(hi[a], v);
					}
		assert_memory_equal(t0, lo, sizeof lo);
		assert_memory_equal(t1, hi, sizeof hi);
		assert_int_equal((uint32_t)t0[3], n->escape);
		assert_int_equal((uint32_t)t1[3], n->level);
		assert_int_equal((uint32_t)t2[0], n->first);
		assert_int_equal((uint32_t)t2[1], n->count);
		assert_int_equal((uint32_t)t2[2], n->order);
		assert_true(t2[3] == 0.0f);
	}
	const double *pos = rs_scene_positions_f64(f.scene);
	const float *nrm = rs_scene_normals(f.scene);
	struct rs_bounds b;
	rs_scene_bounds(f.scene, &b);
	for (int a = 0; a < 3; a++)
		assert_true(p->origin[a] == 0.5 * (b.lo[a] + b.hi[a]));
	const uint32_t *idx = rs_scene_indices(f.scene);
	const uint32_t *mat = rs_scene_triangle_materials(f.scene);
	for (uint32_t s = 0; s < p->triangle_count; s++) {
		uint32_t tri = f.order[s];
		for (uint32_t k = 0; k < 3; k++) {
			const float *t =
			    rs_pack_texel(&p->triangles, RS_PACK_TRIANGLE_TEXELS, s, k);
			const float *nn = rs_pack_texel(&p->normals, RS_PACK_NORMAL_TEXELS, s, k);
			/* relative to the centre, subtracted in double, then rounded (R1) */
			for (int a = 0; a < 3; a++)
				assert_true(t[a] ==
				            (float)(pos[3 * idx[3 * tri + k] + a] - p->origin[a]));
			assert_memory_equal(nn, nrm + 3 * idx[3 * tri + k], 3 * sizeof(float));
			float w = k == 0   ? (float)tri
			          : k == 1 ? (float)mat[tri]
			                   : last_of_leaf(&f, s);
			assert_true(t[3] == w);
			assert_true(nn[3] == 0.0f);
		}
	}
	release(&f);
}

static void round_trip(enum rs_bvh_builder builder, size_t tris)
{
	round_trip_rows(builder, tris, 0);
}

static void round_trip_sah(void **state)
{
	round_trip(RS_BVH_SAH, 3000); /* > 512 items: crosses texture rows */
}
static void round_trip_at_several_row_widths(void **state)
{
	const uint32_t rows[] = {1, 2, 7, 64, 500};
	for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++)
		round_trip_rows(RS_BVH_SAH, 300, rows[i]);
}
static void round_trip_paper(void **state)
{
	round_trip(RS_BVH_PAPER, 1500);
}
static void round_trip_linear_and_none(void **state)
{
	round_trip(RS_BVH_LINEAR, 9000);
	round_trip(RS_BVH_NONE, 5);
}

/* A compact bound is origin + q * step exactly, q a 16-bit integer, step a power of two. */
static void assert_on_grid(float v, float origin, float step)
{
	double q = ((double)v - origin) / step;
	assert_true(q == floor(q) && q >= 0.0 && q <= RS_PACK_GRID_STEPS);
	int e;
	assert_true(frexp(step, &e) == 0.5);
	assert_true((float)((double)origin + q * step) == v);
}

/* Compact nodes against the paper's exact ones for the same BVH: every box holds the tight
 * box and is at most one grid step larger on each side, bounds sit exactly on the grid, and
 * the topology (escape, leaf, first, count) decodes equal. */
static void compact_matches(enum rs_bvh_builder builder, size_t tris, struct shape sh)
{
	uint64_t seed = rng_state; /* the same triangles in both */
	struct fixture c = make_shaped(tris, builder, 0, (struct rs_pack_desc){0}, sh);
	rng_state = seed;
	struct fixture p =
	    make_shaped(tris, builder, 0, (struct rs_pack_desc){.nodes = RS_PACK_NODES_PAPER}, sh);
	assert_int_equal(c.node_count, p.node_count);
	assert_int_equal(c.packed.node_orders, 6);
	assert_int_equal(rs_pack_check(&c.packed, NULL), RS_OK);
	const float *origin = c.packed.node_grid_origin, *step = c.packed.node_grid_step;
	for (uint32_t i = 0; i < 6 * c.node_count; i++) {
		struct rs_pack_node nc, np;
		rs_pack_read_node(&c.packed, i, &nc);
		rs_pack_read_node(&p.packed, i, &np);
		bool empty = np.lo[0] > np.hi[0];
		for (int a = 0; a < 3 && !empty; a++) {
			assert_true(nc.lo[a] <= np.lo[a] && nc.hi[a] >= np.hi[a]);
			assert_true((double)np.lo[a] - nc.lo[a] <= step[a]);
			assert_true((double)nc.hi[a] - np.hi[a] <= step[a]);
			assert_on_grid(nc.lo[a], origin[a], step[a]);
			assert_on_grid(nc.hi[a], origin[a], step[a]);
		}
		if (empty)
			assert_true(nc.lo[0] > nc.hi[0]); /* an empty box stays empty */
		assert_int_equal(nc.escape, np.escape);
		assert_int_equal(nc.leaf, np.leaf && np.count > 0);
		if (nc.leaf) {
			assert_int_equal(nc.first, np.first);
			assert_int_equal(nc.count, np.count);
		}
	}
	release(&c);
	release(&p);
}

static void compact_nodes_hold_the_tight_boxes(void **state)
{
	struct shape plain = {1.0, 0.0, false};
	compact_matches(RS_BVH_SAH, 3000, plain); /* > 512 items: crosses texture rows */
	compact_matches(RS_BVH_PAPER, 1500, plain);
	compact_matches(RS_BVH_LINEAR, 900, plain);
	compact_matches(RS_BVH_NONE, 5, plain);
}

/* The grid stays exact and conservative far from the origin, at tiny and huge scales, and
 * for a scene with no extent along one axis. */
static void compact_nodes_survive_hard_scales(void **state)
{
	const struct shape shapes[] = {{1.0, 1.0e6, false},       {1.0e-30, 0.0, false},
	                               {1.0e-30, 1.0e-25, false}, {1.0e30, -1.0e33, false},
	                               {1.0, 0.0, true},          {1.0, 123.456, true}};
	for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
		compact_matches(RS_BVH_SAH, 400, shapes[i]);
}

/* Wide nodes: walking the tree from the root reaches every triangle slot exactly once, each
 * leaf's vertices lie inside every child box on its path (conservative), every bound is
 * exactly grid_origin + Q * step with Q an integer below 2^18, and a child's index is above
 * its parent's. */
static void wide_matches(enum rs_bvh_builder builder, size_t tris, struct shape sh)
{
	struct fixture f =
	    make_shaped(tris, builder, 0, (struct rs_pack_desc){.nodes = RS_PACK_NODES_WIDE4}, sh);
	assert_int_equal(f.packed.node_orders, 1);
	assert_int_equal(f.packed.nodes.format, RS_TEXEL_RGBA32UI);
	assert_int_equal(rs_pack_check(&f.packed, NULL), RS_OK);
	const float *origin = f.packed.node_grid_origin, *step = f.packed.node_grid_step;
	struct item {
		uint32_t node;
		float lo[3], hi[3];
	} *stack = malloc((f.packed.node_count + 1) * sizeof *stack);
	unsigned char *seen = calloc(tris + 1, 1);
	size_t sp = 0;
	stack[sp++] = (struct item){0, {-FLT_MAX, -FLT_MAX, -FLT_MAX}, {FLT_MAX, FLT_MAX, FLT_MAX}};
	while (sp) {
		struct item it = stack[--sp];
		struct rs_pack_wide w;
		rs_pack_read_wide(&f.packed, it.node, &w);
		assert_true(w.children >= 1 && w.children <= RS_PACK_WIDE_CHILDREN);
		for (uint32_t c = 0; c < w.children; c++) {
			struct item in = it;
			for (int a = 0; a < 3; a++) {
				assert_true(w.qlo[c][a] >= 0 && w.qhi[c][a] < (1 << 18));
				assert_true(w.lo[c][a] == (float)((double)origin[a] +
				                                  (double)w.qlo[c][a] * step[a]));
				assert_true(w.hi[c][a] == (float)((double)origin[a] +
				                                  (double)w.qhi[c][a] * step[a]));
				in.lo[a] = fmaxf(in.lo[a], w.lo[c][a]);
				in.hi[a] = fminf(in.hi[a], w.hi[c][a]);
			}
			uint32_t child = w.child[c];
			if (!(child & RS_PACK_LEAF_BIT)) {
				assert_true(child > it.node && child < f.packed.node_count);
				in.node = child;
				stack[sp++] = in;
				continue;
			}
			for (uint32_t s = child & ~RS_PACK_LEAF_BIT; s < tris; s++) {
				assert_int_equal(seen[s], 0);
				seen[s] = 1;
				for (uint32_t j = 0; j < 3; j++) {
					const float *v = rs_pack_texel(
					    &f.packed.triangles, RS_PACK_TRIANGLE_TEXELS, s, j);
					for (int a = 0; a < 3; a++)
						assert_true(v[a] >= in.lo[a] && v[a] <= in.hi[a]);
				}
				if (rs_pack_texel(&f.packed.triangles, RS_PACK_TRIANGLE_TEXELS, s,
				                  2)[3] != 0.0f)
					break;
			}
		}
	}
	for (size_t s = 0; s < tris; s++)
		assert_int_equal(seen[s], 1);
	free(stack);
	free(seen);
	release(&f);
}

static void wide_nodes_hold_every_triangle(void **state)
{
	const struct shape shapes[] = {{1.0, 0.0, false},        {1.0, 1.0e6, false},
	                               {1.0e-30, 0.0, false},    {1.0e-30, 1.0e-25, false},
	                               {1.0e30, -1.0e33, false}, {1.0, 0.0, true},
	                               {1.0, 123.456, true}};
	for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
		wide_matches(RS_BVH_SAH, 3000, shapes[i]); /* > 512 items: crosses texture rows */
	wide_matches(RS_BVH_PAPER, 1500, shapes[0]);
	wide_matches(RS_BVH_LINEAR, 900, shapes[0]);
	wide_matches(RS_BVH_NONE, 5, shapes[0]);
	wide_matches(RS_BVH_SAH, 1, shapes[0]);
}

/* A tree whose wide walk could need more stack entries than the kernels hold (a caterpillar:
 * every interior node has a leaf child) is refused at packing, naming the stack, never
 * walked with an overflowing stack. */
static void wide_refuses_a_tree_deeper_than_the_stack(void **state)
{
	const uint32_t leaves = 3 * RS_PACK_WIDE_STACK;
	struct fixture f = make_shaped(leaves, RS_BVH_SAH, 0, (struct rs_pack_desc){0},
	                               (struct shape){1.0, 0.0, false});
	uint32_t n = 2 * leaves - 1;
	struct rs_bvh_node *cat = calloc(n, sizeof *cat);
	for (uint32_t i = 0; i < leaves; i++) {
		uint32_t leaf = i + 1 < leaves ? 2 * i + 1 : 2 * i;
		cat[leaf] = (struct rs_bvh_node){.escape = leaf + 1, .first = i, .count = 1};
		if (i + 1 < leaves)
			cat[2 * i] = (struct rs_bvh_node){.level = 1, .escape = n};
		f.order[i] = i;
	}
	struct rs_packed wide;
	struct rs_error err;
	struct rs_pack_desc pd = {.nodes = RS_PACK_NODES_WIDE4};
	assert_int_equal(rs_pack_layout(&pd, n, leaves, 2, &wide, &err), RS_OK);
	assert_int_equal(rs_pack_alloc(&wide, &err), RS_OK);
	assert_int_equal(rs_pack_scene(f.scene, cat, n, f.order, &wide, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "stack"));
	/* compact nodes take the same tree */
	rs_pack_free(&wide);
	pd.nodes = RS_PACK_NODES_COMPACT;
	assert_int_equal(rs_pack_layout(&pd, n, leaves, 2, &wide, &err), RS_OK);
	assert_int_equal(rs_pack_alloc(&wide, &err), RS_OK);
	assert_int_equal(rs_pack_scene(f.scene, cat, n, f.order, &wide, &err), RS_OK);
	rs_pack_free(&wide);
	free(cat);
	release(&f);
}

/* The compact format keeps no escape for a leaf: a tree whose leaf escapes elsewhere cannot
 * be stored and is refused, naming the leaf. */
static void compact_refuses_a_leaf_that_escapes_far(void **state)
{
	struct fixture f = make_shaped(20, RS_BVH_LINEAR, 0,
	                               (struct rs_pack_desc){.orders = RS_PACK_ORDERS_SINGLE},
	                               (struct shape){1.0, 0.0, false});
	struct rs_error err;
	assert_true(f.node_count >= 2 && f.nodes[0].level == 0);
	f.nodes[0].escape = 2;
	assert_int_equal(rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &f.packed, &err),
	                 RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "leaf 0"));
	release(&f);
}

/* Visiting rule of one order: asserts that node order d visits child c0 before c1 (both
 * boxes non-empty); returns the axis it decided by. */
typedef int (*first_child_rule)(uint32_t d, const struct rs_pack_node *c0,
                                const struct rs_pack_node *c1);

/* Each of the node orders of `p` (built from `nodes`) is a pre-order of the same tree (subtrees
 * nest, the same leaves) whose interior nodes obey `rule`; returns the axes the rule decided
 * by (bit a for axis a) and whether any node's children came in descending order. */
static uint32_t check_orders(const struct rs_packed *p, const struct rs_bvh_node *nodes,
                             first_child_rule rule, bool *out_descending)
{
	uint32_t n = p->node_count, axes = 0;
	uint64_t leaves = 0, slots = 0;
	for (uint32_t i = 0; i < n; i++)
		if (nodes[i].level == 0) {
			leaves += nodes[i].first * 2654435761u + 1u;
			slots += nodes[i].count;
		}
	*out_descending = false;
	for (uint32_t d = 0; d < p->node_orders; d++) {
		uint64_t seen = 0, seen_slots = 0;
		for (uint32_t k = d * n; k < (d + 1) * n; k++) {
			struct rs_pack_node a;
			rs_pack_read_node(p, k, &a);
			assert_true(a.escape > k && a.escape <= (d + 1) * n);
			if (a.leaf || a.escape == k + 1) {
				seen += a.first * 2654435761u + 1u;
				seen_slots += a.count;
				continue;
			}
			struct rs_pack_node c0, c1;
			rs_pack_read_node(p, k + 1, &c0);
			assert_true(c0.escape < a.escape);
			rs_pack_read_node(p, c0.escape, &c1);
			assert_int_equal(c1.escape, a.escape); /* two children fill the subtree */
			if (!(c0.lo[0] <= c0.hi[0] && c1.lo[0] <= c1.hi[0]))
				continue;
			int axis = rule(d, &c0, &c1);
			axes |= 1u << axis;
			*out_descending |= c0.lo[axis] + c0.hi[axis] > c1.lo[axis] + c1.hi[axis];
		}
		assert_true(seen == leaves && seen_slots == slots);
	}
	return axes;
}

/* Six orders: the child whose box centre comes first along d's axis, descending for odd d. */
static int directional_rule(uint32_t d, const struct rs_pack_node *c0,
                            const struct rs_pack_node *c1)
{
	int axis = (int)d / 2;
	float m0 = c0->lo[axis] + c0->hi[axis], m1 = c1->lo[axis] + c1->hi[axis];
	assert_true(d % 2 ? m0 >= m1 : m0 <= m1);
	return axis;
}

/* Eight orders: on the axis the two centres are farthest apart (ties to the lower axis), the
 * child whose centre comes first, descending where octant d's bit for that axis is set. */
static int octant_rule(uint32_t d, const struct rs_pack_node *c0, const struct rs_pack_node *c1)
{
	int axis = 0;
	float best = -1.0f;
	for (int x = 0; x < 3; x++) {
		float gap = fabsf(c1->lo[x] + c1->hi[x] - c0->lo[x] - c0->hi[x]);
		if (gap > best) {
			best = gap;
			axis = x;
		}
	}
	float m0 = c0->lo[axis] + c0->hi[axis], m1 = c1->lo[axis] + c1->hi[axis];
	assert_true(d >> axis & 1u ? m0 >= m1 : m0 <= m1);
	return axis;
}

/* The six directional orders (rs_pack_node_order() picks the one of a direction's major axis
 * and sign) and the eight octant orders (rs_pack_node_order_of() picks the octant of its
 * signs), each a pre-order of the same tree visiting the near child first by its rule. */
static void orders_visit_near_children_first(enum rs_bvh_builder builder)
{
	bool descending;
	struct fixture f =
	    make_shaped(2000, builder, 0, (struct rs_pack_desc){.nodes = RS_PACK_NODES_PAPER},
	                (struct shape){1.0, 0.0, false});
	assert_int_equal(f.packed.node_orders, 6);
	uint32_t axes = check_orders(&f.packed, f.nodes, directional_rule, &descending);
	assert_true(builder == RS_BVH_LINEAR || (axes == 7u && descending));
	const double dirs[8][3] = {{1, 0.5, 0.5},  {-1, 0.9, 0},      {0.1, -2, 1},   {-0.1, -2, 1},
	                           {0.3, 0.3, -1}, {-0.5, 0.5, -0.7}, {2, -1e-9, -1}, {-1, -1, -1}};
	const uint32_t major[8] = {0, 1, 3, 3, 5, 5, 0, 1};
	for (uint32_t d = 0; d < 8; d++) {
		assert_int_equal(rs_pack_node_order(dirs[d]), major[d]);
		assert_int_equal(rs_pack_node_order_of(6, dirs[d]), major[d]);
		assert_int_equal(rs_pack_node_order_of(8, dirs[d]), d);
		assert_int_equal(rs_pack_node_order_of(1, dirs[d]), 0);
	}
	release(&f);
	f = make_shaped(
	    2000, builder, 0,
	    (struct rs_pack_desc){.nodes = RS_PACK_NODES_PAPER, .orders = RS_PACK_ORDERS_OCTANT},
	    (struct shape){1.0, 0.0, false});
	assert_int_equal(f.packed.node_orders, 8);
	axes = check_orders(&f.packed, f.nodes, octant_rule, &descending);
	/* a flat list of leaves (LINEAR) has no interior node to check */
	assert_true(builder == RS_BVH_LINEAR || (axes == 7u && descending));
	release(&f);
}

static void node_orders_are_preorders_near_child_first(void **state)
{
	orders_visit_near_children_first(RS_BVH_SAH);
	orders_visit_near_children_first(RS_BVH_PAPER);
	orders_visit_near_children_first(RS_BVH_LINEAR);
}

static void materials_resolve_defaults(void **state)
{
	struct fixture f = make(10, RS_BVH_SAH);
	const float *a0 = rs_pack_texel(&f.packed.materials, RS_PACK_MATERIAL_TEXELS, 0, 0);
	const float *a1 = rs_pack_texel(&f.packed.materials, RS_PACK_MATERIAL_TEXELS, 0, 1);
	const float *a2 = rs_pack_texel(&f.packed.materials, RS_PACK_MATERIAL_TEXELS, 0, 2);
	const float *b1 = rs_pack_texel(&f.packed.materials, RS_PACK_MATERIAL_TEXELS, 1, 1);
	assert_true(a0[0] == 0.5f && a0[1] == 0.25f && a0[2] == 0.125f && a0[3] == 0.3f);
	assert_true(a1[0] == 32.0f && a1[1] == 0.25f && a1[2] == 0.0f && a1[3] == 1.0f);
	assert_true(a2[0] == (float)RS_MATERIAL_FRESNEL);
	assert_true(b1[0] == 1.0f && b1[2] == 0.9f && b1[3] == 1.5f); /* shininess 0 -> 1 */
	release(&f);
}

static void unused_texels_are_zero(void **state)
{
	/* 1500 triangles at 512 a row: the third texture row holds items 1024..1499; items
	 * 1500..1535 of that row are unused and must come back zeroed even over a
	 * garbage-filled buffer. */
	struct fixture f = make(1500, RS_BVH_PAPER);
	struct rs_texture *t = &f.packed.triangles;
	memset(t->texels, 0x7f, (size_t)t->width * t->height * 4 * sizeof(float));
	assert_int_equal(rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &f.packed, NULL),
	                 RS_OK);
	for (uint32_t item = 1500; item < 3 * 512; item++)
		for (uint32_t j = 0; j < RS_PACK_TRIANGLE_TEXELS; j++)
			for (int c = 0; c < 4; c++)
				assert_true(rs_pack_texel(t, RS_PACK_TRIANGLE_TEXELS, item, j)[c] ==
				            0.0f);
	release(&f);
}

static void pack_rejects_mismatch(void **state)
{
	struct fixture f = make(20, RS_BVH_SAH);
	struct rs_error err;
	struct rs_packed wrong;
	assert_int_equal(rs_pack_layout(NULL, f.node_count + 1, 20, 2, &wrong, &err), RS_OK);
	wrong.nodes = f.packed.nodes;
	wrong.triangles = f.packed.triangles;
	wrong.normals = f.packed.normals;
	wrong.materials = f.packed.materials;
	assert_int_equal(rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &wrong, &err),
	                 RS_ERR_INVALID);
	/* textures laid out for another row width */
	struct rs_packed narrow = f.packed;
	narrow.row_items = 2;
	assert_int_equal(rs_pack_check(&narrow, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "2 items per row"));
	assert_int_equal(rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &narrow, &err),
	                 RS_ERR_INVALID);
	f.order[3] = 99;
	assert_int_equal(rs_pack_scene(f.scene, f.nodes, f.node_count, f.order, &f.packed, &err),
	                 RS_ERR_BAD_DATA);
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_pack_scene(NULL, f.nodes, f.node_count, f.order, &f.packed, &err));
	release(&f);
}

static void free_accepts_zeroed(void **state)
{
	struct rs_packed p = {0};
	rs_pack_free(&p);
	rs_pack_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(texture_size_follows_the_row_width),
	    cmocka_unit_test(default_layout_fits_gles3_minimum),
	    cmocka_unit_test(scene_over_the_texture_limit_is_refused_naming_it),
	    cmocka_unit_test(impossible_row_widths_are_invalid),
	    cmocka_unit_test(layout_refuses_2_pow_24),
	    cmocka_unit_test(round_trip_sah),
	    cmocka_unit_test(round_trip_at_several_row_widths),
	    cmocka_unit_test(round_trip_paper),
	    cmocka_unit_test(round_trip_linear_and_none),
	    cmocka_unit_test(compact_nodes_hold_the_tight_boxes),
	    cmocka_unit_test(compact_nodes_survive_hard_scales),
	    cmocka_unit_test(wide_nodes_hold_every_triangle),
	    cmocka_unit_test(wide_refuses_a_tree_deeper_than_the_stack),
	    cmocka_unit_test(compact_refuses_a_leaf_that_escapes_far),
	    cmocka_unit_test(node_orders_are_preorders_near_child_first),
	    cmocka_unit_test(materials_resolve_defaults),
	    cmocka_unit_test(unused_texels_are_zero),
	    cmocka_unit_test(pack_rejects_mismatch),
	    cmocka_unit_test(free_accepts_zeroed),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
