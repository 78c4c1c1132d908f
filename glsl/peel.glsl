// The previous level of thesis §3.7's peeling, in the fragment storage buffer:
// words[p] holds pixel p's previous depth (float bits), words[pixels + p] its site.
layout(std430, set = 0, binding = 0) buffer Previous {
    uint words[];
} previous;

uint pixel_index() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    return pixel.y * uint(picture.size.x) + pixel.x;
}

uint pixel_count() {
    return uint(picture.size.x) * uint(picture.size.y);
}
