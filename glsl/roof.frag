// variants: TRIANGLE SIDES
#version 460
// The height of a saddle roof at the site drawn in this pixel: the area of the
// triangle the site makes with the roof's pair, in double precision from the
// site's own position rather than the pixel centre's (thesis §7.3.2 gives the
// apex angle that makes the height this area). A roof never marks its own two
// sites (the thesis keeps them off with the stencil).
//
// TRIANGLE writes the area as depth and the pair as colour; the depth test
// keeps the smallest or largest per site. SIDES keeps, per pair and per side of
// its line, the nearest or farthest site with a 64-bit atomic min or max of
// (area bits, site) in the third buffer: the per-diagonal passes of §7.3.4 in
// one pass.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#ifdef SIDES
#extension GL_EXT_shader_atomic_int64 : require
#endif
#include "roof.glsl"

layout(location = 0) flat in uvec3 pair;

// The site drawn in each pixel, row-major, NO_SITE where none is.
layout(std430, set = 0, binding = 1) readonly buffer Owners {
    uint site_at[];
};

#ifdef SIDES
// Two keys per pair: the left side (counter-clockwise of i -> j), then the right.
layout(std430, set = 0, binding = 2) coherent buffer Best {
    uint64_t best[];
};
#else
layout(location = 0) out uint out_pair;
#endif

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint s = site_at[pixel.y * uint(roof.size.x) + pixel.x];
    if (s == NO_SITE || s == pair.x || s == pair.y) {
        discard;
    }
    dvec2 p = position[pair.x];
    dvec2 a = position[pair.y] - p;
    dvec2 b = position[s] - p;
    double cross = a.x * b.y - a.y * b.x;
    double area = 0.5lf * abs(cross);
    if (roof.bound > 0.0 && area > double(roof.bound)) {
        discard;
    }
    float z = float(area * double(roof.depth_scale));
#ifdef SIDES
    uint64_t key = (uint64_t(floatBitsToUint(z)) << 32) | uint64_t(s);
    // A site whose area is within the double products' rounding (2^-50 of
    // the diagonal squared) of zero may lie on either side, or on the line:
    // it goes to both, and the CPU decides it exactly.
    bool near_line = area <= dot(dvec2(roof.size), dvec2(roof.size)) / 1125899906842624.0lf;
    for (uint side = 0u; side < 2u; side++) {
        if (near_line || (cross > 0.0lf) == (side == 0u)) {
            uint slot = 2u * pair.z + side;
            if (roof.maximum != 0u) {
                atomicMax(best[slot], key);
            } else {
                atomicMin(best[slot], key);
            }
        }
    }
#else
    gl_FragDepth = z;
    out_pair = pair.z;
#endif
}
