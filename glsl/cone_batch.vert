#version 460
// Up to eight exact cones in one rectangle: the bounding box of their footprints.
// Batching nearby cones trades triangle setup (costly on software rasterizers) for
// a short loop per fragment; the fragment still writes the lower envelope of the
// batch's cones exactly (cone_batch.frag).
#include "common.glsl"

layout(location = 0) in vec3 unit_vertex;  // corner of the unit square
layout(location = 1) in vec4 rect;         // (min x, min y, max x, max y)
layout(location = 2) in vec4 xy01;         // sites 0 and 1: (x0, y0, x1, y1)
layout(location = 3) in vec4 xy23;
layout(location = 4) in vec4 xy45;
layout(location = 5) in vec4 xy67;
layout(location = 6) in vec4 r2_0123;      // squared truncation radii
layout(location = 7) in vec4 r2_4567;
layout(location = 8) in uvec4 ids_0123;
layout(location = 9) in uvec4 ids_4567;

layout(location = 0) flat out vec4 out_xy01;
layout(location = 1) flat out vec4 out_xy23;
layout(location = 2) flat out vec4 out_xy45;
layout(location = 3) flat out vec4 out_xy67;
layout(location = 4) flat out vec4 out_r2_0123;
layout(location = 5) flat out vec4 out_r2_4567;
layout(location = 6) flat out uvec4 out_ids_0123;
layout(location = 7) flat out uvec4 out_ids_4567;

void main() {
    vec2 world = mix(rect.xy, rect.zw, unit_vertex.xy);
    gl_Position = vec4(to_ndc(world), 0.0, 1.0);
    out_xy01 = xy01;
    out_xy23 = xy23;
    out_xy45 = xy45;
    out_xy67 = xy67;
    out_r2_0123 = r2_0123;
    out_r2_4567 = r2_4567;
    out_ids_0123 = ids_0123;
    out_ids_4567 = ids_4567;
}
