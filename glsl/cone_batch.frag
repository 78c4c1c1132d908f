// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP METRIC_LP_SUM
#version 460
// The lower envelope of a batch of exact cones (cone_batch.vert): the metric's key
// of the nearest site of the batch whose truncation radius (Euclidean) reaches
// the pixel; nothing where none does. Earlier sites win ties, as earlier draws do.
#include "common.glsl"

layout(location = 0) flat in vec4 xy01;
layout(location = 1) flat in vec4 xy23;
layout(location = 2) flat in vec4 xy45;
layout(location = 3) flat in vec4 xy67;
layout(location = 4) flat in vec4 r2_0123;
layout(location = 5) flat in vec4 r2_4567;
layout(location = 6) flat in uvec4 ids_0123;
layout(location = 7) flat in uvec4 ids_4567;
layout(location = 0) out uint out_id;

float best = 3.0e38;
uint best_id = 0u;

void consider(vec2 p, vec2 site, float r2, uint id) {
    vec2 d = p - site;
    if (dot(d, d) > r2) {
        return;
    }
    float key = metric_key(d);
    if (key < best) {
        best = key;
        best_id = id;
    }
}

void main() {
    vec2 p = fragment_pixel();
    consider(p, xy01.xy, r2_0123.x, ids_0123.x);
    consider(p, xy01.zw, r2_0123.y, ids_0123.y);
    consider(p, xy23.xy, r2_0123.z, ids_0123.z);
    consider(p, xy23.zw, r2_0123.w, ids_0123.w);
    consider(p, xy45.xy, r2_4567.x, ids_4567.x);
    consider(p, xy45.zw, r2_4567.y, ids_4567.y);
    consider(p, xy67.xy, r2_4567.z, ids_4567.z);
    consider(p, xy67.zw, r2_4567.w, ids_4567.w);
    if (best > 2.0e38) {
        discard;
    }
    gl_FragDepth = best * picture.fragment_depth_scale;
    out_id = best_id;
}
