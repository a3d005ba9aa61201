#version 460

#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;  // homogeneous: w = 0 for the plane's vertices at infinity
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_world_position;  // homogeneous, divided per fragment
layout(location = 1) out vec3 out_world_normal;

void main() {
    ObjectData object = objects[draw.object_index];
    vec4 world = object.model * in_position;
    out_world_position = world;
    out_world_normal = mat3(object.normal_matrix) * in_normal;
    gl_Position = frame.view_projection * world;
}
