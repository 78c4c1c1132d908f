#version 460
// Fan surfaces of sites of any shape (src/algorithms/sites.rs): triangles whose
// vertices carry their picture position and depth, so the rasterizer interpolates
// the weighted distance (thesis §3.8–3.9: cones with weighted apexes, roofs swept
// along segments and arcs).
#include "common.glsl"

layout(location = 0) in vec3 vertex;  // (x, y, depth)
layout(location = 1) in uint site_id;

layout(location = 0) flat out uint out_id;

void main() {
    gl_Position = vec4(to_ndc(vertex.xy), vertex.z, 1.0);
    out_id = site_id;
}
