#version 460
// The potential areas from settle_spans.comp's seven difference pictures, in
// four phases: 0, one invocation per column, sums down the columns; 1, one per
// line x + y = c, sums along it downwards; 2, one per line x - y = c (c + height
// - 1 is the invocation), the same; 3, one per row, sums the row differences
// along the row and adds the counts of the others. The counts replace the row
// differences.
layout(local_size_x = 64) in;

layout(push_constant) uniform Sums {
    ivec2 size;
    uint phase;
} sums;

layout(set = 0, binding = 1) buffer Rows { int rows[]; };
layout(set = 0, binding = 2) buffer Corners { int corners[]; };
layout(set = 0, binding = 3) buffer FallingRuns { int falling_runs[]; };
layout(set = 0, binding = 4) buffer RisingRuns { int rising_runs[]; };
layout(set = 0, binding = 5) buffer Columns { int columns[]; };
layout(set = 0, binding = 6) buffer FallingChords { int falling_chords[]; };
layout(set = 0, binding = 7) buffer RisingChords { int rising_chords[]; };

void main() {
    int i = int(gl_GlobalInvocationID.x);
    int w = sums.size.x;
    int h = sums.size.y;
    if (sums.phase == 0u) {
        if (i >= w) {
            return;
        }
        int run = 0;
        int span = 0;
        for (int k = i; k < w * h; k += w) {
            run += corners[k];
            corners[k] = run;
            span += columns[k];
            columns[k] = span;
        }
    } else if (sums.phase == 1u) {
        if (i >= w + h - 1) {
            return;
        }
        int run = 0;
        int span = 0;
        for (int y = max(0, i - w + 1); y <= min(h - 1, i); ++y) {
            int k = y * w + i - y;
            run += falling_runs[k];
            falling_runs[k] = run;
            span += falling_chords[k];
            falling_chords[k] = span;
        }
    } else if (sums.phase == 2u) {
        if (i >= w + h - 1) {
            return;
        }
        int c = i - (h - 1);
        int run = 0;
        int span = 0;
        for (int y = max(0, -c); y <= min(h - 1, w - 1 - c); ++y) {
            int k = y * w + c + y;
            run += rising_runs[k];
            rising_runs[k] = run;
            span += rising_chords[k];
            rising_chords[k] = span;
        }
    } else {
        if (i >= h) {
            return;
        }
        int sum = 0;
        for (int k = i * w; k < (i + 1) * w; ++k) {
            sum += rows[k] + corners[k] + falling_runs[k] + rising_runs[k];
            rows[k] = sum + columns[k] + falling_chords[k] + rising_chords[k];
        }
    }
}
