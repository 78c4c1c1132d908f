// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP METRIC_LP_SUM
#version 460
// The lower envelope of exact cones without drawing the cones: one triangle
// over the target (picture.vert), and each fragment takes the nearest of the
// sites listed for its screen tile: every site whose region's box meets the
// tile, or under L_p and L-infinity every site within the tile's cover bound.
// A pixel's nearest site is among them, so the envelope is exact without a
// truncation test. On a software rasterizer this trades the setup of one
// footprint per cone, and the depth test and writes of every overlapping
// fragment, for a short loop per pixel.
//
// Records are texels of an image (RECORD_ROW to a row): first one per tile,
// row-major over the target's tiles of TILE_SIDE pixels, holding (first texel
// of the tile's sites, their number); then the tiles' sites. Where keys take
// powers (METRIC_LP*), a texel per site: x, y in picture pixels and the
// smallest key of a pixel of the tile from the site, as float bits, and the
// site id, each tile's by that smallest key. Else two per pair of sites, by
// id: (x, y, x, y) as float bits and (0, 0, id, id), a tile with an odd number
// repeating its last, so that the loop reads ids only for the nearest. An
// image rather than a storage buffer because lavapipe loads images with one
// gather.
#include "common.glsl"

// Both as in src/algorithms/voronoi.rs (SCREEN_TILE_SIDE, RECORD_ROW).
const uint TILE_SIDE = 8u;
const uint RECORD_ROW = 4096u;

layout(set = 0, binding = 3, rgba32ui) uniform readonly uimage2D records;
layout(location = 0) out uint out_id;

uvec4 record(uint r) {
    return imageLoad(records, ivec2(r % RECORD_ROW, r / RECORD_ROW));
}

#if defined(METRIC_LP) || defined(METRIC_LP_SUM)
#define ORDERED
#else
// A bound on the error of the key of offset d from site s, both float32,
// against the key of the exact offset from the site's double: the site
// rounds by at most 2^-24 |s| per coordinate, the offset by 2^-24 |d|, the
// key by 2^-23 of itself (L2: two products and a sum); each bound doubled
// for the rounding of this computation.
float key_error(vec2 s, vec2 d, float key) {
    vec2 e = (abs(s) + abs(d)) * 2.4e-7 + 1.0e-30;
#ifdef METRIC_L2
    return 2.0 * dot(abs(d), e) + dot(e, e) + key * 4.8e-7;
#else
    return e.x + e.y + key * 4.8e-7;
#endif
}
#endif

void main() {
    uvec2 tile = uvec2(gl_FragCoord.xy) / TILE_SIDE;
    uint across = (uint(picture.size.x) + TILE_SIDE - 1u) / TILE_SIDE;
    uvec2 sites = record(tile.y * across + tile.x).xy;
    if (sites.y == 0u) {
        discard;
    }
    vec2 p = fragment_pixel();
    float best = 3.0e38;
#ifdef ORDERED
    uint best_id = 0u;
    // Sites come by the smallest key they can have in the tile: once that
    // exceeds the nearest key so far, no later site can win. Of equal keys the
    // smallest id wins, whatever the order of the list, so that every tiling
    // of the picture resolves ties alike.
    for (uint r = sites.x; r < sites.x + sites.y; r++) {
        uvec4 site = record(r);
        if (uintBitsToFloat(site.z) > best) {
            break;
        }
        float key = metric_key(p - uintBitsToFloat(site.xy));
        if (key < best || (key == best && site.w < best_id)) {
            best = key;
            best_id = site.w;
        }
    }
#else
    // Sites come by id: the first of equal keys has the smallest, whatever
    // the tiling of the picture. The pair of the nearest (its first texel,
    // from the tile's first) and which of the two it is (the low bit); and
    // the runner-up's key and error bound.
    uint best_slot = 0u;
    vec2 best_site = vec2(0.0);
    float second = 3.0e38;
    vec2 second_site = vec2(0.0);
    for (uint r = sites.x; r < sites.x + sites.y; r += 2u) {
        vec4 xy = uintBitsToFloat(record(r));
        // An odd list repeats its last site, which is no runner-up to itself.
        bool last = r + 2u >= sites.x + sites.y;
        uint halves = last && record(r + 1u).z == record(r + 1u).w ? 1u : 2u;
        for (uint half_ = 0u; half_ < halves; half_++) {
            vec2 site = half_ == 0u ? xy.xy : xy.zw;
            float key = metric_key(p - site);
            if (key < best) {
                second = best;
                second_site = best_site;
                best = key;
                best_slot = (r - sites.x) | half_;
                best_site = site;
            } else if (key < second) {
                second = key;
                second_site = site;
            }
        }
    }
    uvec4 ids = record(sites.x + (best_slot & ~1u) + 1u);
    uint best_id = (best_slot & 1u) == 0u ? ids.z : ids.w;
    // Asked for the second level too (levels 2): a runner-up within the two
    // keys' error bounds may be the nearest of the unrounded sites, or tie it,
    // so the top bit marks the pixel for the exact check
    // (src/algorithms/certify.rs).
    if (picture.levels == 2u && second < 3.0e38
            && second - best <= key_error(best_site, p - best_site, best)
                                 + key_error(second_site, p - second_site, second)) {
        best_id |= 0x80000000u;
    }
#endif
    gl_FragDepth = best * picture.fragment_depth_scale;
    out_id = best_id;
}
