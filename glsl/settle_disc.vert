#version 460
// The thesis's disc of one source pixel (§3.10.3), drawn as its bounding square
// (a 4-vertex strip per instance); settle_disc.frag keeps the disc's pixels.
#include "settle.glsl"

layout(location = 0) flat out ivec2 centre;
layout(location = 1) flat out float key;

void main() {
    uint index = settle.first + uint(gl_InstanceIndex);
    centre = ivec2(int(index % uint(settle.size.x)), int(index / uint(settle.size.x)));
    key = radius_key[index];
    int m = disc_bound(key, max(settle.size.x, settle.size.y));
    // An empty disc collapses to a point, which makes no fragments.
    float half_side = m < 0 ? 0.0 : float(m) + 0.5;
    vec2 corner = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1) * 2.0 - 1.0;
    vec2 world = vec2(centre) + corner * half_side;
    gl_Position = vec4((world + 0.5) / vec2(settle.size) * 2.0 - 1.0, 0.0, 1.0);
}
