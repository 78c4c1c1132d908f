#version 460
// An exact cone's footprint as one point sprite: a square of side 2r + 1 around the
// site. Points whose centre leaves the picture are clipped whole, so only sites
// inside the picture are drawn this way.
#include "common.glsl"

layout(location = 1) in vec4 site;  // (x, y, outer radius, truncation radius)
layout(location = 2) in uint site_id;

layout(location = 0) flat out uint out_id;
layout(location = 1) flat out vec3 out_site;

void main() {
    gl_Position = vec4(to_ndc(site.xy), 0.0, 1.0);
    gl_PointSize = 2.0 * site.w + 1.0;
    out_id = site_id;
    out_site = site.xyw;
}
