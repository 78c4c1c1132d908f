#version 460
// Prefix sums along each row, in place: +1/-1 span ends become counts.
layout(local_size_x = 64) in;

layout(push_constant) uniform Rows {
    ivec2 size;
} rows;

layout(set = 0, binding = 1) buffer Values {
    int value[];
};

void main() {
    int y = int(gl_GlobalInvocationID.x);
    if (y >= rows.size.y) {
        return;
    }
    int row = y * rows.size.x;
    int sum = 0;
    for (int x = 0; x < rows.size.x; ++x) {
        sum += value[row + x];
        value[row + x] = sum;
    }
}
