// Saddle roofs (thesis §7.3), shared by roof.vert and roof.frag; see
// src/algorithms/area.rs.
layout(push_constant) uniform Roof {
    // Picture size in pixels.
    vec2 size;
    // Largest area (pixels squared) a roof reaches across to; 0: the whole picture.
    float bound;
    // Depth per unit of area (pixels squared).
    float depth_scale;
    // 1: keep the largest areas (roof.frag's SIDES), 0: the smallest.
    uint maximum;
    // 1: the roof covers only the strip beside its segment (a triangle is found
    // by the roof of its longest edge, whose opposite vertex projects into the
    // edge); 0: the strip beside the whole line.
    uint segment;
} roof;

// The sites in picture pixels, in double precision: the area of a long thin
// triangle is a small difference of large products.
layout(std430, set = 0, binding = 0) readonly buffer Sites {
    dvec2 position[];
};

const uint NO_SITE = 0xFFFFFFFFu;

// Instance k is the pair (i, j), i < j, with k = j (j - 1) / 2 + i.
uvec2 pair_of(uint k) {
    uint j = uint(floor((1.0lf + sqrt(1.0lf + 8.0lf * double(k))) * 0.5lf));
    // Rounding can put j one off either way.
    if (j * (j - 1u) / 2u > k) {
        j -= 1u;
    }
    if ((j + 1u) * j / 2u <= k) {
        j += 1u;
    }
    return uvec2(k - j * (j - 1u) / 2u, j);
}
