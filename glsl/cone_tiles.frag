// variants: K1 K2 K3 K4 K6 K8 K12 K16 K24 K32
// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// The k lowest layers of the cones binned to a screen tile (tiles.vert), per
// fragment: a sorted list of (metric key, id) in registers, then one plain
// store per level, since tiles do not overlap. Cones are texels of the records
// image (x, y, squared truncation radius as float bits, site id; RECORD_ROW
// texels to a row), sorted by distance from the tile's centre, so the list
// mostly fills in order. Keys as in cone_knearest.frag: ties by id,
// multiplicities kept. The records are an image rather than a storage buffer
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
layout(location = 1) flat in vec3 tile;    // centre, half diagonal

// Keys as 64-bit little-endian words, without needing 64-bit integers: the id,
// then the squared distance's bits.
layout(std430, set = 0, binding = 0) writeonly buffer Levels {
    uint keys[];
};

layout(set = 0, binding = 3, rgba32ui) uniform readonly uimage2D records;

// Texels per row of the records image (higher_order.rs: RECORD_ROW).
const uint RECORD_ROW = 4096u;

bool before(float d2, uint id, float other_d2, uint other_id) {
    return d2 < other_d2 || (d2 == other_d2 && id < other_id);
}

void main() {
    vec2 p = fragment_pixel();
    float best_d2[LEVELS];
    uint best_id[LEVELS];
    for (uint l = 0u; l < LEVELS; l++) {
        best_d2[l] = 3.0e38;
        best_id[l] = NO_SITE;
    }
    for (uint i = 0u; i < cones.y; i++) {
        uint r = cones.x + i;
        uvec4 cone = imageLoad(records, ivec2(r % RECORD_ROW, r / RECORD_ROW));
        vec2 site = uintBitsToFloat(cone.xy);
        // Cones come by distance from the tile's centre: once that distance, less
        // the pixel's own offset from the centre, passes the pixel's last key, no
        // later cone can enter the list.
        float reach = (distance(site, tile.xy) - tile.z) * metric_euclidean_lower();
        if (reach > 0.0 && metric_key_of_distance(reach) > best_d2[LEVELS - 1u]) {
            break;
        }
        vec2 d = p - site;
        float d2 = metric_key(d);
        uint id = cone.w;
        if (dot(d, d) > uintBitsToFloat(cone.z)
            || !before(d2, id, best_d2[LEVELS - 1u], best_id[LEVELS - 1u])) {
            continue;
        }
        // Insert by carrying the larger key down the list: no dynamic index.
        for (uint l = 0u; l < LEVELS; l++) {
            bool smaller = before(d2, id, best_d2[l], best_id[l]);
            float kept_d2 = smaller ? d2 : best_d2[l];
            uint kept_id = smaller ? id : best_id[l];
            d2 = smaller ? best_d2[l] : d2;
            id = smaller ? best_id[l] : id;
            best_d2[l] = kept_d2;
            best_id[l] = kept_id;
        }
    }
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint k = picture.levels;
    uint base = (pixel.y * uint(picture.size.x) + pixel.x) * k * 2u;
    for (uint l = 0u; l < LEVELS; l++) {
        if (l < k) {
            bool empty = best_id[l] == NO_SITE;
            keys[base + 2u * l] = best_id[l];
            keys[base + 2u * l + 1u] = empty ? 0xFFFFFFFFu : floatBitsToUint(best_d2[l]);
        }
    }
}
