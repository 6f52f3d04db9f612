/* The per-frame plan: which programs run, in which order, reading and writing which
 * targets. Decided once per set_scene (the frame's plan and the capture frames'), then run
 * by gles_frame.c. The chain is chosen here and only here:
 *   fused     one trace pass per segment (the first one makes its own primary rays, or
 *             takes them from the visibility pass); only without counters (its fourth target
 *             carries the hit). With cube maps only the first pass traces: the rays it
 *             leaves read the maps at its end (step.mapped), so the frame is that one pass
 *             (the separate chain's second pass traces nothing, yet costs two full-screen
 *             kernels, docs/benchmarks.md). Its last pass can write the frame's RGBA8
 *             colour in place of the display pass (rs_gles_step.display; whether a frame
 *             does is gles_render's choice). With compute kernels (rs_render_desc.kernels)
 *             its passes are the same kernels as compute programs, and the last one never
 *             displays: its outputs are RGBA32F images, whose format a program fixes;
 *   separate  ray generation, then per segment intersect (or the raster visibility and
 *             resolve passes) and shade;
 *   paper     as separate, with shade split into the paper's environment, shading and
 *             next-ray kernels, each writing only the state it changes;
 *   hits only (rs_render_desc.hits_only, whatever the chain) one primary.glsl pass: the
 *             camera ray made in the kernel, its closest hit into the hit texture (pass 0's,
 *             the frame's depth and triangle ids), no ray texture, nothing shaded; with
 *             rasterized primaries the visibility and resolve passes instead.
 * Whether an instanced scene is walked in two levels is decided here too
 * (rs_gles_two_level), after lib/render's rs_render_two_level.
 * The state lives in ping-pong pairs: a pass reads one texture of each pair it uses and
 * writes the other, which then becomes the current one. */
#include <string.h>

#include "gles_internal.h"

/* Which texture of each ping-pong pair holds the current per-pixel state. */
struct cursor {
	int st[ST_COUNT];
	int cnt;
};

static uint8_t state_ref(int k, int s)
{
	return (uint8_t)(REF_STATE + 3 * k + s);
}

/* The current state as a step's inputs (u_orig, u_dir, u_acc, u_cnt), and `hit`. */
static void inputs(const struct cursor *c, uint8_t hit, struct rs_gles_step *s)
{
	for (int k = 0; k < ST_COUNT; ++k)
		s->in[k] = state_ref(c->st[k], k);
	s->in[3] = (uint8_t)(REF_CNT + c->cnt);
	s->in[4] = hit;
}

/* State pair `s` moves to its other texture, which the step writes. */
static uint8_t flip(struct cursor *c, int s)
{
	c->st[s] = 1 - c->st[s];
	return state_ref(c->st[s], s);
}

static uint8_t flip_cnt(struct cursor *c)
{
	c->cnt = 1 - c->cnt;
	return (uint8_t)(REF_CNT + c->cnt);
}

static struct rs_gles_step *add(struct rs_gles_plan *plan, const char *name, int prog, uint8_t bind,
                                uint32_t pass)
{
	struct rs_gles_step *s = &plan->steps[plan->count++];
	memset(s, 0, sizeof *s);
	s->name = name;
	s->prog = (uint8_t)prog;
	s->bind = bind;
	s->pass = pass;
	return s;
}

/* The visibility pass of rasterized primaries, into the second hit texture (free until the
 * second pass reads it). */
static void raster_step(struct rs_gles_plan *plan, uint32_t pass)
{
	struct rs_gles_step *v = add(plan, "raster", PROG_RASTER, BIND_SCENE | BIND_CAMERA, pass);
	v->raster = true;
	v->out[0] = REF_HIT + 1;
	v->n_out = 1;
}

/* The fused chain's pass: intersection and path step in one kernel, a fragment or (compute)
 * a compute program. */
static void fused_pass(struct rs_gles_plan *plan, struct cursor *c, uint32_t pass, bool last,
                       bool rasterized, uint8_t envmap, bool mapped, bool compute)
{
	if (rasterized)
		raster_step(plan, pass);
	int prog = pass > 0 ? PROG_FUSED : rasterized ? PROG_FUSED_RASTER : PROG_FUSED_FIRST;
	if (compute)
		prog = pass > 0     ? PROG_FUSED_COMPUTE
		       : rasterized ? PROG_FUSED_RASTER_COMPUTE
		                    : PROG_FUSED_FIRST_COMPUTE;
	uint8_t bind = BIND_SCENE;
	bind |= pass == 0 ? BIND_CAMERA | BIND_NEAR | (rasterized ? BIND_VIS : 0) : BIND_STATE;
	/* with cube maps bound on every pass: a samplerCube left on a 2D texture's unit fails */
	bind |= envmap;
	struct rs_gles_step *s = add(plan, compute ? "trace compute" : "trace", prog, bind, pass);
	s->mapped = mapped;
	inputs(c, REF_NONE, s);
	for (int k = 0; k < ST_COUNT; ++k)
		s->out[k] = flip(c, k);
	s->out[3] = (uint8_t)(REF_HIT + (pass == 0 ? 0 : 1));
	s->n_out = 4;
	/* Nothing reads the last pass's rays, nor its hits after pass 0's (the frame's depth):
	 * not stored (3-5 % of a Cow17 2-pass frame, llvmpipe). */
	if (last) {
		s->out[ST_ORIG] = s->out[ST_DIR] = REF_NONE;
		if (pass > 0)
			s->out[3] = REF_NONE;
		/* Displayed (a frame asked for RGBA8 bytes only, gles_renderer.c): the free
		 * target 0 takes them, and the colour nothing reads after it is not stored
		 * (the display pass and a float write a pixel fewer: docs/benchmarks.md, "The
		 * display pass fused into the last trace pass"). */
		s->display = !compute;
		memcpy(s->shown, s->out, sizeof s->shown);
		s->shown[0] = REF_COLOR;
		s->shown[ST_ACC] = REF_NONE;
	}
}

/* The separate and paper chains' segment after its hits are in `hit`. */
static void path_step(struct rs_gles_plan *plan, struct cursor *c, uint32_t pass, uint8_t hit,
                      bool paper, uint8_t envmap)
{
	uint8_t bind = BIND_SCENE | BIND_STATE | BIND_HIT | envmap;
	bool counters = plan->counters;
	if (!paper) {
		struct rs_gles_step *s = add(plan, "shade", PROG_SHADE, bind, pass);
		inputs(c, hit, s);
		for (int k = 0; k < ST_COUNT; ++k)
			s->out[k] = flip(c, k);
		s->out[3] = counters ? flip_cnt(c) : REF_NONE;
		s->n_out = counters ? 4 : 3;
		return;
	}
	struct rs_gles_step *s = add(plan, "environment", PROG_ENVIRONMENT, bind, pass);
	inputs(c, hit, s);
	s->out[0] = flip(c, ST_ACC);
	s->n_out = 1;
	s = add(plan, "shading", PROG_SHADING, bind, pass);
	inputs(c, hit, s);
	s->out[0] = flip(c, ST_ACC);
	s->out[1] = counters ? flip_cnt(c) : REF_NONE;
	s->n_out = counters ? 2 : 1;
	s = add(plan, "next ray", PROG_NEXTRAY, bind, pass);
	inputs(c, hit, s);
	s->out[0] = flip(c, ST_ORIG);
	s->out[1] = flip(c, ST_DIR);
	s->out[2] = flip(c, ST_ACC);
	s->n_out = 3;
}

/* The primary hits only: into REF_HIT (readback's depth and triangle ids). result_acc and
 * result_cnt stay REF_NONE: there is no colour (lib/render refuses to be asked for one). */
static void hits_only(struct rs_gles_plan *plan, bool rasterized)
{
	if (rasterized)
		raster_step(plan, 0);
	struct rs_gles_step *s =
	    rasterized
	        ? add(plan, "resolve", PROG_RESOLVE, BIND_SCENE | BIND_CAMERA | BIND_VIS, 0)
	        : add(plan, "primary", PROG_PRIMARY, BIND_SCENE | BIND_CAMERA | BIND_NEAR, 0);
	s->out[0] = REF_HIT;
	s->n_out = 1;
}

enum rs_status rs_gles_two_level(const struct rs_render_desc *desc, const struct rs_scene *scene,
                                 bool moving, uint64_t max_texels, bool *out_two_level,
                                 struct rs_error *err)
{
	enum rs_status st = rs_render_two_level(desc, scene, out_two_level, err);
	if (st != RS_OK || !*out_two_level)
		return st;
	/* The two-level walk is a traced ray's: raster passes (primary visibility, shadow
	 * maps) draw the triangle texture as world-space triangles, and the cube-map captures'
	 * object ids index it by slot; those render the flattened scene. Every chain works: a
	 * hit texel's w is the scene triangle id, which shading decodes (rs_locate). */
	const char *why = NULL;
	if (desc->primary == RS_PRIMARY_RASTER)
		why = "rasterized primaries draw world-space triangles";
	else if (desc->shadows == RS_SHADOW_MAP)
		why = "shadow maps draw world-space triangles";
	else if (desc->reflections != RS_REFLECT_TRACE)
		why = "environment maps are captured from the flattened scene";
	if (why && desc->instances == RS_INSTANCES_TWO_LEVEL)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: instances two-level: %s (use "
		                    "instances=flatten)",
		                    why);
	*out_two_level = why == NULL;
	/* auto: a still scene flattened, where its triangle texture fits (on llvmpipe the
	 * flattened walk is 1.33-1.41x faster a frame, docs/gles.md "Instances"); instances
	 * that move (the first update_instances sets the scene again) and a flattened scene
	 * over the texture limit in two levels. The node texture is never larger than the
	 * triangle texture's items (a leaf holds at least one triangle). */
	uint64_t tris = rs_scene_triangle_count(scene);
	bool fits = tris * RS_PACK_TRIANGLE_TEXELS <= max_texels && tris < RS_PACK_MAX_ITEMS / 2u;
	if (*out_two_level && desc->instances == RS_INSTANCES_AUTO && !moving && fits)
		*out_two_level = false;
	return RS_OK;
}

bool rs_gles_plan_displays(const struct rs_gles_plan *plan)
{
	return plan->count > 0 && plan->steps[plan->count - 1].display;
}

void rs_gles_plan_make(const struct rs_gles_plan_desc *d, struct rs_gles_plan *out)
{
	memset(out, 0, sizeof *out);
	out->counters = d->counters;
	bool fused = d->chain == RS_CHAIN_FUSED && !d->counters;
	bool paper = d->chain == RS_CHAIN_PAPER;
	uint8_t envmap = d->envmap ? BIND_ENVMAP : 0;
	/* With cube maps every path ends in the second pass: later ones would be empty. The
	 * fused chain reads the maps at the end of the first (fused_pass). */
	uint32_t passes = d->envmap && d->passes > 2 ? 2 : d->passes;
	bool mapped = fused && d->envmap && passes == 2;
	if (mapped)
		passes = 1;
	struct cursor c = {{0, 0, 0}, 0};
	if (d->hits_only) {
		hits_only(out, d->primary == RS_PRIMARY_RASTER);
		return;
	}
	if (!fused) {
		struct rs_gles_step *s =
		    add(out, "raygen", PROG_RAYGEN, BIND_CAMERA | BIND_NEAR, 0);
		for (int k = 0; k < ST_COUNT; ++k)
			s->out[k] = state_ref(0, k);
		s->out[3] = REF_CNT;
		s->n_out = d->counters ? 4 : 3;
	}
	for (uint32_t pass = 0; pass < passes; ++pass) {
		bool rasterized = pass == 0 && d->primary == RS_PRIMARY_RASTER;
		uint8_t hit = (uint8_t)(REF_HIT + (pass == 0 ? 0 : 1));
		if (fused) {
			fused_pass(out, &c, pass, pass + 1 == passes, rasterized, envmap, mapped,
			           d->compute);
			continue;
		}
		if (rasterized) {
			raster_step(out, pass);
			struct rs_gles_step *s = add(out, "resolve", PROG_RESOLVE,
			                             BIND_SCENE | BIND_CAMERA | BIND_VIS, pass);
			s->out[0] = hit;
			s->n_out = 1;
		} else {
			struct rs_gles_step *s = add(out, "intersect", PROG_INTERSECT,
			                             BIND_SCENE | BIND_STATE | envmap, pass);
			inputs(&c, REF_NONE, s);
			s->out[0] = hit;
			s->out[1] = d->counters ? flip_cnt(&c) : REF_NONE;
			s->n_out = d->counters ? 2 : 1;
		}
		path_step(out, &c, pass, hit, paper, envmap);
	}
	out->result_acc = state_ref(c.st[ST_ACC], ST_ACC);
	out->result_cnt = (uint8_t)(REF_CNT + c.cnt);
}
