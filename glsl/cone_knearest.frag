// variants: EXACT FAN
// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// k nearest sites per pixel in one pass: each fragment of a cone inserts its key
// (distance, site id) into the pixel's list of the `levels` smallest
// keys, kept sorted in a storage buffer. Insertion walks the list with atomic min,
// carrying the larger key on, so concurrent fragments leave the smallest keys in
// order; equal distances are distinct keys, so multiplicities are kept (thesis
// §3.7) and ties are ordered by id. The distance is the exact squared distance
// (EXACT) or the fan's interpolated height, its depth (FAN, thesis §3.3); both are
// non-negative floats, whose bits order like the numbers.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "common.glsl"

layout(location = 0) flat in uint id;
layout(location = 1) flat in vec3 site;  // (x, y, truncation radius)

layout(std430, set = 0, binding = 0) coherent buffer Levels {
    uint64_t keys[];
};

const uint64_t EMPTY = 0xFFFFFFFFFFFFFFFFul;

void main() {
    vec2 d = fragment_pixel() - site.xy;
    float d2 = dot(d, d);
    if (d2 > site.z * site.z) {
        return;
    }
#ifdef EXACT
    float distance = metric_key(d);
#else
    // Interpolation may dip a hair below the apex's 0; a negative float's bits
    // would order as a huge key.
    float distance = max(gl_FragCoord.z, 0.0);
#endif
    uint64_t key = (uint64_t(floatBitsToUint(distance)) << 32) | uint64_t(id);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint base = (pixel.y * uint(picture.size.x) + pixel.x) * picture.levels;
    // Keys only ever decrease, so a stale last key can only let a fragment in that
    // then finds no place: the shortcut never drops a key that belongs.
    if (key >= keys[base + picture.levels - 1u]) {
        return;
    }
    // Find the key's place among the (possibly stale) sorted keys: the ones before
    // it can only have shrunk since, so the atomic walk may start there.
    uint lo = 0u;
    uint hi = picture.levels - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (keys[base + mid] <= key) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    for (uint i = lo; i < picture.levels && key != EMPTY; i++) {
        key = max(key, atomicMin(keys[base + i], key));
    }
}
