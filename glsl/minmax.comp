// variants: R32UI R32F RGBA32F
#version 460
// The thesis's minmax (§1.7): per channel minimum and maximum over a rectangle of
// the picture. Floats are mapped to order-preserving uints so that atomicMin and
// atomicMax work on them; the host maps them back.
layout(local_size_x = 16, local_size_y = 16) in;

#if defined(R32UI)
layout(set = 0, binding = 0, r32ui) uniform readonly uimage2D picture;
#elif defined(R32F)
layout(set = 0, binding = 0, r32f) uniform readonly image2D picture;
#else
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D picture;
#endif

layout(set = 0, binding = 1) buffer Result {
    uint minimum[4];
    uint maximum[4];
} result;

layout(push_constant) uniform Region {
    ivec2 origin;
    ivec2 extent;
} region;

shared uint group_min[4];
shared uint group_max[4];

uint ordered(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

void main() {
    uint lane = gl_LocalInvocationIndex;
    if (lane < 4u) {
        group_min[lane] = 0xffffffffu;
        group_max[lane] = 0u;
    }
    barrier();

    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(p, region.extent))) {
#if defined(R32UI)
        uvec4 v = uvec4(imageLoad(picture, region.origin + p).r, 0u, 0u, 0u);
        const uint channels = 1u;
#elif defined(R32F)
        uvec4 v = uvec4(ordered(imageLoad(picture, region.origin + p).r), 0u, 0u, 0u);
        const uint channels = 1u;
#else
        vec4 f = imageLoad(picture, region.origin + p);
        uvec4 v = uvec4(ordered(f.r), ordered(f.g), ordered(f.b), ordered(f.a));
        const uint channels = 4u;
#endif
        for (uint c = 0u; c < channels; ++c) {
            atomicMin(group_min[c], v[c]);
            atomicMax(group_max[c], v[c]);
        }
    }
    barrier();

    if (lane < 4u) {
        atomicMin(result.minimum[lane], group_min[lane]);
        atomicMax(result.maximum[lane], group_max[lane]);
    }
}
