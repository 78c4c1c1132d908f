// variants: POINT SEGMENT CIRCLE ARC
// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// The weighted distance of a site of any shape, per fragment (thesis §3.8–3.9:
// the roof of a segment, the straw hut of a circle, the sliced hut of an arc, with
// the apex angle and height of its weights), written as depth:
// kind 0 point, 1 segment, 2 circle, 3 arc, shaped as site_distance.glsl reads.
// The weighted distance is dist * weights.x + weights.y (world units). Each
// build handles one shape (POINT, SEGMENT, CIRCLE or ARC):
// lavapipe runs every branch a fragment could take, so one shader for all shapes
// made every fragment pay for the curves' searches (L1 segments: 12 times
// slower), and with the metric read at run time, for the L_p searches too.
#include "common.glsl"
#include "site_distance.glsl"

layout(location = 0) flat in vec4 shape0;
layout(location = 1) flat in vec4 shape1;
layout(location = 2) flat in vec2 weights;
layout(location = 3) flat in uvec2 kind_id;
layout(location = 0) out uint out_id;

void main() {
    float d = site_distance(fragment_pixel(), shape0, shape1);
    gl_FragDepth = (d * weights.x + weights.y) * picture.fragment_depth_scale;
    out_id = kind_id.y;
}
