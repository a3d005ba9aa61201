#ifndef COMMON_ENVIRONMENT_MAP_GLSL
#define COMMON_ENVIRONMENT_MAP_GLSL

// The environment's map and its frame (src/environment/mod.rs): the texel at (u, v) holds the radiance
// arriving from (sin(theta) sin(phi), cos(theta), sin(theta) cos(phi)), theta = pi v, phi = 2 pi (u - 0.5),
// before the map is turned by its rotation about +y and scaled by its intensity (frame.environment).

#include "common/scene.glsl"
#include "common/math.glsl"

// How the environment is integrated, fixed when the pipeline is built: not at all (a scene without one,
// whose pipelines run the code they always ran), the exact mode or the fast one. The background's pipeline
// takes 1 when the environment may show as the background.
layout(constant_id = 5) const uint ENVIRONMENT = 0u;
const uint ENVIRONMENT_NONE = 0u;
const uint ENVIRONMENT_EXACT = 1u;
const uint ENVIRONMENT_FAST = 2u;

layout(set = 0, binding = 5) uniform sampler2D environment_map;

// A world direction in the map's frame (the world turned by minus the rotation), and back.
vec3 to_map(vec3 d) {
    float c = frame.environment.x, s = frame.environment.y;
    return vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}
vec3 to_world(vec3 d) {
    float c = frame.environment.x, s = frame.environment.y;
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// Map coordinates of a unit direction of the map's frame, and the direction at map coordinates. Straight up
// or down (an upward floor's normal) u is 1/2: GLSL leaves atan(0, 0) undefined, and NVIDIA's and lavapipe's
// differed, which moved a floor's irradiance in the fast mode by 5% (src/environment/mod.rs, uv_of).
vec2 map_uv(vec3 d) {
    float phi = d.x == 0.0 && d.z == 0.0 ? 0.0 : atan(d.x, d.z);
    return vec2(phi * (0.5 * INV_PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) * INV_PI);
}
vec3 map_direction(vec2 uv) {
    float theta = PI * uv.y, phi = 2.0 * PI * (uv.x - 0.5);
    return vec3(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
}

// The radiance arriving from world direction d (unit). Level 0 explicitly: this runs in non-uniform
// control flow, and the map has one level.
vec3 environment_radiance(vec3 d) {
    return frame.environment.z * textureLod(environment_map, map_uv(to_map(d)), 0.0).rgb;
}

#endif
