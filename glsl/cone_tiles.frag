// variants: K1 K2 K3 K4 K6 K8 K12 K16 K24 K32
// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// The k lowest layers of the cones binned to a screen tile (tiles.vert), per
// fragment: a sorted list of (metric key, id) in registers, then one plain
// store of the id per level, since tiles do not overlap. The host computes the
// ids' distances and orders equal ones by id, which halves the stores (lavapipe
// makes them lane by lane). Cones are texels of the records image (x, y, the
// smallest key any pixel of the tile can have as float bits, site id;
// RECORD_ROW texels to a row), sorted by distance from the tile's centre, so
// the list mostly fills in order. No truncation test: the tile's list holds
// every site that is among k nearest of one of its pixels, so the k nearest of
// the list are the pixel's. Equidistant sites each keep a level, so
// multiplicities are kept. The records are an image rather than a storage buffer
// because lavapipe loads a storage buffer lane by lane, an image with one
// gather: four buffer loads per cone took half the time.
#include "common.glsl"

// The list's length is fixed per variant, so that the insertion below unrolls
// into registers; the host picks the shortest variant that holds its levels
// (higher_order.rs: TILE_LEVELS is the longest).
#if defined(K1)
const uint LEVELS = 1u;
#elif defined(K2)
const uint LEVELS = 2u;
#elif defined(K3)
const uint LEVELS = 3u;
#elif defined(K4)
const uint LEVELS = 4u;
#elif defined(K6)
const uint LEVELS = 6u;
#elif defined(K8)
const uint LEVELS = 8u;
#elif defined(K12)
const uint LEVELS = 12u;
#elif defined(K16)
const uint LEVELS = 16u;
#elif defined(K24)
const uint LEVELS = 24u;
#else
const uint LEVELS = 32u;
#endif
const uint NO_SITE = 0xFFFFFFFFu;

layout(location = 0) flat in uvec2 cones;  // first word, count

// The ids of levels 1..k of every pixel, nearest first; NO_SITE where fewer
// than k sites reach it.
layout(std430, set = 0, binding = 0) writeonly buffer Levels {
    uint labels[];
};

layout(set = 0, binding = 3, rgba32ui) uniform readonly uimage2D records;

// Texels per row of the records image (higher_order.rs: RECORD_ROW).
const uint RECORD_ROW = 4096u;

uvec4 record(uint r) {
    return imageLoad(records, ivec2(r % RECORD_ROW, r / RECORD_ROW));
}

float best_d2[LEVELS];
uint best_id[LEVELS];

// Inserts key (d2, id) into levels 0..LAST-1 (LAST a constant) by carrying the
// larger key down the list: no dynamic index, and no test first, since
// lavapipe runs the carry under a mask anyway; a key after the last carries
// through unchanged. Equal keys keep their order of arrival; the host orders
// equal distances by id.
#define INSERT(LAST, d2, id)                          \
    for (uint l = 0u; l < LAST; l++) {                \
        bool smaller = d2 < best_d2[l];               \
        uint kept_id = smaller ? id : best_id[l];     \
        id = smaller ? best_id[l] : id;               \
        best_id[l] = kept_id;                         \
        float kept_d2 = min(d2, best_d2[l]);          \
        d2 = max(d2, best_d2[l]);                     \
        best_d2[l] = kept_d2;                         \
    }

// The list's first LEVELS cones, unrolled: cone I can only reach level I, so
// it carries through I + 1 levels instead of all of them, and nothing can
// leave the list yet.
#define FIRST(I)                                      \
    if (I < LEVELS && I < cones.y) {                  \
        uvec4 cone = record(cones.x + I);             \
        float d2 = metric_key(p - uintBitsToFloat(cone.xy)); \
        uint id = cone.w;                             \
        INSERT(I + 1u, d2, id)                        \
    }

void main() {
    vec2 p = fragment_pixel();
    for (uint l = 0u; l < LEVELS; l++) {
        best_d2[l] = 3.0e38;
        best_id[l] = NO_SITE;
    }
    FIRST(0u)
    FIRST(1u)
    FIRST(2u)
    FIRST(3u)
    FIRST(4u)
    FIRST(5u)
    FIRST(6u)
    FIRST(7u)
    FIRST(8u)
    FIRST(9u)
    FIRST(10u)
    FIRST(11u)
    FIRST(12u)
    FIRST(13u)
    FIRST(14u)
    FIRST(15u)
    FIRST(16u)
    FIRST(17u)
    FIRST(18u)
    FIRST(19u)
    FIRST(20u)
    FIRST(21u)
    FIRST(22u)
    FIRST(23u)
    FIRST(24u)
    FIRST(25u)
    FIRST(26u)
    FIRST(27u)
    FIRST(28u)
    FIRST(29u)
    FIRST(30u)
    FIRST(31u)
    for (uint i = LEVELS; i < cones.y; i++) {
        uvec4 cone = record(cones.x + i);
        // Cones come by distance from the tile's centre, so their smallest keys
        // over the tile rise: once one passes the pixel's last key, no later
        // cone can enter the list.
        if (uintBitsToFloat(cone.z) > best_d2[LEVELS - 1u]) {
            break;
        }
        float d2 = metric_key(p - uintBitsToFloat(cone.xy));
        uint id = cone.w;
        INSERT(LEVELS, d2, id)
    }
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint k = picture.levels;
    uint base = (pixel.y * uint(picture.size.x) + pixel.x) * k;
    for (uint l = 0u; l < LEVELS; l++) {
        if (l < k) {
            labels[base + l] = best_id[l];
        }
    }
}
