// variants: METRIC_L2 METRIC_L1 METRIC_LINF METRIC_LP METRIC_LP_SUM
#version 460
// pixgeo's span counting of the potential areas (thesis §3.12.3 on the device).
// Lavapipe performs atomics lane by lane, so their number sets the pace: each
// source pixel's disc is cut into parts that take few of them, in seven
// difference pictures that settle_sums.comp sums along their directions.
//
// Offsets (x, y) from the disc's centre; w(d) is the disc's half-width in row d,
// and by the ball's symmetry also its half-height in column d. With 0 <= b <= A:
// - the core, the octagon |x| <= A, |y| <= A, |x| + |y| <= C = A + b: a
//   rectangle of 2D differences (rows |y| <= b) and, for the rows b < |y| <= A,
//   row ends that run along diagonals (four runs of two entries each);
// - caps beyond the core's sides: the rows A < |y| <= m and the columns
//   A < |x| <= m, each a whole span of the disc (two entries);
// - caps beyond its diagonal sides: the chords of the lines |x| + |y| = k > C,
//   each a whole span along its diagonal (two entries).
// A = w(b) makes the caps disjoint from the core and from each other: (b, A + 1)
// lies outside the disc, so the diagonal chords stay within |x|, |y| <= A, and
// w(d) <= b for d > A. Chords along diagonals are single spans for convex balls
// with exact keys: L2 and L1. For L2, b = r sin(pi/8) cuts the circle into
// eight equal arcs, and a disc of radius r costs about 1.5 r atomics (4 r with
// row spans alone). L1's disc is its core (b = 0, A = C = m) unless the picture
// cuts m short. The other metrics take the square core A = b = s, the largest
// with (s, s) in the disc: about 2.3 r.
//
// Lavapipe (Mesa 22.3) ends every loop of an invocation after 65535 iterations in
// total. The walks below take at most about 2 m + 11 (m - A for A, m - A for
// the caps beyond the sides, b for their half-widths, and the diagonal caps end
// by k = 2 s + 2, where their middle point leaves the disc; s <= A), and m is
// below the picture's longer side: sides up to 16384 pixels stay below that.
#include "settle.glsl"

layout(local_size_x = 64) in;

// The difference pictures, each of the picture's size, row-major.
// Row differences: prefix sums along rows give counts.
layout(set = 0, binding = 1) buffer Rows { int rows[]; };
// Summed down the columns, then as row differences.
layout(set = 0, binding = 2) buffer Corners { int corners[]; };
// Summed along the lines x + y = c (downwards), then as row differences.
layout(set = 0, binding = 3) buffer FallingRuns { int falling_runs[]; };
// Summed along the lines x - y = c (downwards), then as row differences.
layout(set = 0, binding = 4) buffer RisingRuns { int rising_runs[]; };
// Column differences: prefix sums down the columns give counts.
layout(set = 0, binding = 5) buffer Columns { int columns[]; };
// Differences along the lines x + y = c (downwards).
layout(set = 0, binding = 6) buffer FallingChords { int falling_chords[]; };
// Differences along the lines x - y = c (downwards).
layout(set = 0, binding = 7) buffer RisingChords { int rising_chords[]; };

int at(int x, int y) {
    return y * settle.size.x + x;
}

// Row differences land at x < 0 as at x = 0 and vanish at x >= width.

// Pixels x - w .. x + w of row y (0 <= x < width).
void add_row_span(int y, int x, int w) {
    if (y >= 0 && y < settle.size.y) {
        atomicAdd(rows[at(max(x - w, 0), y)], 1);
        if (x + w + 1 < settle.size.x) {
            atomicAdd(rows[at(x + w + 1, y)], -1);
        }
    }
}

// Pixels y - w .. y + w of column x (0 <= y < height).
void add_column_span(int x, int y, int w) {
    if (x >= 0 && x < settle.size.x) {
        atomicAdd(columns[at(x, max(y - w, 0))], 1);
        if (y + w + 1 < settle.size.y) {
            atomicAdd(columns[at(x, y + w + 1)], -1);
        }
    }
}

// Row differences `value` at column x of rows y0 .. y1, as 2D differences
// (x < width; x < 0 stands for 0).
void add_column_run(int x, int y0, int y1, int value) {
    y0 = max(y0, 0);
    y1 = min(y1, settle.size.y - 1);
    if (y0 <= y1) {
        atomicAdd(corners[at(max(x, 0), y0)], value);
        if (y1 + 1 < settle.size.y) {
            atomicAdd(corners[at(max(x, 0), y1 + 1)], -value);
        }
    }
}

// The lines x = c + dir y: dir -1 falls (x + y = c), dir 1 rises (x - y = c).
// Their first and last rows inside the picture (empty if first > last).
ivec2 line_rows(int c, int dir) {
    ivec2 rows = dir > 0 ? ivec2(-c, settle.size.x - 1 - c) : ivec2(c - settle.size.x + 1, c);
    return ivec2(max(rows.x, 0), min(rows.y, settle.size.y - 1));
}

void add_at_line(bool chord, int dir, int c, int y, int value) {
    int k = at(c + dir * y, y);
    if (chord && dir > 0) {
        atomicAdd(rising_chords[k], value);
    } else if (chord) {
        atomicAdd(falling_chords[k], value);
    } else if (dir > 0) {
        atomicAdd(rising_runs[k], value);
    } else {
        atomicAdd(falling_runs[k], value);
    }
}

// `value` at the points of line (c, dir) in rows y0 .. y1 inside the picture,
// as differences along the line into its chords' or runs' picture.
void add_line_span(bool chord, int dir, int c, int y0, int y1, int value) {
    ivec2 rows = line_rows(c, dir);
    y0 = max(y0, rows.x);
    y1 = min(y1, rows.y);
    if (y0 <= y1) {
        add_at_line(chord, dir, c, y0, value);
        if (y1 < rows.y) {
            add_at_line(chord, dir, c, y1 + 1, -value);
        }
    }
}

// Row differences `value` at the points of line (c, dir) in rows y0 .. y1: the
// run along the line, and where the line has left the picture to the left, a
// run down column 0.
void add_run(int dir, int c, int y0, int y1, int value) {
    // x < 0 below row c (falling) or above row -c (rising).
    if (dir > 0) {
        add_column_run(0, y0, min(y1, -c - 1), value);
    } else {
        add_column_run(0, max(y0, c + 1), y1, value);
    }
    add_line_span(false, dir, c, y0, y1, value);
}

// Pixels of line (c, dir) in rows y0 .. y1, clipped to the picture.
void add_chord(int dir, int c, int y0, int y1) {
    add_line_span(true, dir, c, y0, y1, 1);
}

// The octagon |x| <= a, |y| <= a, |x| + |y| <= a + b around p.
void add_core(ivec2 p, int a, int b) {
    int c = a + b;
    // Rows |y| <= b: columns p.x - a .. p.x + a.
    add_column_run(p.x - a, p.y - b, p.y + b, 1);
    if (p.x + a + 1 < settle.size.x) {
        add_column_run(p.x + a + 1, p.y - b, p.y + b, -1);
    }
    if (a > b) {
        // Rows b < y <= a: columns p.x - c + y .. p.x + c - y; the left ends
        // never pass the right edge, nor the right ends the left one.
        add_run(1, p.x - p.y - c, p.y + b + 1, p.y + a, 1);
        add_run(-1, p.x + p.y + c + 1, p.y + b + 1, p.y + a, -1);
        // Rows -a <= y < -b: columns p.x - c - y .. p.x + c + y.
        add_run(-1, p.x + p.y - c, p.y - a, p.y - b - 1, 1);
        add_run(1, p.x - p.y + c + 1, p.y - a, p.y - b - 1, -1);
    }
}

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= settle.count) {
        return;
    }
    uint index = settle.first + k;
    ivec2 p = ivec2(int(index % uint(settle.size.x)), int(index / uint(settle.size.x)));
    float key = radius_key[index];
    if (key <= 0.0) {
        return;
    }
    // Offsets beyond the farthest edge of the picture add nothing.
    int limit = max(max(p.x, settle.size.x - 1 - p.x), max(p.y, settle.size.y - 1 - p.y));
    // The reach m along the centre row (and column), at most `limit`.
    float r = metric_distance_of_key(key, METRIC_KIND, settle.metric_p);
    int m = int(min(r, float(limit)));
    while (m < limit && in_disc(ivec2(m + 1, 0), key)) {
        ++m;
    }
    while (m >= 0 && !in_disc(ivec2(m, 0), key)) {
        --m;
    }
    if (m < 0) {
        return;
    }
    // The largest square: s, from the distance of the diagonal step (1, 1).
    float diagonal = metric_distance_of_key(
        metric_key_of(vec2(1.0), METRIC_KIND, settle.metric_p), METRIC_KIND, settle.metric_p);
    int s = min(int(r / diagonal) + 1, m);
    while (s > 0 && !in_disc(ivec2(s), key)) {
        --s;
    }
    while (s < m && in_disc(ivec2(s + 1), key)) {
        ++s;
    }
    // The core. L2 and L1: b, then A = w(b) >= w(s) >= s (at most m: beyond
    // `limit` the picture ends, and so do the caps that A would bound). The
    // others: the square A = b = s, whose caps are the rows and columns beyond.
    int b = s;
    int a = s;
    if (METRIC_KIND == 0u || METRIC_KIND == 1u) {
        b = METRIC_KIND == 0u ? min(int(r * 0.38268343 + 0.5), s) : 0;
        a = m;
        while (!in_disc(ivec2(b, a), key)) {
            --a;
        }
    }
    add_core(p, a, b);
    // Caps beyond the sides: w(d) <= b for d > A, and w only decreases.
    int w = b;
    for (int d = a + 1; d <= m; ++d) {
        while (w >= 0 && !in_disc(ivec2(w, d), key)) {
            --w;
        }
        if (w < 0) {
            break;
        }
        add_row_span(p.y - d, p.x, w);
        add_row_span(p.y + d, p.x, w);
        add_column_span(p.x - d, p.y, w);
        add_column_span(p.x + d, p.y, w);
    }
    // Caps beyond the diagonal sides: the chord of x + y = k (x, y > 0) runs
    // from x = u to x = k - u, u growing with k; u > b since (b, A + 1) is out.
    // The chord is empty once its middle point is out, and outside the picture
    // once k > 2 limit. (L1's chords are empty unless m was cut to `limit`.)
    int u = b + 1;
    for (int k = a + b + 1; METRIC_KIND <= 1u && k <= 2 * limit; ++k) {
        if (!in_disc(ivec2(k / 2, k - k / 2), key)) {
            break;
        }
        while (!in_disc(ivec2(u, k - u), key)) {
            ++u;
        }
        add_chord(-1, p.x + p.y + k, p.y + u, p.y + k - u);
        add_chord(-1, p.x + p.y - k, p.y - k + u, p.y - u);
        add_chord(1, p.x - p.y + k, p.y - k + u, p.y - u);
        add_chord(1, p.x - p.y - k, p.y + u, p.y + k - u);
    }
}
