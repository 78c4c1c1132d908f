#version 460
// The dual of a colouring (Cao, Edelsbrunner and Tan 2015, Fig. 2): one
// invocation per strip of 64 pixel corners of a column, looking at the 2-by-2
// pixels around each corner counter-clockwise (x right, y up). Four colours
// make two triangles; three with the repeated colour on two side-neighbours
// make one (on a diagonal they are a neck, and make none). Pixels beyond the texture have the dummy
// vertex's colour. Triangles are appended with an atomic counter.
layout(local_size_x = 64) in;

layout(push_constant) uniform Dual {
    ivec2 size;
    uint capacity;
} dual;

layout(set = 0, binding = 0) readonly buffer Labels {
    uint label[];
};
// words[0] counts triangles; triangle t is words[1 + 3t .. 4 + 3t].
layout(set = 0, binding = 1) coherent buffer Triangles {
    uint words[];
};

const uint DUMMY = 0xFFFFFFFFu;
const int ROWS = 64;

uint colour(int x, int y) {
    bool inside = x >= 0 && y >= 0 && x < dual.size.x && y < dual.size.y;
    return inside ? label[y * dual.size.x + x] : DUMMY;
}

void emit(uint slot, uvec3 t) {
    if (slot < dual.capacity) {
        words[1u + 3u * slot] = t.x;
        words[2u + 3u * slot] = t.y;
        words[3u + 3u * slot] = t.z;
    }
}

// The corner at (x + 1/2, y + 1/2).
void corner(int x, int y) {
    uint c0 = colour(x, y);
    uint c1 = colour(x + 1, y);
    uint c2 = colour(x + 1, y + 1);
    uint c3 = colour(x, y + 1);
    bool e01 = c0 == c1, e12 = c1 == c2, e23 = c2 == c3, e30 = c3 == c0;
    bool e02 = c0 == c2, e13 = c1 == c3;
    uint equal = uint(e01) + uint(e12) + uint(e23) + uint(e30) + uint(e02) + uint(e13);
    bool side = e01 || e12 || e23 || e30;
    if (equal == 0u) {
        uint slot = atomicAdd(words[0], 2u);
        emit(slot, uvec3(c0, c1, c2));
        emit(slot + 1u, uvec3(c0, c2, c3));
    } else if (equal == 1u && side) {
        // The three colours counter-clockwise, from the one after the pair.
        uvec3 t = e01 ? uvec3(c1, c2, c3)
            : e12 ? uvec3(c2, c3, c0)
            : e23 ? uvec3(c3, c0, c1)
            : uvec3(c0, c1, c2);
        emit(atomicAdd(words[0], 1u), t);
    }
}

void main() {
    // A strip of ROWS corners of a column, x and y from -1 (few workgroups:
    // each costs a CPU device a call of its own).
    int x = int(gl_GlobalInvocationID.x) - 1;
    int y0 = int(gl_GlobalInvocationID.y) * ROWS - 1;
    if (x < dual.size.x) {
        int rows = min(ROWS, dual.size.y - y0);
        for (int r = 0; r < rows; ++r) {
            corner(x, y0 + r);
        }
    }
}
