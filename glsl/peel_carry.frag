#version 460
// Step 2 of the thesis's peeling (§3.7), drawn picture-wide where the stencil says
// the previous distance has multiplicity left: the level keeps that distance and
// site. (The shader writes depth, so it runs before the stencil test: it must
// have no other effect.)
#include "common.glsl"
#include "peel.glsl"

layout(location = 0) out uint out_id;

void main() {
    uint p = pixel_index();
    gl_FragDepth = uintBitsToFloat(previous.words[p]);
    out_id = previous.words[pixel_count() + p];
}
