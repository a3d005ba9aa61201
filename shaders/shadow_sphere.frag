#version 460
// webgl

// The shadow pass of spheres: the distance from the light to the exact sphere along the texel centre's ray
// (the bounding mesh's interpolated point lies on it), which the cube lookup reads; texels whose ray misses
// the sphere are left to what else they see.

#include "common/scene.glsl"
#include "common/sphere.glsl"

layout(location = 0) in vec4 in_world_position;

layout(location = 0) out float out_distance;

void main() {
    ObjectData object = objects[draw.object_index];
    vec3 light = lights[draw.light_index].position.xyz;
    vec3 ray = normalize(in_world_position.xyz / in_world_position.w - light);
    float t;
    if (!ray_sphere(light, ray, sphere_center(object), sphere_radius(object), t)) {
        discard;
    }
    out_distance = t;
    uint cube = uint(lights[draw.light_index].shadow.x);
    vec4 clip = shadow_views[6u * cube + draw.face] * vec4(light + t * ray, 1.0);
    gl_FragDepth = clip.z / clip.w;
}
