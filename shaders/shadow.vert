#version 460
// webgl

// The shadow pass: the scene seen from one light through one face of its cube (draw.face).

#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;  // homogeneous: w = 0 for the plane's vertices at infinity
layout(location = 1) in vec3 in_normal;    // unused: the shadow pass needs positions only
layout(location = 2) in vec3 in_tangent;   // unused

layout(location = 0) out vec4 out_world_position;

void main() {
    ObjectData object = objects[draw.object_index];
    vec4 world = object.model * in_position;
    out_world_position = world;
    uint cube = uint(lights[draw.light_index].shadow.x);
    gl_Position = shadow_views[6u * cube + draw.face] * world;
}
