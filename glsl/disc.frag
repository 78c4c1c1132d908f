#version 460
// Keeps the pixel centres of the closed disc and writes its value to a float
// target: overwritten it marks, blended with ADD it counts (thesis §6.4.2).
#include "common.glsl"

layout(location = 0) flat in vec4 disc;
layout(location = 0) out vec4 colour;

void main() {
    vec2 d = fragment_pixel() - disc.xy;
    if (dot(d, d) > disc.z * disc.z) {
        discard;
    }
    colour = vec4(disc.w);
}
