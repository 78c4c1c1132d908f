#version 460
// One triangle over the whole target, for fragment shaders that find their
// own work from the pixel they shade (nearest_tiles.frag).

void main() {
    // (-1, -1), (3, -1), (-1, 3): the triangle's clipped part is the target.
    vec2 corner = vec2(float((gl_VertexIndex & 1) * 4 - 1), float((gl_VertexIndex & 2) * 2 - 1));
    gl_Position = vec4(corner, 0.0, 1.0);
}
