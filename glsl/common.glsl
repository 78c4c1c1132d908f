// Push constants shared by the cone programs (see src/algorithms/cones.rs, ConePush).
layout(push_constant) uniform Picture {
    // Target size in pixels.
    vec2 size;
    // The picture pixel shown at the target's pixel (0, 0): a tile's origin. Picture
    // pixel (i, j) is centred at pixel coordinates (i, j).
    vec2 offset;
    // Depth of a fan vertex = its cone height times this (0 for exact cones).
    float vertex_depth_scale;
    // Depth written by an exact cone = squared distance times this.
    float fragment_depth_scale;
    // Length of each pixel's list of nearest sites (cone_knearest.frag,
    // cone_tiles.frag).
    uint levels;
    // The distance function of exact cones (geometry/metric.rs): 0 Euclidean,
    // 1 L1, 2 L-infinity, 3 L_p with p = metric_p, 4 the same with keys that are
    // sums of powers (DepthKey).
    uint metric;
    float metric_p;
} picture;

#ifdef STAGE_FRAG
#include "metric.glsl"

#ifndef METRIC_KIND
#define METRIC_KIND picture.metric
#endif

// The metric's key of offset d (metric.glsl).
float metric_key(vec2 d) {
    return metric_key_of(d, METRIC_KIND, picture.metric_p);
}

// The key of a distance r (metric_key of an offset of that length).
float metric_key_of_distance(float r) {
    if (METRIC_KIND == 0u) {
        return r * r;
    } else if (METRIC_KIND == 4u) {
        return pow(r, picture.metric_p);
    }
    return r;
}

// The largest a with a |x|_2 <= |x| for every offset x.
float metric_euclidean_lower() {
    if (METRIC_KIND == 2u) {
        return 0.70710677;
    } else if (METRIC_KIND == 3u && picture.metric_p > 2.0) {
        return pow(2.0, 1.0 / picture.metric_p - 0.5);
    }
    return 1.0;
}

// The pixel coordinates of the fragment's pixel centre.
vec2 fragment_pixel() {
    return gl_FragCoord.xy - 0.5 + picture.offset;
}
#else
// Pixel coordinates (i, j) -> normalized device coordinates of the target.
vec2 to_ndc(vec2 p) {
    return (p - picture.offset + 0.5) / picture.size * 2.0 - 1.0;
}
#endif
