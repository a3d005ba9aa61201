#version 460
// webgl
// variant: WITH_ENVIRONMENT
// variant: TERM_VIEWS
// variant: WITH_ENVIRONMENT+TERM_VIEWS

// The forward pass of spheres. The bounding mesh's fragments cover the samples whose camera rays meet the
// exact sphere (gl_SampleMask) and shade the point where the pixel centre's ray meets it, as the ray tracer
// does; at the silhouette, where the centre's ray misses, the point of the pixel's first sample whose ray
// meets it: every fragment of a pixel (the mesh's triangles may share it) shades the same point, so that
// the image does not depend on the tessellation. The depth is that point's, so that spheres and other
// objects occlude each other where the exact surfaces do.

#include "common/shading.glsl"
#include "common/sphere.glsl"

layout(location = 0) out vec4 out_radiance;

// MSAA samples per pixel, fixed when the pipeline is built (a pipeline is made for one sample count anyway).
// Read from the frame's uniform buffer instead, the loop's bound was a uniform in control flow, which Mesa
// 22's lavapipe inlines by compiling the shader again each time the pipeline is bound, and keeps every copy:
// 0.7 MB more memory and a compilation for each image of a sweep.
layout(constant_id = 6) const int SAMPLES = 1;

// Vulkan's standard sample locations within a pixel (the specification's table; the renderer checks that
// the device uses them). Counts of 1, 2, 4 and 8.
const vec2 SAMPLE_LOCATIONS[15] = vec2[15](
    vec2(0.5, 0.5),
    vec2(0.75, 0.75), vec2(0.25, 0.25),
    vec2(0.375, 0.125), vec2(0.875, 0.375), vec2(0.125, 0.625), vec2(0.625, 0.875),
    vec2(0.5625, 0.3125), vec2(0.4375, 0.6875), vec2(0.8125, 0.5625), vec2(0.3125, 0.1875),
    vec2(0.1875, 0.8125), vec2(0.0625, 0.4375), vec2(0.6875, 0.9375), vec2(0.9375, 0.0625));

// The samples this fragment covers. WebGL2 (GLSL ES 3.00) has no sample masks: the browser draws one sample a
// pixel (SAMPLES 1), which the fragment covers whole, so its coverage is the pixel centre's ray's alone.
#ifdef WEBGL
#define SAMPLES_OF_FRAGMENT 1
#else
#define SAMPLES_OF_FRAGMENT gl_SampleMaskIn[0]
#endif

// The camera's unit ray through a framebuffer position.
vec3 camera_ray(vec2 position) {
    return normalize((frame.pixel_rays * vec4(position, 1.0, 0.0)).xyz);
}

void main() {
    ObjectData object = objects[draw.object_index];
    vec3 center = sphere_center(object);
    float radius = sphere_radius(object);
    vec3 eye = frame.camera_position.xyz;

    int covered = 0;
    float first_t = 0.0;
    vec3 first_ray = vec3(0.0);
    int first_location = SAMPLES - 1;  // the table's entries for a count n start at n - 1
    vec2 corner = floor(gl_FragCoord.xy);
    bool any_hit = false;
    for (int i = 0; i < SAMPLES; ++i) {
        vec3 ray = camera_ray(corner + SAMPLE_LOCATIONS[first_location + i]);
        float t;
        if (ray_sphere(eye, ray, center, radius, t)) {
            if (!any_hit) {
                first_t = t;
                first_ray = ray;
                any_hit = true;
            }
            // Samples outside this triangle's are another triangle's fragment's to cover.
            covered |= SAMPLES_OF_FRAGMENT & (1 << i);
        }
    }
    if (covered == 0) {
        discard;
    }
    vec3 ray = camera_ray(gl_FragCoord.xy);
    float t;
    if (!ray_sphere(eye, ray, center, radius, t)) {
        ray = first_ray;
        t = first_t;
    }
    vec3 p = eye + t * ray;
#ifndef WEBGL
    gl_SampleMask[0] = covered;
#endif
    vec4 clip = frame.view_projection * vec4(p, 1.0);
    gl_FragDepth = clip.z / clip.w;
    out_radiance = vec4(pixel_value(object, p, (p - center) / radius, vec3(0.0)), 1.0);
}
