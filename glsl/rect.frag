// variants: UINT FLOAT
#version 460
// Writes the rectangle's constant value to a uint or float colour target.
layout(push_constant) uniform Rect {
    vec2 size;
    vec2 lo;
    vec2 hi;
    float depth;
    uint pad;
    vec4 value;
} rect;

#ifdef UINT
layout(location = 0) out uvec4 out_value;
void main() { out_value = floatBitsToUint(rect.value); }
#else
layout(location = 0) out vec4 out_value;
void main() { out_value = rect.value; }
#endif
