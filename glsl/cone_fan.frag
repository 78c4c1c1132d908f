#version 460
// A fan cone: the depth is the interpolated cone height (thesis §3.3).
layout(location = 0) flat in uint id;
layout(location = 1) flat in vec2 site;
layout(location = 0) out uint out_id;

void main() {
    out_id = id;
}
