// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP METRIC_LP_SUM
#version 460
// Keeps the fragments of the source pixel's disc; the stencil counts them with
// wrap-around and blending adds 1/255 to the current channel at every wrap
// (thesis Fig. 3.49).
#include "settle.glsl"

layout(location = 0) flat in ivec2 centre;
layout(location = 1) flat in float key;
layout(location = 0) out vec4 colour;

void main() {
    ivec2 t = ivec2(floor(gl_FragCoord.xy));
    if (!in_disc(t - centre, key)) {
        discard;
    }
    colour = vec4(0.0);
    colour[settle.channel] = 1.0 / 255.0;
}
