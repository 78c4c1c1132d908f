// variants: R32UI R32F RGBA32F
#version 460
// The thesis's histogram (§1.7): counts of one channel's values in equal bins
// [low + b * width, low + (b + 1) * width), b < bins. Values outside are not counted.
layout(local_size_x = 16, local_size_y = 16) in;

#if defined(R32UI)
layout(set = 0, binding = 0, r32ui) uniform readonly uimage2D picture;
#elif defined(R32F)
layout(set = 0, binding = 0, r32f) uniform readonly image2D picture;
#else
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D picture;
#endif

layout(set = 0, binding = 1) buffer Counts {
    uint count[];
} counts;

layout(push_constant) uniform Bins {
    ivec2 origin;
    ivec2 extent;
    uint channel;
    uint bins;
    // For uint pictures the bit patterns of uints, for float pictures of floats.
    uint low;
    uint width;
} bins;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, bins.extent))) {
        return;
    }
#if defined(R32UI)
    uint v = imageLoad(picture, bins.origin + p).r;
    if (v < bins.low) {
        return;
    }
    uint b = (v - bins.low) / bins.width;
#else
    float v = imageLoad(picture, bins.origin + p)[bins.channel];
    float t = floor((v - uintBitsToFloat(bins.low)) / uintBitsToFloat(bins.width));
    if (!(t >= 0.0) || t >= float(bins.bins)) {
        return;
    }
    uint b = uint(t);
#endif
    if (b < bins.bins) {
        atomicAdd(counts.count[b], 1u);
    }
}
