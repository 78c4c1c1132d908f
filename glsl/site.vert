#version 460
// A site of any shape (src/geometry/site.rs) drawn as one rectangle; its fragments
// evaluate the weighted distance exactly (site_exact.frag).
#include "common.glsl"

layout(location = 0) in vec3 unit_vertex;  // corner of the unit square
layout(location = 1) in vec4 rect;         // (min x, min y, max x, max y)
layout(location = 2) in vec4 shape0;       // see site_exact.frag
layout(location = 3) in vec4 shape1;
layout(location = 4) in vec2 weights;      // (1 / (frame scale * m), a - smallest a)
layout(location = 5) in uvec2 kind_id;

layout(location = 0) flat out vec4 out_shape0;
layout(location = 1) flat out vec4 out_shape1;
layout(location = 2) flat out vec2 out_weights;
layout(location = 3) flat out uvec2 out_kind_id;

void main() {
    vec2 world = mix(rect.xy, rect.zw, unit_vertex.xy);
    gl_Position = vec4(to_ndc(world), 0.0, 1.0);
    out_shape0 = shape0;
    out_shape1 = shape1;
    out_weights = weights;
    out_kind_id = kind_id;
}
