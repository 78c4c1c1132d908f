#version 460
// The id of the site whose fan surface is lowest (site_fan.vert).
layout(location = 0) flat in uint id;
layout(location = 0) out uint out_id;

void main() {
    out_id = id;
}
