#version 460
// Up to eight sites of one shape in one rectangle, the bounding box of their own
// (site.vert draws one site per rectangle): lavapipe sets up and bins every
// triangle, as costly as many fragments, so small sites share one.
// The fragment keeps the lowest weighted distance (site_batch.frag).
#include "common.glsl"

layout(location = 0) in vec3 unit_vertex;  // corner of the unit square
layout(location = 1) in vec4 rect;         // (min x, min y, max x, max y)
// Each site's shape0 (site_distance.glsl); its shape1 is unused by points,
// segments and circles. Arc k's shape0 and shape1 are shape_2k and shape_2k+1.
layout(location = 2) in vec4 shape_0;
layout(location = 3) in vec4 shape_1;
layout(location = 4) in vec4 shape_2;
layout(location = 5) in vec4 shape_3;
layout(location = 6) in vec4 shape_4;
layout(location = 7) in vec4 shape_5;
layout(location = 8) in vec4 shape_6;
layout(location = 9) in vec4 shape_7;
// The weights (site.vert) of sites 0 and 1, 2 and 3, ...
layout(location = 10) in vec4 weights_01;
layout(location = 11) in vec4 weights_23;
layout(location = 12) in vec4 weights_45;
layout(location = 13) in vec4 weights_67;
layout(location = 14) in uvec4 ids_0123;
layout(location = 15) in uvec4 ids_4567;

layout(location = 0) flat out vec4 out_shape_0;
layout(location = 1) flat out vec4 out_shape_1;
layout(location = 2) flat out vec4 out_shape_2;
layout(location = 3) flat out vec4 out_shape_3;
layout(location = 4) flat out vec4 out_shape_4;
layout(location = 5) flat out vec4 out_shape_5;
layout(location = 6) flat out vec4 out_shape_6;
layout(location = 7) flat out vec4 out_shape_7;
layout(location = 8) flat out vec4 out_weights_01;
layout(location = 9) flat out vec4 out_weights_23;
layout(location = 10) flat out vec4 out_weights_45;
layout(location = 11) flat out vec4 out_weights_67;
layout(location = 12) flat out uvec4 out_ids_0123;
layout(location = 13) flat out uvec4 out_ids_4567;

void main() {
    vec2 world = mix(rect.xy, rect.zw, unit_vertex.xy);
    gl_Position = vec4(to_ndc(world), 0.0, 1.0);
    out_shape_0 = shape_0;
    out_shape_1 = shape_1;
    out_shape_2 = shape_2;
    out_shape_3 = shape_3;
    out_shape_4 = shape_4;
    out_shape_5 = shape_5;
    out_shape_6 = shape_6;
    out_shape_7 = shape_7;
    out_weights_01 = weights_01;
    out_weights_23 = weights_23;
    out_weights_45 = weights_45;
    out_weights_67 = weights_67;
    out_ids_0123 = ids_0123;
    out_ids_4567 = ids_4567;
}
