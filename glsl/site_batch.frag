// variants: POINT SEGMENT CIRCLE ARC
// variants: METRIC_L2 METRIC_L1 METRIC_LINF
#version 460
// The lower envelope of a batch of sites (site_batch.vert): the lowest weighted
// distance among its eight sites (four arcs, each with two vec4 of shape), each
// evaluated as site_exact.frag does. Earlier sites win ties. Drawn for the sites
// whose distances cost a few operations (src/algorithms/sites.rs, `batched`).
#include "common.glsl"
#include "site_distance.glsl"

layout(location = 0) flat in vec4 shape_0;
layout(location = 1) flat in vec4 shape_1;
layout(location = 2) flat in vec4 shape_2;
layout(location = 3) flat in vec4 shape_3;
layout(location = 4) flat in vec4 shape_4;
layout(location = 5) flat in vec4 shape_5;
layout(location = 6) flat in vec4 shape_6;
layout(location = 7) flat in vec4 shape_7;
layout(location = 8) flat in vec4 weights_01;
layout(location = 9) flat in vec4 weights_23;
layout(location = 10) flat in vec4 weights_45;
layout(location = 11) flat in vec4 weights_67;
layout(location = 12) flat in uvec4 ids_0123;
layout(location = 13) flat in uvec4 ids_4567;
layout(location = 0) out uint out_id;

float best = 3.0e38;
uint best_id = 0u;

void consider(vec2 p, vec4 shape0, vec4 shape1, vec2 weights, uint id) {
    float d = site_distance(p, shape0, shape1) * weights.x + weights.y;
    if (d < best) {
        best = d;
        best_id = id;
    }
}

void main() {
    vec2 p = fragment_pixel();
#ifdef ARC
    consider(p, shape_0, shape_1, weights_01.xy, ids_0123.x);
    consider(p, shape_2, shape_3, weights_01.zw, ids_0123.y);
    consider(p, shape_4, shape_5, weights_23.xy, ids_0123.z);
    consider(p, shape_6, shape_7, weights_23.zw, ids_0123.w);
#else
    const vec4 none = vec4(0.0);
    consider(p, shape_0, none, weights_01.xy, ids_0123.x);
    consider(p, shape_1, none, weights_01.zw, ids_0123.y);
    consider(p, shape_2, none, weights_23.xy, ids_0123.z);
    consider(p, shape_3, none, weights_23.zw, ids_0123.w);
    consider(p, shape_4, none, weights_45.xy, ids_4567.x);
    consider(p, shape_5, none, weights_45.zw, ids_4567.y);
    consider(p, shape_6, none, weights_67.xy, ids_4567.z);
    consider(p, shape_7, none, weights_67.zw, ids_4567.w);
#endif
    gl_FragDepth = best * picture.fragment_depth_scale;
    out_id = best_id;
}
