// Shared by the settle-point programs (src/algorithms/settle.rs): the disc C(p)
// of a pixel p holds the candidate sites t that would win p, dist(t, p) <
// dist(p, its nearest site) (thesis §3.10.3). Both counting methods test
// membership with `in_disc`, so they count the same pixels.
#include "metric.glsl"

layout(push_constant) uniform Settle {
    // Picture size in pixels.
    ivec2 size;
    // The distance function (metric.glsl).
    uint metric;
    float metric_p;
    // The source pixels of this dispatch or draw: row-major indices
    // first .. first + count.
    uint first;
    uint count;
    // The colour channel that counts stencil wrap-arounds (settle_disc.frag).
    uint channel;
} settle;

#ifndef METRIC_KIND
#define METRIC_KIND settle.metric
#endif

// Each pixel's disc radius as a metric key: the key of its nearest site, 0 where
// the pixel does not count (it is already the user's own).
layout(set = 0, binding = 0) readonly buffer Radii {
    float radius_key[];
};

// Whether the candidate at offset d from p lies in C(p) of radius key `key`.
bool in_disc(ivec2 d, float key) {
    return metric_key_of(vec2(d), METRIC_KIND, settle.metric_p) < key;
}

// A bound on the disc's reach along its centre row (a little beyond it, so that
// an inexact pow cannot cut the disc short), at most `limit`; -1 when empty.
int disc_bound(float key, int limit) {
    int m = -1;
    if (key > 0.0) {
        float r = metric_distance_of_key(key, METRIC_KIND, settle.metric_p);
        m = int(min(r * 1.001 + 2.0, float(limit)));
    }
    return m;
}
