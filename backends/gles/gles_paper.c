/* The paper's separate-kernel chain (RS_CHAIN_PAPER): after a segment's intersection, the
 * environment, shading and next-ray kernels each run as their own fragment pass over the
 * ping-pong state. Each writes only the state it changes (environment and shading the
 * colour, shading the counters, next ray the ray), so a pass costs the textures it moves:
 * the chain's price against the fused kernels is that texture traffic and the surface
 * rebuilt from the hit by both shading and next ray, which is what the benchmark shows. */
#include "gles_internal.h"

/* Bind the scene, the state `c` and the hits to `prog` (made current). */
static void inputs(struct gles *g, GLuint prog, uint32_t pass, GLuint hit,
                   const struct rs_gles_cursor *c)
{
	g->gl.UseProgram(prog);
	rs_gles_scene_uniforms(g, prog);
	if (g->desc.reflections != RS_REFLECT_TRACE)
		rs_gles_envmap_uniforms(g, prog, pass);
	rs_gles_state_inputs(g, prog, c);
	rs_gles_bind_2d(&g->gl, prog, UNIT_HIT, "u_hit", hit);
}

/* The other texture of state pair `s`, which becomes the current one. */
static GLuint flip(struct gles *g, struct rs_gles_cursor *c, int s)
{
	c->st[s] = 1 - c->st[s];
	return g->state[c->st[s]][s];
}

enum rs_status rs_gles_paper_segment(struct gles *g, uint32_t pass, GLuint hit,
                                     struct rs_gles_cursor *c, struct rs_render_stats *stats,
                                     struct rs_error *err)
{
	bool counters = g->desc.counters;
	/* Inputs are bound before the cursor moves: a pass reads one texture of each pair and
	 * writes the other. */
	double t0 = rs_now_ms();
	inputs(g, g->prog[PROG_ENVIRONMENT], pass, hit, c);
	GLuint out[3] = {flip(g, c, ST_ACC)};
	enum rs_status st = rs_gles_draw(g, "environment", out, 1, stats, t0, err);
	if (st != RS_OK)
		return st;

	t0 = rs_now_ms();
	inputs(g, g->prog[PROG_SHADING], pass, hit, c);
	out[0] = flip(g, c, ST_ACC);
	if (counters) {
		c->cnt = 1 - c->cnt;
		out[1] = g->cnt[c->cnt];
	}
	st = rs_gles_draw(g, "shading", out, counters ? 2 : 1, stats, t0, err);
	if (st != RS_OK)
		return st;

	t0 = rs_now_ms();
	inputs(g, g->prog[PROG_NEXTRAY], pass, hit, c);
	out[0] = flip(g, c, ST_ORIG);
	out[1] = flip(g, c, ST_DIR);
	out[2] = flip(g, c, ST_ACC);
	return rs_gles_draw(g, "next ray", out, 3, stats, t0, err);
}
