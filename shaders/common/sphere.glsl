#ifndef COMMON_SPHERE_GLSL
#define COMMON_SPHERE_GLSL

// Spheres are drawn as a coarse mesh that bounds them (src/mesh: bounding_sphere): each fragment finds the
// exact sphere along its ray, as the ray tracer does, and covers, shades and takes the depth of that point.
// Coverage and shading do not depend on the tessellation, which only has to bound the sphere.

#include "common/scene.glsl"

// A sphere's model matrix is translate(center) * scale(radius).
vec3 sphere_center(ObjectData object) {
    return object.model[3].xyz;
}

float sphere_radius(ObjectData object) {
    return length(object.model[0].xyz);
}

// The distance t along the unit ray (origin, d) to the sphere: the nearer hit in front of the origin, the
// far one when the origin is inside; false when the ray misses.
bool ray_sphere(vec3 origin, vec3 d, vec3 center, float radius, out float t) {
    vec3 oc = origin - center;
    float b = dot(oc, d);
    float discriminant = b * b - (dot(oc, oc) - radius * radius);
    t = 0.0;
    if (discriminant < 0.0) {
        return false;
    }
    float root = sqrt(discriminant);
    t = -b - root > 0.0 ? -b - root : -b + root;
    return t > 0.0;
}

#endif
