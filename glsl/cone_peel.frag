// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// An exact cone peeled against the previous level (thesis §3.7): only fragments
// deeper than the pixel's previous depth z take part, so the depth test LESS
// finds the next layer of the arrangement. Also counts equal distances (step 3),
// drawn there with the depth test EQUAL and the stencil incrementing.
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
    if (depth <= uintBitsToFloat(previous.words[pixel_index()])) {
        discard;
    }
    gl_FragDepth = depth;
    out_id = id;
}
