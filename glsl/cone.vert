#version 460
// One cone per instance: a unit triangle fan (apex h = 0, rim h = 1), or the
// footprint polygon of an exact cone, scaled to the site's outer radius,
// translated to the site and clamped into the rectangle that holds its region
// (ConeInstance in src/algorithms/cones.rs).
#include "common.glsl"

layout(location = 0) in vec3 unit_vertex;  // (cos, sin, h)
layout(location = 1) in vec4 site;         // (x, y, outer radius, truncation radius)
layout(location = 2) in uint site_id;
layout(location = 3) in vec4 clip;         // (min x, min y, max x, max y)

layout(location = 0) flat out uint out_id;
layout(location = 1) flat out vec3 out_site;  // (x, y, truncation radius)

void main() {
    vec2 world = clamp(site.xy + unit_vertex.xy * site.z, clip.xy, clip.zw);
    vec2 ndc = to_ndc(world);
    float depth = unit_vertex.z * site.z * picture.vertex_depth_scale;
    gl_Position = vec4(ndc, depth, 1.0);
    out_id = site_id;
    out_site = site.xyw;
}
