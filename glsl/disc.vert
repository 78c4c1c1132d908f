#version 460
// One closed disc per instance (alpha hulls, thesis ch. 6), drawn as its bounding
// square: a 4-vertex strip made from gl_VertexIndex; disc.frag keeps the disc.
#include "common.glsl"

layout(location = 0) in vec4 disc;  // (centre x, centre y, radius, value), pixels

layout(location = 0) flat out vec4 out_disc;

void main() {
    vec2 corner = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1) * 2.0 - 1.0;
    // Half a pixel more, so that no pixel centre on the rim is left to the
    // rasterizer's edge rules.
    vec2 world = disc.xy + corner * (disc.z + 0.5);
    gl_Position = vec4(to_ndc(world), 0.0, 1.0);
    out_disc = disc;
}
