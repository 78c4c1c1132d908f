#version 460
// One pass of jump flooding (Rong and Tan 2006): every pixel looks at the
// pixels `step` away in the eight directions and keeps the nearest of the
// seeds they know. Pixels hold their seed's position packed as x | y << 16
// (NO_SEED where none is known yet); ties go to the seed with the smaller
// (x, y), as in the flooding order. Fast and approximate: a pixel can miss its
// nearest seed when no chain of steps leads to it.
layout(local_size_x = 64) in;

layout(push_constant) uniform Pass {
    ivec2 size;
    int step;
    uint first;
} pass;

layout(set = 0, binding = 0) readonly buffer Before {
    uint before[];
};
layout(set = 0, binding = 1) writeonly buffer After {
    uint after[];
};

const uint NO_SEED = 0xFFFFFFFFu;

// The better of the best so far and the seed `step` away in direction d.
uvec2 consider(uvec2 best, ivec2 p, ivec2 d) {
    ivec2 q = p + d * pass.step;
    bool inside = q.x >= 0 && q.y >= 0 && q.x < pass.size.x && q.y < pass.size.y;
    uint seed = inside ? before[q.y * pass.size.x + q.x] : NO_SEED;
    ivec2 s = ivec2(int(seed & 0xFFFFu), int(seed >> 16));
    ivec2 o = s - p;
    uint d2 = uint(o.x * o.x + o.y * o.y);
    // Order by distance, then by x, then by y: (x, y) packs as y << 16 | x,
    // so compare x first explicitly.
    uint key = (seed & 0xFFFFu) << 16 | (seed >> 16);
    uint best_key = (best.y & 0xFFFFu) << 16 | (best.y >> 16);
    bool better = seed != NO_SEED
        && (best.y == NO_SEED || d2 < best.x || (d2 == best.x && key < best_key));
    return better ? uvec2(d2, seed) : best;
}

void main() {
    uint k = pass.first + gl_GlobalInvocationID.x;
    uint pixels = uint(pass.size.x * pass.size.y);
    if (k < pixels) {
        ivec2 p = ivec2(int(k) % pass.size.x, int(k) / pass.size.x);
        uvec2 best = uvec2(0xFFFFFFFFu, NO_SEED);
        best = consider(best, p, ivec2(0, 0));
        best = consider(best, p, ivec2(-1, -1));
        best = consider(best, p, ivec2(0, -1));
        best = consider(best, p, ivec2(1, -1));
        best = consider(best, p, ivec2(-1, 0));
        best = consider(best, p, ivec2(1, 0));
        best = consider(best, p, ivec2(-1, 1));
        best = consider(best, p, ivec2(0, 1));
        best = consider(best, p, ivec2(1, 1));
        after[k] = best.y;
    }
}
