// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP METRIC_LP_SUM
#version 460
// An exact cone: the depth is the metric's key of the offset from the site (the
// squared Euclidean distance unless another metric is chosen), computed per
// fragment (the depth-texture remedy of thesis §3.4). Keys of integer offsets are
// exact in float32 below 2^24 for L1, L2 and L-infinity, and the scale is a power
// of two, so ties between integer sites are exact ties. Fragments beyond the
// (Euclidean) truncation radius are dropped (see cone_fan.frag).
#include "common.glsl"

layout(location = 0) flat in uint id;
layout(location = 1) flat in vec3 site;
layout(location = 0) out uint out_id;

void main() {
    vec2 d = fragment_pixel() - site.xy;
    float d2 = dot(d, d);
    if (d2 > site.z * site.z) {
        discard;
    }
    gl_FragDepth = metric_key(d) * picture.fragment_depth_scale;
    out_id = id;
}
