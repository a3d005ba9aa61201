#ifndef COMMON_SCENE_GLSL
#define COMMON_SCENE_GLSL

// The forward pass's inputs. Mirrored byte for byte by src/render/gpu_types.rs.

#include "common/material.glsl"

struct ObjectData {
    mat4 model;          // object to world
    mat4 normal_matrix;  // inverse transpose of model (upper 3x3 used)
    Material material;
    uvec4 flags;         // x: two-sided (a plane has no inside: shade the side the camera sees)
                         // y: a sphere, shaded on the exact surface (see forward.frag)
};

struct PointLight {
    vec4 position;   // xyz
    vec4 radiance;   // rgb = colour * power: incident radiance at distance d is radiance / d^2
};

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_projection;
    vec4 camera_position;
    uint light_count;
} frame;

layout(set = 0, binding = 1, std430) readonly buffer Lights { PointLight lights[]; };
layout(set = 0, binding = 2, std430) readonly buffer Objects { ObjectData objects[]; };

layout(push_constant) uniform Draw { uint object_index; } draw;

#endif
