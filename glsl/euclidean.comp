#version 460
// The exact Euclidean colouring of seed pixels, separably (Meijster, Roerdink
// and Hesselink 2000): phase 0 gives every pixel the nearest seed of its own
// column, phase 1 takes the lower envelope of the columns' parabolas
// (x - c)^2 + h_c along each row. Phase 2 marks the roots of debris: pixels
// with no neighbour of their colour nearer to their seed in the flooding's
// order, the seed's own pixel excepted. Ties go to the smaller (x, y) of the seed,
// the flooding's order: the upper seed within a column, the left column
// within a row (integer arithmetic, floors at the envelope's breakpoints).
// Phase 3 instead writes each pixel's squared distance to its seed plus one,
// times `scale`, as a float: a distance picture to copy into a depth buffer,
// every pixel above a depth of 0 (which a mask writes).
//
// Buffer 0 holds the seed index per pixel (NONE where there is none), then
// phase 0's result (the row of each pixel's column seed), then each seed's
// position packed as x | y << 16. Buffer 1 receives the colouring and then
// phase 1's segment starts, which phase 2 overwrites with the roots (1) and
// other pixels (0). Sides up to 16000 keep
// every square in 32 bits and a row's loops under lavapipe's 65535
// iterations per invocation (at most 4 x width).
layout(local_size_x = 64) in;

layout(push_constant) uniform Pass {
    ivec2 size;
    int phase;
    float scale;
} pass;

layout(set = 0, binding = 0) buffer Seeds {
    uint seeds[];
};
layout(set = 0, binding = 1) buffer Colours {
    uint colours[];
};

const uint NONE = 0xFFFFFFFFu;
const int ROWS = 64;

// The nearest seed's row along column x, for every row.
void columns(int x) {
    int w = pass.size.x;
    int h = pass.size.y;
    uint pixels = uint(w * h);
    uint above = NONE;
    for (int y = 0; y < h; ++y) {
        if (seeds[y * w + x] != NONE) {
            above = uint(y);
        }
        seeds[pixels + uint(y * w + x)] = above;
    }
    uint below = NONE;
    for (int y = h - 1; y >= 0; --y) {
        if (seeds[y * w + x] != NONE) {
            below = uint(y);
        }
        uint up = seeds[pixels + uint(y * w + x)];
        // The lower seed only when strictly nearer.
        bool lower = below != NONE && (up == NONE || int(below) - y < y - int(up));
        if (lower) {
            seeds[pixels + uint(y * w + x)] = below;
        }
    }
}

int floor_div(int a, int b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The envelope of the parabolas of row y's column seeds; the stack of columns
// lives in the row's colours, the segment starts in the second half.
void row(int y) {
    int w = pass.size.x;
    uint pixels = uint(w * pass.size.y);
    uint base = uint(y * w);
    int top = -1;
    for (int u = 0; u < w; ++u) {
        uint g = seeds[pixels + base + uint(u)];
        if (g != NONE) {
            int hu = (y - int(g)) * (y - int(g));
            bool popping = true;
            while (top >= 0 && popping) {
                int c = int(colours[base + uint(top)]);
                int start = int(colours[pixels + base + uint(top)]);
                int gc = int(seeds[pixels + base + uint(c)]);
                int hc = (y - gc) * (y - gc);
                int fc = (start - c) * (start - c) + hc;
                int fu = (start - u) * (start - u) + hu;
                if (fc > fu) {
                    top -= 1;
                } else {
                    popping = false;
                }
            }
            if (top < 0) {
                top = 0;
                colours[base] = uint(u);
                colours[pixels + base] = 0u;
            } else {
                int c = int(colours[base + uint(top)]);
                int gc = int(seeds[pixels + base + uint(c)]);
                int hc = (y - gc) * (y - gc);
                int start = 1 + floor_div(u * u - c * c + hu - hc, 2 * (u - c));
                if (start < w) {
                    top += 1;
                    colours[base + uint(top)] = uint(u);
                    colours[pixels + base + uint(top)] = uint(start);
                }
            }
        }
    }
    for (int x = w - 1; x >= 0; --x) {
        int c = int(colours[base + uint(top)]);
        int start = int(colours[pixels + base + uint(top)]);
        uint g = seeds[pixels + base + uint(c)];
        colours[base + uint(x)] = seeds[g * uint(w) + uint(c)];
        if (x == start) {
            top -= 1;
        }
    }
}

// Whether pixel a (index k) of colour i is a root: not the seed, and no
// neighbour of colour i comes before it in the order (squared distance, then
// x, then y).
void root(ivec2 a, uint k) {
    int w = pass.size.x;
    uint pixels = uint(w * pass.size.y);
    uint i = colours[k];
    uint packed = seeds[2u * pixels + i];
    ivec2 s = ivec2(int(packed & 0xFFFFu), int(packed >> 16));
    ivec2 da = a - s;
    int pa = da.x * da.x + da.y * da.y;
    bool earlier = false;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 b = a + ivec2(dx, dy);
            bool inside = (dx != 0 || dy != 0) && b.x >= 0 && b.y >= 0 && b.x < w
                && b.y < pass.size.y;
            if (inside && colours[b.y * w + b.x] == i) {
                ivec2 db = b - s;
                int pb = db.x * db.x + db.y * db.y;
                earlier = earlier || pb < pa || (pb == pa && (b.x < a.x || (b.x == a.x && b.y < a.y)));
            }
        }
    }
    colours[pixels + k] = (a != s && !earlier) ? 1u : 0u;
}

// Pixel k's squared distance to its seed plus one, scaled, in place of phase
// 1's segment starts.
void distance(ivec2 a, uint k) {
    uint pixels = uint(pass.size.x * pass.size.y);
    uint packed = seeds[2u * pixels + colours[k]];
    ivec2 d = a - ivec2(int(packed & 0xFFFFu), int(packed >> 16));
    colours[pixels + k] = floatBitsToUint(float(d.x * d.x + d.y * d.y + 1) * pass.scale);
}

void main() {
    int k = int(gl_GlobalInvocationID.x);
    if (pass.phase == 0 && k < pass.size.x) {
        columns(k);
    }
    if (pass.phase == 1 && k < pass.size.y) {
        row(k);
    }
    // Phases 2 and 3: an invocation per strip of ROWS pixels of a column, over
    // a grid of columns by strips (few workgroups: each costs a CPU device a
    // call of its own).
    ivec2 first = ivec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y * ROWS);
    if (pass.phase >= 2 && first.x < pass.size.x) {
        int rows = min(ROWS, pass.size.y - first.y);
        for (int r = 0; r < rows; ++r) {
            ivec2 a = first + ivec2(0, r);
            uint pixel = uint(a.y * pass.size.x + a.x);
            if (pass.phase == 2) {
                root(a, pixel);
            } else {
                distance(a, pixel);
            }
        }
    }
}
