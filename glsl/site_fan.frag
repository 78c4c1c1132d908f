// variants: PLAIN FOLDED
#version 460
// The id of the site whose fan surface is lowest (site_fan.vert); a folded
// surface's depth is the magnitude of its interpolated value about zero.
layout(location = 0) flat in uint id;
#ifdef FOLDED
layout(location = 1) in float value_depth;
layout(location = 2) flat in float zero_depth;
#endif
layout(location = 0) out uint out_id;

void main() {
    out_id = id;
#ifdef FOLDED
    gl_FragDepth = zero_depth + abs(value_depth - zero_depth);
#endif
}
