#version 460
// variant: WITH_ENVIRONMENT
// variant: TERM_VIEWS
// variant: WITH_ENVIRONMENT+TERM_VIEWS

// The forward pass of meshes and planes: each fragment shaded at the interpolated point and normal.
// Spheres have their own pass, forward_sphere.frag.

#include "common/shading.glsl"

layout(location = 0) in vec4 in_world_position;
layout(location = 1) in vec3 in_world_normal;
layout(location = 2) in vec3 in_world_tangent;

layout(location = 0) out vec4 out_radiance;

void main() {
    ObjectData object = objects[draw.object_index];
    // Past 1e7 units a point light's 1/d^2 is nil.
    vec3 p;
    if (!world_point(in_world_position, p)) {
        out_radiance = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    out_radiance = vec4(pixel_value(object, p, normalize(in_world_normal), in_world_tangent), 1.0);
}
