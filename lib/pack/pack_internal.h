/* Private to lib/pack: the node texture writer shared by rs_pack_scene. */
#ifndef RS_PACK_INTERNAL_H
#define RS_PACK_INTERNAL_H

#include "raystream/rs_pack.h"

/* Node bounds from the packed triangles (which must be written first), the node texture in
 * packed->node_format, and the leaves' last flags in the triangle texture. */
enum rs_status rs__pack_nodes(const struct rs_bvh_node *nodes, size_t node_count,
                              struct rs_packed *packed, struct rs_error *err);

#endif
