// variants: R32UI R32F RGBA32F
#version 460
// The thesis's minmax (§1.7): per channel minimum and maximum over a rectangle of
// the picture. Each invocation walks a column strip of ROWS pixels keeping its
// minimum and maximum in registers, then makes one atomic update; no shared memory
// and no barrier, which software rasterizers execute slowly. Floats are mapped to
// order-preserving uints so that atomicMin/atomicMax work on them; the host maps
// them back.
layout(local_size_x = 64) in;

const int ROWS = 64;

#if defined(R32UI)
layout(set = 0, binding = 0, r32ui) uniform readonly uimage2D picture;
const uint CHANNELS = 1u;
#elif defined(R32F)
layout(set = 0, binding = 0, r32f) uniform readonly image2D picture;
const uint CHANNELS = 1u;
#else
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D picture;
const uint CHANNELS = 4u;
#endif

layout(set = 0, binding = 1) buffer Result {
    uint minimum[4];
    uint maximum[4];
} result;

layout(push_constant) uniform Region {
    ivec2 origin;
    ivec2 extent;
} region;

uint ordered(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

uvec4 load(ivec2 p) {
#if defined(R32UI)
    return uvec4(imageLoad(picture, p).r, 0u, 0u, 0u);
#elif defined(R32F)
    return uvec4(ordered(imageLoad(picture, p).r), 0u, 0u, 0u);
#else
    vec4 f = imageLoad(picture, p);
    return uvec4(ordered(f.r), ordered(f.g), ordered(f.b), ordered(f.a));
#endif
}

void main() {
    int x = int(gl_GlobalInvocationID.x);
    int y0 = int(gl_GlobalInvocationID.y) * ROWS;
    if (x >= region.extent.x || y0 >= region.extent.y) {
        return;
    }
    int y1 = min(y0 + ROWS, region.extent.y);
    uvec4 lo = uvec4(0xffffffffu);
    uvec4 hi = uvec4(0u);
    for (int y = y0; y < y1; ++y) {
        uvec4 v = load(region.origin + ivec2(x, y));
        lo = min(lo, v);
        hi = max(hi, v);
    }
    for (uint c = 0u; c < CHANNELS; ++c) {
        atomicMin(result.minimum[c], lo[c]);
        atomicMax(result.maximum[c], hi[c]);
    }
}
