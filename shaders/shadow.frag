#version 460

// Writes the distance from the light to the surface, which the forward pass compares with its own.

#include "common/scene.glsl"

layout(location = 0) in vec4 in_world_position;

layout(location = 0) out float out_distance;

// What "nothing in this direction" reads as; the attachment is cleared to it.
const float FAR_AWAY = 3.0e38;

void main() {
    vec3 p;
    out_distance = world_point(in_world_position, p) ? length(p - lights[draw.light_index].position.xyz) : FAR_AWAY;
}
