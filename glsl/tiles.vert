#version 460
// One screen tile per instance, for fragment shaders that take the envelope of
// all cones binned to the tile. Tile records (binding 1), six words each: the
// first and last pixel centre (x0, y0, x1, y1 as float bits), the index of the
// tile's first cone in the fragment shader's list and the number of cones.
#include "common.glsl"

layout(std430, set = 0, binding = 1) readonly buffer Tiles {
    uint words[];
} tiles;

layout(location = 0) flat out uvec2 cones;

void main() {
    uint t = uint(gl_InstanceIndex) * 6u;
    vec2 lo = uintBitsToFloat(uvec2(tiles.words[t], tiles.words[t + 1u])) - 0.5;
    vec2 hi = uintBitsToFloat(uvec2(tiles.words[t + 2u], tiles.words[t + 3u])) + 0.5;
    // Two triangles: corners (0,0) (1,0) (0,1) (1,0) (1,1) (0,1), as bit masks.
    uint v = uint(gl_VertexIndex);
    vec2 corner = vec2(float((26u >> v) & 1u), float((52u >> v) & 1u));
    gl_Position = vec4(to_ndc(mix(lo, hi, corner)) , 0.0, 1.0);
    cones = uvec2(tiles.words[t + 4u], tiles.words[t + 5u]);
}
