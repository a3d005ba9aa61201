#version 460
// webgl

// Writes the distance from the light to the surface, which the forward pass compares with its own.

#include "common/scene.glsl"

layout(location = 0) in vec4 in_world_position;

layout(location = 0) out float out_distance;

// What "nothing in this direction" reads as; the attachment is cleared to it.
const float FAR_AWAY = 3.0e38;

void main() {
#ifdef WEBGL
    // The browser draws no plane into the shadow cubes: SwiftShader's WebGL2 interpolates nothing right
    // across the infinite plane's triangles (forward.frag), and a plane's interpolated depth could hide what
    // stands on it. A plane then shadows nothing (it would only shadow what lies under it from the light).
    if (objects[draw.object_index].flags.y == TANGENT_PLANE) {
        discard;
    }
#endif
    vec3 p;
    out_distance = world_point(in_world_position, p) ? length(p - lights[draw.light_index].position.xyz) : FAR_AWAY;
}
