#version 460
// webgl

#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;  // homogeneous: w = 0 for the plane's vertices at infinity
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_tangent;    // zero where the mesh has no texture coordinates

layout(location = 0) out vec4 out_world_position;  // homogeneous, divided per fragment
layout(location = 1) out vec3 out_world_normal;
layout(location = 2) out vec3 out_world_tangent;

void main() {
    ObjectData object = objects[draw.object_index];
    vec4 world = object.model * in_position;
    out_world_position = world;
    out_world_normal = mat3(object.normal_matrix) * in_normal;
    // A tangent lies in the surface, so it turns and stretches with it: by the model matrix, not the normals'.
    out_world_tangent = mat3(object.model) * in_tangent;
    gl_Position = frame.view_projection * world;
}
