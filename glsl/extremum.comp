#version 460
#extension GL_EXT_control_flow_attributes : require
// The smallest and largest value of a float picture (a depth buffer copied to a
// storage buffer) and where they are. Phase 0 takes the minmax (§1.7): each
// invocation walks a column strip of ROWS pixels and makes one atomic update.
// Phase 1 finds the first row-major index holding each extreme. Phase 2 (3)
// lists the indices and values within `within` of the minimum (maximum), as
// many as the list holds. A few words reach the host instead of the picture.
// Phase 0 also leaves each strip's extremes after the list, so that the later
// phases skip the strips that cannot hold what they look for: near an extreme
// that is only a few strips.
layout(local_size_x = 64) in;

const int ROWS = 64;

layout(push_constant) uniform Job {
    ivec2 size;
    int phase;
    float within;
    uint capacity;
    // Nonzero: values are squared distances times this scale, and `within` is
    // a distance.
    float squared_scale;
} job;

layout(set = 0, binding = 0) readonly buffer Values {
    float value[];
};

layout(set = 0, binding = 1) buffer Result {
    // minimum, maximum, first index of the minimum, of the maximum, the list's
    // length, the list of (index, ordered value), each strip's (minimum,
    // maximum)
    uint word[];
} result;

float unordered(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

// Order-preserving uint of a float, without a branch (negative: all bits
// flipped; positive: the sign bit set).
uint ordered(float f) {
    uint u = floatBitsToUint(f);
    return u ^ (uint(-int(u >> 31u)) | 0x80000000u);
}

void main() {
    // One invocation per column strip, strips of a column after each other.
    uint id = gl_GlobalInvocationID.x;
    int x = int(id % uint(job.size.x));
    int y0 = int(id / uint(job.size.x)) * ROWS;
    // No early return: naga loses the scope of values loaded before it.
    if (all(lessThan(ivec2(x, y0), job.size))) {
        int y1 = min(y0 + ROWS, job.size.y);
        // Phase 1 looks for what phase 0 found.
        uint want_lo = result.word[0];
        uint want_hi = result.word[1];
        uint lo = 0xffffffffu;
        uint hi = 0u;
        uint at_lo = 0xffffffffu;
        uint at_hi = 0xffffffffu;
        // Phases 2 and 3 keep the values at or below (above) this one.
        float lo_bar = unordered(want_lo) + job.within;
        float hi_bar = unordered(want_hi) - job.within;
        if (job.squared_scale > 0.0) {
            float s = job.squared_scale;
            float d_lo = sqrt(unordered(want_lo) / s) + job.within;
            float d_hi = max(sqrt(unordered(want_hi) / s) - job.within, 0.0);
            lo_bar = d_lo * d_lo * s;
            hi_bar = d_hi * d_hi * s;
        }
        uint bar = job.phase == 2 ? ordered(lo_bar) : ordered(hi_bar);
        uint strip = 5u + 2u * job.capacity + 2u * id;
        bool wanted = job.phase == 0;
        if (job.phase > 0) {
            uint strip_lo = result.word[strip];
            uint strip_hi = result.word[strip + 1u];
            wanted = (job.phase == 1 && (strip_lo == want_lo || strip_hi == want_hi))
                || (job.phase == 2 && strip_lo <= bar) || (job.phase == 3 && strip_hi >= bar);
        }
        if (wanted) {
        // Unrolled: naga's SPIR-V reader loses values carried out of loops.
        [[unroll]] for (int r = 0; r < ROWS; ++r) {
            int y = min(y0 + r, y1 - 1);
            uint index = uint(y * job.size.x + x);
            uint v = ordered(value[index]);
            lo = min(lo, v);
            hi = max(hi, v);
            at_lo = min(at_lo, v == want_lo ? index : 0xffffffffu);
            at_hi = min(at_hi, v == want_hi ? index : 0xffffffffu);
            // Near the maximum, depth 0 (a mask) is never listed.
            bool listed = (job.phase == 2 && v <= bar)
                || (job.phase == 3 && v >= bar && v > ordered(0.0));
            // The clamped rows repeat the last one: list it once.
            if (listed && y0 + r < y1) {
                uint slot = atomicAdd(result.word[4], 1u);
                if (slot < job.capacity) {
                    result.word[5u + 2u * slot] = index;
                    result.word[6u + 2u * slot] = v;
                }
            }
        }
        }
        if (job.phase == 0) {
            result.word[strip] = lo;
            result.word[strip + 1u] = hi;
            atomicMin(result.word[0], lo);
            atomicMax(result.word[1], hi);
        } else if (job.phase == 1) {
            atomicMin(result.word[2], at_lo);
            atomicMin(result.word[3], at_hi);
        }
    }
}
