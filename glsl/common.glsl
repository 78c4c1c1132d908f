// Push constants shared by the cone programs (see src/machine/pipelines.rs).
layout(push_constant) uniform Picture {
    // Picture size in pixels; pixel (i, j) is centred at world (i, j).
    vec2 size;
    // Depth of a fan vertex = its cone height times this (0 for exact cones).
    float vertex_depth_scale;
    // Depth written by an exact cone = squared distance times this.
    float fragment_depth_scale;
} picture;
