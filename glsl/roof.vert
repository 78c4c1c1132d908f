#version 460
// One saddle roof per instance, without vertex buffers (a 4-vertex strip): the
// ridge is the line through the instance's pair of sites, and the quad runs
// along it (across the whole picture, or along the pair's segment) and reaches
// to either side as far as a triangle with the pair stays within the area
// bound (thesis §7.3.3).
#include "roof.glsl"

layout(location = 0) flat out uvec3 out_pair;  // (i, j, instance)

void main() {
    uint k = uint(gl_InstanceIndex);
    uvec2 ij = pair_of(k);
    vec2 p = vec2(position[ij.x]);
    vec2 q = vec2(position[ij.y]);
    float g = distance(p, q);
    float diagonal = length(roof.size) + 2.0;
    vec2 along = g > 0.0 ? (q - p) / g : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    // Area = g d / 2, so the bound reaches d = 2 bound / g. A site lies within
    // half a pixel diagonal of its pixel's centre, and a pixel more keeps
    // rounding from dropping a centre at the rim.
    const float margin = 0.7072 + 1.0;
    float reach = roof.bound > 0.0 && g > 0.0 ? min(2.0 * roof.bound / g + margin, diagonal) : diagonal;
    float length = roof.segment != 0u ? 0.5 * g + margin : diagonal;
    vec2 corner = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1) * 2.0 - 1.0;
    vec2 world = 0.5 * (p + q) + corner.x * length * along + corner.y * reach * across;
    gl_Position = vec4((world + 0.5) / roof.size * 2.0 - 1.0, 0.0, 1.0);
    out_pair = uvec3(ij, k);
}
