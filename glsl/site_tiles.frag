// variants: POINT SEGMENT CIRCLE ARC
// variants: METRIC_L2 METRIC_L1 METRIC_LINF
#version 460
// The lower envelope of sites of one shape without drawing them: one triangle
// over the target (picture.vert), and each fragment takes the lowest weighted
// distance of the sites listed for its screen tile, every site whose smallest
// weighted distance over the tile is within the tile's cover bound (the
// smallest largest weighted distance of a site there), evaluated as
// site_exact.frag does (under L2, L1 or L-infinity).
//
// Records are texels of an image (RECORD_ROW to a row): first one per tile,
// row-major over the target's tiles of TILE_SIDE pixels, holding (first texel
// of the tile's sites, their number); then the tiles' sites, WORDS texels
// each: the shape's words (site_distance.glsl; arcs take two texels) as float
// bits, then (1 / (scale m), a less the smallest a, the smallest weighted
// distance of the site over the tile, as float bits, and the site id). Each
// tile's sites come by that smallest distance, so that a fragment can stop at
// the first that cannot beat its nearest.
#include "common.glsl"
#include "site_distance.glsl"

// Both as in src/algorithms/voronoi.rs (SCREEN_TILE_SIDE, RECORD_ROW).
const uint TILE_SIDE = 8u;
const uint RECORD_ROW = 4096u;

#ifdef ARC
const uint WORDS = 3u;
#else
const uint WORDS = 2u;
#endif

layout(set = 0, binding = 3, rgba32ui) uniform readonly uimage2D records;
layout(location = 0) out uint out_id;

uvec4 record(uint r) {
    return imageLoad(records, ivec2(r % RECORD_ROW, r / RECORD_ROW));
}

void main() {
    uvec2 tile = uvec2(gl_FragCoord.xy) / TILE_SIDE;
    uint across = (uint(picture.size.x) + TILE_SIDE - 1u) / TILE_SIDE;
    uvec2 sites = record(tile.y * across + tile.x).xy;
    if (sites.y == 0u) {
        discard;
    }
    vec2 p = fragment_pixel();
    float best = 3.0e38;
    uint best_id = 0u;
    // Of equal distances the smallest id wins, whatever the order of the list.
    for (uint r = sites.x; r < sites.x + WORDS * sites.y; r += WORDS) {
        uvec4 site = record(r + WORDS - 1u);
        if (uintBitsToFloat(site.z) > best) {
            break;
        }
        vec4 shape0 = uintBitsToFloat(record(r));
#ifdef ARC
        vec4 shape1 = uintBitsToFloat(record(r + 1u));
#else
        const vec4 shape1 = vec4(0.0);
#endif
        vec2 weights = uintBitsToFloat(site.xy);
        float d = site_distance(p, shape0, shape1) * weights.x + weights.y;
        if (d < best || (d == best && site.w < best_id)) {
            best = d;
            best_id = site.w;
        }
    }
    gl_FragDepth = best * picture.fragment_depth_scale;
    out_id = best_id;
}
