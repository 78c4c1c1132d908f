#version 460
// A fan cone: the depth is the interpolated cone height (thesis §3.3). Fragments
// beyond the truncation radius are dropped, so a pixel is covered exactly when some
// site lies within that radius: the coverage test of the quadtree speedup relies on
// it (thesis §3.5).
#include "common.glsl"

layout(location = 0) flat in uint id;
layout(location = 1) flat in vec3 site;
layout(location = 0) out uint out_id;

void main() {
    vec2 d = fragment_pixel() - site.xy;
    if (dot(d, d) > site.z * site.z) {
        discard;
    }
    out_id = id;
}
