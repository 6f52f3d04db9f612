/* Shared pieces of the scene generator (not installed): flat-shaded shapes and the rules
 * SCENES.md applies to every scene (camera, environment cube). */
#ifndef RS_SCENEGEN_INTERNAL_H
#define RS_SCENEGEN_INTERNAL_H

/* Glass stands this far above the surface it rests on, so that no glass face is coplanar
 * with another face (see docs/scenes.md). */
#define SG_GLASS_GAP 1e-3

#include <stdint.h>

#include "raystream/rs_scene.h"

/* Add a material, returning its id in *out_id; errors carry the scene's message. */
enum rs_status sg_material(struct rs_scene *scene, const struct rs_material *m, uint32_t *out_id,
                           struct rs_error *err);

/* A box (12 triangles, 24 vertices, flat normals, outward winding): [lo, hi] turned by
 * yaw_deg about +y (right-handed: +x towards -z) about its own centre. */
enum rs_status sg_add_box(struct rs_scene *scene, const double lo[3], const double hi[3],
                          double yaw_deg, uint32_t material, struct rs_error *err);

/* An upright prism (8 triangles): equilateral base of the given circumradius centred on
 * `base` with one vertex towards +z, extruded `height` along +y. */
enum rs_status sg_add_prism(struct rs_scene *scene, const double base[3], double circumradius,
                            double height, uint32_t material, struct rs_error *err);

/* One triangle a, b, c (flat normal (b-a)x(c-a)). */
enum rs_status sg_add_triangle(struct rs_scene *scene, const double a[3], const double b[3],
                               const double c[3], uint32_t material, struct rs_error *err);

/* Camera (45 deg, 512x512) framed by rs_camera_frame() on `focus` from 30 deg above. */
enum rs_status sg_frame_camera(struct rs_scene *scene, const struct rs_bounds *focus,
                               struct rs_error *err);

/* White point light, intensity 1. */
enum rs_status sg_add_light(struct rs_scene *scene, const double pos[3], struct rs_error *err);

/* Environment cube on the whole scene's bounds: side 4x the largest extent, six distinct
 * face colours, 16x16 grid. Call after all geometry is in. */
enum rs_status sg_set_environment(struct rs_scene *scene, struct rs_error *err);

/* The last step of a scene: the four lights L1..L4 at `lights`, the environment cube
 * (sg_set_environment) and ambient 0.1. */
enum rs_status sg_finish(struct rs_scene *scene, const double lights[4][3], struct rs_error *err);

/* The cow's material in every cow scene. */
extern const struct rs_material sg_cow_material;

/* Load the cow model into a new scene *out, with scratch for one placed copy (xyz per
 * vertex: *pos, *nrm); the caller frees all three. Nothing is left on failure. */
enum rs_status sg_load_cow(const char *cow_path, struct rs_scene **out, double **pos, float **nrm,
                           struct rs_error *err);

/* One copy of `cow` turned by `yaw` radians about +y (right-handed) about its bounds' centre,
 * that centre put on (gx, gz), standing on y = 0; `pos` and `nrm` are scratch. */
enum rs_status sg_add_cow(struct rs_scene *scene, const struct rs_scene *cow, double yaw, double gx,
                          double gz, uint32_t mat, double *pos, float *nrm, struct rs_error *err);

/* The scene builders, into an empty scene. A CowN with frame > 0 has its cow n / 2 sway
 * (fps > 0); the stage is that of frame 0. */
enum rs_status sg_build_cows(struct rs_scene *scene, const char *cow_path, uint32_t n,
                             uint32_t frame, uint32_t fps, bool instanced, struct rs_error *err);
/* The animated scene (docs/scenes.md) at frame / fps seconds. */
enum rs_status sg_build_animated(struct rs_scene *scene, const char *cow_path, uint32_t frame,
                                 uint32_t fps, struct rs_error *err);
enum rs_status sg_build_box(struct rs_scene *scene, struct rs_error *err);
enum rs_status sg_build_mirrors(struct rs_scene *scene, struct rs_error *err);

/* Bounds centre. */
void sg_center(const struct rs_bounds *b, double out[3]);

#endif
