#version 460

// Forward shading: L = sum over lights of f_r(wi, wo) * radiance / d^2 * max(0, n . wi), no ambient.

#include "common/scene.glsl"
#include "common/brdf.glsl"

layout(location = 0) in vec4 in_world_position;
layout(location = 1) in vec3 in_world_normal;

layout(location = 0) out vec4 out_radiance;

const float MIN_NOV = 1e-4;

// A sphere is shaded where the view ray meets the exact sphere, as a ray tracer does: the tessellated mesh
// decides coverage and depth, but its flat facets lie up to 7.5e-5 radii inside the sphere, enough to move
// a pixel across an 8-bit level (the course's gold centre, 231.003, would truncate to 230). The model matrix
// of a sphere is translate(center) * scale(radius). Rays that miss (silhouette fragments) keep the mesh's
// interpolated point and normal.
void exact_sphere_point(mat4 model, vec3 eye, inout vec3 p, inout vec3 n) {
    vec3 center = model[3].xyz;
    float radius = length(model[0].xyz);
    vec3 d = normalize(p - eye);
    vec3 oc = eye - center;
    float b = dot(oc, d);
    float discriminant = b * b - (dot(oc, oc) - radius * radius);
    if (discriminant < 0.0) {
        return;
    }
    float root = sqrt(discriminant);
    // The nearer intersection in front of the eye; the far one when the eye is inside the sphere.
    float t = -b - root > 0.0 ? -b - root : -b + root;
    if (t <= 0.0) {
        return;
    }
    p = eye + t * d;
    n = (p - center) / radius;
}

void main() {
    ObjectData object = objects[draw.object_index];
    // Interpolating a homogeneous position is exact in clip space; w tends to 0 towards the plane's horizon.
    // Past 1e7 units a point light's 1/d^2 is nil, and dividing there would overflow.
    if (in_world_position.w <= 1e-7 * length(in_world_position.xyz)) {
        out_radiance = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 p = in_world_position.xyz / in_world_position.w;
    vec3 n = normalize(in_world_normal);
    if (object.flags.y != 0u) {
        exact_sphere_point(object.model, frame.camera_position.xyz, p, n);
    }
    vec3 wo = normalize(frame.camera_position.xyz - p);
    if (object.flags.x != 0u && dot(n, wo) < 0.0) {
        n = -n;
    } else if (dot(n, wo) < MIN_NOV) {
        // At a silhouette an interpolated normal can face away from a camera that still sees the
        // tessellated surface: bend it back over the horizon, since the BRDFs reflect nothing below it.
        n = normalize(n + (MIN_NOV - dot(n, wo)) * wo);
    }
    vec3 radiance = vec3(0.0);
    for (uint i = 0u; i < frame.light_count; ++i) {
        vec3 to_light = lights[i].position.xyz - p;
        float d2 = dot(to_light, to_light);
        vec3 wi = to_light * inversesqrt(d2);
        float NoL = dot(n, wi);
        if (NoL <= 0.0) {
            continue;  // the light is behind the surface
        }
        radiance += brdf_eval(object.material, n, wi, wo) * (lights[i].radiance.rgb / d2) * NoL;
    }
    out_radiance = vec4(radiance, 1.0);
}
