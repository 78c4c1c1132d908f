#version 460
// The nearest site by great circle of every pixel of a band of a
// longitude-latitude grid, as a filter (src/algorithms/great_circle/device.rs):
// one invocation per pixel builds its unit vector from its column's and row's
// cosines and sines and measures the squared chords to the sites listed for
// its tile, which hold every site that can be nearest there. It writes the
// nearest listed site, with the high bit set where the runner-up is within
// the float32 error bound of it: the host decides those pixels exactly.
layout(local_size_x = 64) in;

layout(push_constant) uniform Pass {
    uint width;      // pixels along a row
    uint pixels;     // pixels in the band
    uint tile_side;  // tiles are tile_side pixels square
    uint across;     // tiles along a row
    uint ids;        // where the lists' site ids start in `lists`
} pass;

// The cosine and sine of each column's longitude, then of each band row's
// latitude.
layout(set = 0, binding = 0) readonly buffer Grid {
    vec2 grid[];
};
// Each site's unit vector.
layout(set = 0, binding = 1) readonly buffer Sites {
    vec4 sites[];
};
// Each tile's first entry among the ids, one more for the end, then the ids.
layout(set = 0, binding = 2) readonly buffer Lists {
    uint lists[];
};
layout(set = 0, binding = 3) writeonly buffer Labels {
    uint labels[];
};

const uint UNSURE = 0x80000000u;

// A bound on the error of a squared chord computed here against the exact one
// between the place's and the site's true unit vectors: a component of either
// vector is within 3 * 2^-24 (the host's double rounded, then the product), a
// difference within e = 4.8e-7 with its own rounding, and the sum of the
// squares errs by at most 2 e |d|_1 + 3 e^2 (|d|_1 <= sqrt(3 key)) and its
// roundings, 3 * 2^-24 of itself.
float chord_error(float key) {
    const float e = 4.8e-7;
    return 2.0 * e * sqrt(3.0 * key) + 3.0 * e * e + 2.4e-7 * key;
}

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= pass.pixels) {
        return;
    }
    uint row = k / pass.width;
    uint column = k % pass.width;
    vec2 lon = grid[column];
    vec2 lat = grid[pass.width + row];
    vec3 p = vec3(lat.x * lon.x, lat.x * lon.y, lat.y);
    uint tile = (row / pass.tile_side) * pass.across + column / pass.tile_side;
    // Squared chords are at most 4.
    float best = 8.0;
    float second = 8.0;
    uint best_id = 0u;
    for (uint r = lists[tile]; r < lists[tile + 1u]; r++) {
        uint id = lists[pass.ids + r];
        vec3 d = p - sites[id].xyz;
        float key = dot(d, d);
        if (key < best) {
            second = best;
            best = key;
            best_id = id;
        } else if (key < second) {
            second = key;
        }
    }
    // Doubled for the bound's own arithmetic.
    bool unsure = second - best <= 2.0 * (chord_error(best) + chord_error(second));
    labels[k] = best_id | (unsure ? UNSURE : 0u);
}
