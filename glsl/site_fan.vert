// variants: PLAIN FOLDED
#version 460
// Fan surfaces of sites of any shape (src/algorithms/sites.rs): triangles whose
// vertices carry their picture position and depth, so the rasterizer interpolates
// the weighted distance (thesis §3.8–3.9: cones with weighted apexes, roofs swept
// along segments and arcs). A folded surface (the straw huts of circles and
// arcs) carries the depth of a signed value and the depth of zero, and its
// fragments take the magnitude (site_fan.frag).
#include "common.glsl"

#ifdef FOLDED
layout(location = 0) in vec4 vertex;  // (x, y, depth of the value, depth of zero)
#else
layout(location = 0) in vec3 vertex;  // (x, y, depth)
#endif
layout(location = 1) in uint site_id;

layout(location = 0) flat out uint out_id;
#ifdef FOLDED
layout(location = 1) out float value_depth;
layout(location = 2) flat out float zero_depth;
#endif

void main() {
#ifdef FOLDED
    // The fragment writes its depth; the rasterized one only has to lie in
    // the depth range.
    gl_Position = vec4(to_ndc(vertex.xy), vertex.w, 1.0);
    value_depth = vertex.z;
    zero_depth = vertex.w;
#else
    gl_Position = vec4(to_ndc(vertex.xy), vertex.z, 1.0);
#endif
    out_id = site_id;
}
