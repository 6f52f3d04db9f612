/* Cow17 flattened (one level) against Cow17i (two levels, docs/bvh.md "Instances"): build +
 * pack time on one thread and the CPU reference walk of 256x256 camera rays, alternating,
 * medians of 7. Not built by CMake; the command is in docs/benchmarks.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_scenegen.h"
#include "raystream/rs_trace.h"

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

static double flat_pack(const struct rs_scene *s, struct rs_packed *out)
{
	double t0 = rs_now_ms();
	size_t tris = rs_scene_triangle_count(s), count = 0;
	struct rs_bvh_desc bvh = {.threads = 1};
	size_t cap = rs_bvh_node_bound(&bvh, tris);
	struct rs_bvh_node *nodes = malloc(cap * sizeof *nodes);
	uint32_t *order = malloc(tris * sizeof *order);
	rs_bvh_build(&bvh, rs_scene_positions(s), rs_scene_vertex_count(s), rs_scene_indices(s),
	             tris, nodes, cap, order, &count, NULL);
	rs_pack_layout(NULL, count, tris, rs_scene_material_count(s), out, NULL);
	rs_pack_alloc(out, NULL);
	rs_pack_scene(s, nodes, count, order, out, NULL);
	free(nodes);
	free(order);
	return rs_now_ms() - t0;
}

int main(void)
{
	struct rs_scene *flat = NULL, *inst = NULL;
	struct rs_scenegen_desc d;
	rs_scenegen_parse("cow17", &d, NULL);
	rs_scenegen_build(&d, &flat, NULL);
	rs_scenegen_parse("cow17i", &d, NULL);
	rs_scenegen_build(&d, &inst, NULL);
	const struct rs_camera *cam = rs_scene_camera(flat);
	struct rs_bounds b;
	rs_scene_bounds(flat, &b);
	enum { N = 7, G = 256 };
	double pf[N], pi[N], wf[N], wi[N];
	size_t bf = 0, bi = 0;
	for (int k = 0; k < N; k++) {
		struct rs_packed one;
		struct rs_packed_instances two;
		pf[k] = flat_pack(flat, &one);
		double t0 = rs_now_ms();
		struct rs_bvh_desc bvh = {.threads = 1};
		rs_pack_instances(inst, &bvh, NULL, &two, NULL);
		pi[k] = rs_now_ms() - t0;
		bf = rs_pack_bytes(&one);
		bi = rs_pack_instances_bytes(&two);
		for (int which = 0; which < 2; which++) {
			double t1 = rs_now_ms();
			unsigned hits = 0;
			for (int y = 0; y < G; y++)
				for (int x = 0; x < G; x++) {
					double tg[3] = {
					    b.lo[0] + (b.hi[0] - b.lo[0]) * (x + 0.5) / G,
					    b.lo[1] + (b.hi[1] - b.lo[1]) * (y + 0.5) / G,
					    0.5 * (b.lo[2] + b.hi[2])};
					struct rs_ray r = {.tmax = INFINITY,
					                   .skip_slot = RS_NO_SLOT};
					for (int a = 0; a < 3; a++) {
						r.origin[a] = cam->eye[a];
						r.dir[a] = tg[a] - cam->eye[a];
					}
					struct rs_hit h;
					struct rs_instance_hit ih;
					hits += which ? rs_trace_instances_closest(&two, 0, &r, &ih,
					                                           NULL)
					              : rs_trace_closest(&one, 0, &r, &h, NULL);
				}
			(which ? wi : wf)[k] = rs_now_ms() - t1;
			if (k == 0)
				fprintf(stderr, "hits %u\n", hits);
		}
		rs_pack_free(&one);
		rs_pack_instances_free(&two);
	}
	qsort(pf, N, sizeof *pf, cmp);
	qsort(pi, N, sizeof *pi, cmp);
	qsort(wf, N, sizeof *wf, cmp);
	qsort(wi, N, sizeof *wi, cmp);
	printf("build+pack (1 thread): flattened %.1f ms, two-level %.1f ms (%.3f)\n", pf[N / 2],
	       pi[N / 2], pi[N / 2] / pf[N / 2]);
	printf("walk %d rays: flattened %.1f ms, two-level %.1f ms (%.3f)\n", G * G, wf[N / 2],
	       wi[N / 2], wi[N / 2] / wf[N / 2]);
	printf("bytes: flattened %zu, two-level %zu (%.4f)\n", bf, bi, (double)bi / (double)bf);
	rs_scene_destroy(&flat);
	rs_scene_destroy(&inst);
	return 0;
}
