/* raystream-glbench: frame times of a render backend (the GLES kernels above all) per scene
 * and option set, for docs/benchmarks.md: median and min-max over N frames after one
 * warm-up frame, fps, Mrays/s (rays counted in one extra counting frame, not timed), the
 * median time of each kernel, and the process CPU time per frame (llvmpipe's threads
 * included): on a shared machine that is far steadier than wall time. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_renderers.h"
#include "tool_common.h"

#define MAX_FRAMES 64

static int usage(void)
{
	fprintf(stderr, "usage: raystream-glbench [--backend egl|osmesa|cpu] [--size N] "
	                "[--passes N] [--lights N] [--frames N] [--chain fused|separate|paper] "
	                "[--primary trace|raster] [--shadows rays|map:RES:FILTER] "
	                "[--reflections trace|envmap|interreflect[:BOUNCES]] "
	                "[--nodes compact|paper[:directional|single]] "
	                "[--scene-storage auto|2d|buffer] SCENE...\n");
	return 2;
}

static int bench(const char *name, const char *backend, struct rs_render_desc desc, uint32_t frames)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	struct rs_renderer *r = NULL;
	uint8_t *px = malloc((size_t)desc.width * desc.height * 4);
	int code = 1;
	if (!px || rs_scenegen_load(name, &scene, &err) != RS_OK)
		goto done;
	if (desc.lights > rs_scene_light_count(scene)) {
		rs_error_set(&err, RS_ERR_INVALID, "%s has %zu lights", name,
		             rs_scene_light_count(scene));
		goto done;
	}
	/* one counting frame for the ray numbers, then the timed frames without counters */
	struct rs_render_desc counting = desc;
	counting.counters = true;
	struct rs_frame frame = {.rgba8 = px};
	if (rs_renderer_open(backend, &counting, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		goto done;
	const struct rs_render_stats *s = rs_renderer_stats(r);
	uint64_t rays = s->primary_rays + s->secondary_rays + s->shadow_rays;
	double hits = s->total_per_pixel;
	rs_renderer_destroy(&r);
	if (rs_renderer_open(backend, &desc, &r, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &frame, &err) != RS_OK) /* warm-up */
		goto done;
	double ms[MAX_FRAMES], cpu[MAX_FRAMES], kms[RS_RENDER_MAX_KERNELS][MAX_FRAMES];
	s = rs_renderer_stats(r);
	for (uint32_t f = 0; f < frames; ++f) {
		double c0 = rs_tool_cpu_ms();
		if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
			goto done;
		cpu[f] = rs_tool_cpu_ms() - c0;
		ms[f] = s->render_ms + s->readback_ms;
		for (uint32_t k = 0; k < s->kernel_count; ++k)
			kms[k][f] = s->kernels[k].ms;
	}
	qsort(ms, frames, sizeof ms[0], rs_tool_cmp_double);
	qsort(cpu, frames, sizeof cpu[0], rs_tool_cmp_double);
	double med = ms[frames / 2];
	char refl[32] = "";
	if (desc.reflections != RS_REFLECT_TRACE) {
		refl[0] = ' ';
		rs_tool_reflections_name(&desc, refl + 1, sizeof refl - 1);
	}
	char nodes[32];
	printf("%-6s %-6s %ux%u passes %u lights %u %s %s %s%s nodes %s storage %s: cpu %.1f ms "
	       "(%.1f-%.1f), "
	       "wall "
	       "%.1f ms (%.1f-%.1f) = %.2f fps, %.2f Mrays/s (%llu rays), hit numbers %.1f;",
	       name, s->backend, desc.width, desc.height, desc.passes, desc.lights,
	       desc.chain == RS_CHAIN_PAPER      ? "paper"
	       : desc.chain == RS_CHAIN_SEPARATE ? "separate"
	                                         : "fused",
	       desc.primary == RS_PRIMARY_RASTER ? "raster" : "trace",
	       desc.shadows == RS_SHADOW_MAP ? "map" : "rays", refl,
	       rs_tool_nodes_name(&desc.pack, nodes, sizeof nodes),
	       rs_tool_storage_name(s->scene_storage), cpu[frames / 2], cpu[0], cpu[frames - 1],
	       med, ms[0], ms[frames - 1], 1000.0 / med, (double)rays / (med * 1000.0),
	       (unsigned long long)rays, hits);
	for (uint32_t k = 0; k < s->kernel_count; ++k) {
		qsort(kms[k], frames, sizeof kms[k][0], rs_tool_cmp_double);
		printf(" %s %.1f", s->kernels[k].name, kms[k][frames / 2]);
	}
	printf("\n  renderer: %s\n", s->renderer);
	code = 0;
done:
	if (code)
		fprintf(stderr, "raystream-glbench: %s: %s\n", name, err.message);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
	free(px);
	return code;
}

int main(int argc, char **argv)
{
	const char *backend = "egl";
	uint32_t size = 512, frames = 5, res = 0, filter = 0;
	struct rs_render_desc desc = {.passes = 1, .lights = 1, .bvh = {.builder = RS_BVH_SAH}};
	int first_scene = 0;
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (a[0] != '-') {
			first_scene = first_scene ? first_scene : i;
			continue;
		}
		if (!v)
			return usage();
		++i;
		if (strcmp(a, "--backend") == 0)
			backend = v;
		else if (strcmp(a, "--size") == 0 && rs_tool_parse_u32(v, 8, 4096, &size))
			;
		else if (strcmp(a, "--passes") == 0 && rs_tool_parse_u32(v, 1, 64, &desc.passes))
			;
		else if (strcmp(a, "--lights") == 0 && rs_tool_parse_u32(v, 1, 16, &desc.lights))
			;
		else if (strcmp(a, "--frames") == 0 && rs_tool_parse_u32(v, 1, MAX_FRAMES, &frames))
			;
		else if (strcmp(a, "--chain") == 0 && strcmp(v, "fused") == 0)
			desc.chain = RS_CHAIN_FUSED;
		else if (strcmp(a, "--chain") == 0 && strcmp(v, "separate") == 0)
			desc.chain = RS_CHAIN_SEPARATE;
		else if (strcmp(a, "--chain") == 0 && strcmp(v, "paper") == 0)
			desc.chain = RS_CHAIN_PAPER;
		else if (strcmp(a, "--primary") == 0 && strcmp(v, "trace") == 0)
			desc.primary = RS_PRIMARY_TRACE;
		else if (strcmp(a, "--primary") == 0 && strcmp(v, "raster") == 0)
			desc.primary = RS_PRIMARY_RASTER;
		else if (strcmp(a, "--reflections") == 0 &&
		         rs_tool_parse_reflections(v, &desc.reflections, &desc.reflection_bounces))
			;
		else if (strcmp(a, "--nodes") == 0 && rs_tool_parse_nodes(v, &desc.pack))
			;
		else if (strcmp(a, "--scene-storage") == 0 &&
		         rs_tool_parse_storage(v, &desc.scene_storage))
			;
		else if (strcmp(a, "--shadows") == 0 && strcmp(v, "rays") == 0)
			desc.shadows = RS_SHADOW_RAYS;
		else if (strcmp(a, "--shadows") == 0 && sscanf(v, "map:%u:%u", &res, &filter) == 2)
			desc.shadows = RS_SHADOW_MAP;
		else
			return usage();
	}
	if (!first_scene)
		return usage();
	desc.width = desc.height = size;
	desc.shadow_map_size = res;
	desc.shadow_filter = filter;
	int code = 0;
	for (int i = first_scene; i < argc; ++i) {
		if (argv[i][0] == '-') {
			++i;
			continue;
		}
		code |= bench(argv[i], backend, desc, frames);
	}
	return code;
}
