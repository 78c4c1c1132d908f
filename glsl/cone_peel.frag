// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// An exact cone peeled against the previous level (thesis §3.7): only fragments
// after the pixel's previous (depth z, site) in the order (distance, site id)
// take part, so the depth test LESS, over cones drawn in the order of their ids,
// finds the next layer and names equally far sites on levels of their own.
#include "common.glsl"
#include "peel.glsl"

layout(location = 0) flat in uint id;
layout(location = 1) flat in vec3 site;
layout(location = 0) out uint out_id;

void main() {
    vec2 d = fragment_pixel() - site.xy;
    float d2 = dot(d, d);
    if (d2 > site.z * site.z) {
        discard;
    }
    float depth = metric_key(d) * picture.fragment_depth_scale;
    uint p = pixel_index();
    float before = uintBitsToFloat(previous.words[p]);
    if (depth < before || (depth == before && id <= previous.words[pixel_count() + p])) {
        discard;
    }
    gl_FragDepth = depth;
    out_id = id;
}
