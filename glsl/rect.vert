#version 460
// An axis-aligned rectangle at constant depth, from gl_VertexIndex (4-vertex strip).
layout(push_constant) uniform Rect {
    vec2 size;        // picture size in pixels
    vec2 lo;          // world corner (min x, min y)
    vec2 hi;          // world corner (max x, max y)
    float depth;
    uint pad;
    vec4 value;       // colour written by rect.frag (bit pattern for uint targets)
} rect;

void main() {
    vec2 corner = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1);
    vec2 world = mix(rect.lo, rect.hi, corner);
    gl_Position = vec4((world + 0.5) / rect.size * 2.0 - 1.0, rect.depth, 1.0);
}
