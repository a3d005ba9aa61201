#version 460
// webgl

// The forward pass of spheres: the bounding mesh placed in clip space. Its fragments find the exact sphere
// along the camera's rays (forward_sphere.frag), so nothing is interpolated.

#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;
layout(location = 1) in vec3 in_normal;   // unused: the sphere's normal is exact
layout(location = 2) in vec3 in_tangent;  // unused: a sphere's tangent follows its rule

void main() {
    gl_Position = frame.view_projection * (objects[draw.object_index].model * in_position);
}
