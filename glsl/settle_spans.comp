// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP
#version 460
// pixgeo's span counting of the potential areas (thesis §3.12.3 on the device):
// each source pixel walks the border of its disc row by row and adds +1 where the
// disc's row span begins and -1 just after it ends; row_prefix.comp sums each row.
// The walk visits 2r rows instead of the disc's pi r^2 pixels.
//
// Lavapipe (Mesa 22.3) ends every loop of an invocation after 65535 iterations in
// total; the walk takes at most three per row of the picture, so pictures up to
// 16384 rows stay below that.
#include "settle.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 1) buffer Differences {
    int difference[];
};

void add_span(int y, int x, int m) {
    if (y >= 0 && y < settle.size.y) {
        int row = y * settle.size.x;
        atomicAdd(difference[row + max(x - m, 0)], 1);
        if (x + m + 1 < settle.size.x) {
            atomicAdd(difference[row + x + m + 1], -1);
        }
    }
}

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= settle.count) {
        return;
    }
    uint index = settle.first + k;
    ivec2 p = ivec2(int(index % uint(settle.size.x)), int(index / uint(settle.size.x)));
    float key = radius_key[index];
    // Offsets beyond the picture's extent add nothing.
    int limit = max(settle.size.x, settle.size.y);
    int m = -1;
    if (key > 0.0) {
        float r = metric_distance_of_key(key, METRIC_KIND, settle.metric_p);
        m = int(min(r, float(limit)));
        while (m < limit && in_disc(ivec2(m + 1, 0), key)) {
            ++m;
        }
    }
    int rows = max(p.y, settle.size.y - 1 - p.y);
    for (int dy = 0; dy <= rows && m >= 0; ++dy) {
        // The ball shrinks away from the centre row: the reach only decreases.
        while (m >= 0 && !in_disc(ivec2(m, dy), key)) {
            --m;
        }
        if (m >= 0) {
            add_span(p.y + dy, p.x, m);
            if (dy > 0) {
                add_span(p.y - dy, p.x, m);
            }
        }
    }
}
