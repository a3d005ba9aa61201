#ifndef COMMON_SCENE_GLSL
#define COMMON_SCENE_GLSL

// The forward pass's inputs. Mirrored byte for byte by src/render/gpu_types.rs.

#include "common/material.glsl"

struct ObjectData {
    mat4 model;          // object to world
    mat4 normal_matrix;  // inverse transpose of model (upper 3x3 used)
    Material material;
    uvec4 flags;         // x: two-sided (a plane has no inside: shade the side the camera sees)
                         // y: the tangent's rule (common/brdf.glsl): TANGENT_DEFAULT, the vertices'
                         // tangents where they have them, else default_tangent; TANGENT_PLANE, plane_tangent
};

const uint TANGENT_DEFAULT = 0u;
const uint TANGENT_PLANE = 1u;

struct PointLight {
    vec4 position;   // xyz
    vec4 radiance;   // rgb = colour * power: incident radiance at distance d is radiance / d^2
    ivec4 shadow;    // x: the light's cube in shadow_maps, or -1 when it casts no shadows
                     // y: the faces of that cube the image needs, drawn (bit i: face i)
};

// No value of the frame decides control flow in a shader: Mesa 22's lavapipe inlines the values of a uniform
// buffer that do (a loop over the sample count, the exact mode's sampling table's size) by compiling the
// shader again each time the buffer changes, when that makes it much smaller, and keeps every copy: an
// exact-mode image of 60 x 40 held 400 MB more once rendered, and a sweep 0.7 MB more an image. What steers
// control flow is a specialization constant or comes from a storage buffer.
layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_projection;
    // The camera's ray through framebuffer position (x, y), unnormalized: pixel_rays * vec4(x, y, 1, 0)
    // (columns: its change per pixel right and down, and the ray through the corner (0, 0)). The rays of
    // the CPU reference, through any sample position.
    mat4 pixel_rays;
    vec4 camera_position;
    vec4 background;           // rgb, alpha 1: what no object covers
    float shadow_texel_angle;  // 2 / shadow_map_size: a texel's angle at the centre of a cube face
    uint environment_first_sample;  // the exact mode: the first sample of this pass
    uint pad0;
    uint pad1;
    // The environment (common/environment_map.glsl): cos and sin of its rotation about +y, its intensity,
    // and 0.
    vec4 environment;
} frame;

#ifdef WEBGL
// The browser's build (WebGL2, GLSL ES 3.00 by SPIRV-Cross: build.rs): no storage buffers and no cube arrays.
// The lights and the shadow views are uniform blocks of the scene format's most lights (src/scene: MAX_LIGHTS);
// the objects' block holds the one object drawn (draw.object_index is 0); the shadow cubes are the layers
// of a 2D array texture, six a cube in Vulkan's face order, read as Vulkan reads a cube (shadow_distance).
const uint MAX_LIGHTS = 16u;
layout(set = 0, binding = 1, std140) uniform Lights { PointLight lights[MAX_LIGHTS]; };
layout(set = 0, binding = 2, std140) uniform Objects { ObjectData objects[1]; };
layout(set = 0, binding = 3, std140) uniform ShadowViews { mat4 shadow_views[6u * MAX_LIGHTS]; };
layout(set = 0, binding = 4) uniform sampler2DArray shadow_maps;
#else
layout(set = 0, binding = 1, std430) readonly buffer Lights { PointLight lights[]; };
layout(set = 0, binding = 2, std430) readonly buffer Objects { ObjectData objects[]; };
// Six view-projections per shadow cube, in Vulkan's face order (+x, -x, +y, -y, +z, -z).
layout(set = 0, binding = 3, std430) readonly buffer ShadowViews { mat4 shadow_views[]; };
// Distance from each light to the nearest surface, one cube per shadow-casting light.
layout(set = 0, binding = 4) uniform samplerCubeArray shadow_maps;
#endif
// Bindings 5 to 8 are the environment's (common/environment.glsl); 9 holds the measured tables, 10 the
// analytic materials' values and 11 the object's report of them (common/analytic.glsl).
#define MEASURED_BINDING 9
#define ANALYTIC_BINDING 10
#define ANALYTIC_REPORT_BINDING 11

// light_index and face: the light and the face of its shadow cube that the shadow pass draws (unused by
// the forward pass).
layout(push_constant) uniform Draw { uint object_index; uint light_index; uint face; } draw;

// The world position of a fragment from its interpolated homogeneous position, or false past 1e7 units
// (towards the plane's horizon, where w tends to 0 and dividing would overflow).
bool world_point(vec4 homogeneous, out vec3 p) {
    if (homogeneous.w <= 1e-7 * length(homogeneous.xyz)) {
        return false;
    }
    p = homogeneous.xyz / homogeneous.w;
    return true;
}

// What shadow cube `layer` holds in `direction` (the distance from its light to the nearest surface), the
// texel nearest to where the direction points, as the renderer's nearest sampler reads it.
#ifdef WEBGL
// Vulkan's cube lookup written out (the specification's table: the face of the major axis, x before y before
// z on a tie, and (s, t) on it), then the nearest texel of that face's layer.
float shadow_distance(vec3 d, float layer) {
    vec3 a = abs(d);
    int face;
    vec3 st_ma;  // sc, tc and the major axis's magnitude
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0.0 ? 0 : 1;
        st_ma = vec3(d.x > 0.0 ? -d.z : d.z, -d.y, a.x);
    } else if (a.y >= a.z) {
        face = d.y > 0.0 ? 2 : 3;
        st_ma = vec3(d.x, d.y > 0.0 ? d.z : -d.z, a.y);
    } else {
        face = d.z > 0.0 ? 4 : 5;
        st_ma = vec3(d.z > 0.0 ? d.x : -d.x, -d.y, a.z);
    }
    vec2 st = 0.5 * (st_ma.xy / st_ma.z + 1.0);
    int size = textureSize(shadow_maps, 0).x;
    ivec2 texel = clamp(ivec2(floor(st * float(size))), ivec2(0), ivec2(size - 1));
    return texelFetch(shadow_maps, ivec3(texel, 6 * int(layer) + face), 0).r;
}
#else
float shadow_distance(vec3 direction, float layer) {
    return textureLod(shadow_maps, vec4(direction, layer), 0.0).r;
}
#endif

#endif
