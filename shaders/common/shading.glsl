#ifndef COMMON_SHADING_GLSL
#define COMMON_SHADING_GLSL

// Forward shading: L = sum over lights of f_r(wi, wo) * radiance / d^2 * max(0, n . wi), plus the
// environment's light where the scene has one (common/environment.glsl), no ambient. Shared
// by the pass for meshes and planes (forward.frag) and the one for exact spheres (forward_sphere.frag).

#include "common/scene.glsl"
#include "common/brdf.glsl"
#include "common/views.glsl"
// The environment's light is compiled into the entry files' WITH_ENVIRONMENT variants alone: lavapipe
// reads and optimizes every function of a shader before the specialization constants settle what runs, and
// the environment's code made the pipelines of scenes without one 25% slower to build (figures).
#ifdef WITH_ENVIRONMENT
#include "common/environment.glsl"
#endif

const float MIN_NOV = 1e-4;

// The largest tan(theta_i) the shadow bias follows: beyond (theta_i > 87 degrees) the light's cosine
// leaves too little radiance for acne to show.
const float MAX_BIAS_SLOPE = 20.0;

// The shadow filter, fixed when the pipeline is built (0: hard, 1: PCF): lavapipe would run the nine PCF
// lookups, masked off, behind a branch on a uniform value too (they doubled Figure 1's shading time).
layout(constant_id = 1) const uint SHADOW_FILTER = 0u;

// The number of lights, fixed when the pipeline is built: a loop of known length is unrolled (the bunny's
// two lights shaded about 10% faster on lavapipe).
layout(constant_id = 2) const uint LIGHT_COUNT = 0u;

// The faces of a cube a lookup in direction d may read (bit i for face i: +x, -x, +y, -y, +z, -z): its
// major axis's, and any other within SEEN_FACES_TIE of it, where rounding may pick either.
const float SEEN_FACES_TIE = 1e-3;
uint faces_read(vec3 d) {
    vec3 a = abs(d);
    float least = max(a.x, max(a.y, a.z)) * (1.0 - SEEN_FACES_TIE);
    uint faces = 0u;
    faces |= a.x >= least ? (d.x >= 0.0 ? 1u : 2u) : 0u;
    faces |= a.y >= least ? (d.y >= 0.0 ? 4u : 8u) : 0u;
    faces |= a.z >= least ? (d.z >= 0.0 ? 16u : 32u) : 0u;
    return faces;
}

// 1 where the cube holds a distance beyond `unoccluded` in `direction` (the light sees that far), 0 where
// it does not. Only the faces a visible point can read and an occluder falls on are drawn (`seen`:
// src/render/shadow.rs, faces_seen, and src/render/occluders.rs); a lookup that may read another counts as
// lit: either no occluder is there, or it comes from no visible point (attributes extrapolated from a sample
// to the pixel centre can leave the view), so that what a face no image needed holds never shows.
float lit_in(vec3 direction, float layer, uint seen, float unoccluded) {
    if ((faces_read(direction) & ~seen) != 0u) {
        return 1.0;
    }
    return shadow_distance(direction, layer) < unoccluded ? 0.0 : 1.0;
}

// Whether the light sees p (1) or not (0), or the fraction of PCF lookups that do.
//
// The cube holds, per texel, the distance from the light to the nearest surface along the texel's centre
// direction. A lookup `reach` texels away from p's own direction (0.71, half a diagonal, for the nearest
// texel; one texel more for PCF's outer lookups) meets the surface at a distance that differs by about
// d * texel * reach * tan(theta_i): the bias covers that, plus half a texel for curvature and rounding.
// Shadows therefore start within about d * texel * (0.75 tan(theta_i) + 0.5) of the exact contact with hard
// lookups: 2 mm at 4 units with 1024 texels, head-on.
float light_visibility(PointLight light, vec3 p, float NoL, float distance) {
    if (light.shadow.x < 0) {
        return 1.0;
    }
    bool pcf = SHADOW_FILTER != 0u;
    vec3 from_light = p - light.position.xyz;
    float tan_theta = min(sqrt(max(1.0 - NoL * NoL, 0.0)) / NoL, MAX_BIAS_SLOPE);
    float texel = frame.shadow_texel_angle;
    float reach = pcf ? 1.75 : 0.75;
    float unoccluded = distance - distance * texel * (reach * tan_theta + 0.5);
    float layer = float(light.shadow.x);
    uint seen = uint(light.shadow.y);
    // lit_in reads level 0 explicitly: this runs in non-uniform control flow (per light, past a
    // per-fragment test), where texture()'s implicit level of detail is undefined; the cubes have one level.
    if (!pcf) {
        return lit_in(from_light, layer, seen, unoccluded);
    }
    // PCF: 3 x 3 lookups one texel apart across the lookup direction, averaged.
    vec3 u = normalize(abs(from_light.x) < 0.9 * distance ? cross(from_light, vec3(1.0, 0.0, 0.0))
                                                           : cross(from_light, vec3(0.0, 1.0, 0.0)));
    vec3 v = normalize(cross(from_light, u));
    float step_length = distance * texel;
    float lit = 0.0;
    for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
            vec3 direction = from_light + (float(i) * u + float(j) * v) * step_length;
            lit += lit_in(direction, layer, seen, unoccluded);
        }
    }
    return lit / 9.0;
}

// What the image shows at the object's point p, of normal n and interpolated vertex tangent (zero where the
// surface has none): the radiance that leaves it towards the camera, or the term VIEW (views.glsl).
vec3 pixel_value(ObjectData object, vec3 p, vec3 n, vec3 vertex_tangent) {
    vec3 wo = normalize(frame.camera_position.xyz - p);
    if (object.flags.x != 0u && dot(n, wo) < 0.0) {
        n = -n;
    } else if (dot(n, wo) < MIN_NOV) {
        // At a silhouette an interpolated normal can face away from a camera that still sees the
        // tessellated surface: bend it back over the horizon, since the BRDFs reflect nothing below it.
        n = normalize(n + (MIN_NOV - dot(n, wo)) * wo);
    }
    if (VIEW == VIEW_NORMAL) {
        return n;
    }
    // The tangent frame, which only an analytic model reads (and the compiler drops for the others).
    vec3 t = object.flags.y == TANGENT_PLANE ? plane_tangent(n) : surface_tangent(n, vertex_tangent);
    vec3 radiance = vec3(0.0);
    for (uint i = 0u; i < LIGHT_COUNT; ++i) {
        vec3 to_light = lights[i].position.xyz - p;
        float d2 = dot(to_light, to_light);
        vec3 wi = to_light * inversesqrt(d2);
        float NoL = dot(n, wi);
        if (NoL <= 0.0) {
            continue;  // the light is behind the surface
        }
        float visible = view_is_radiance() ? light_visibility(lights[i], p, NoL, sqrt(d2)) : 1.0;
        radiance += light_view(object.material, n, t, wi, wo, lights[i].radiance.rgb / d2, NoL, visible);
    }
#ifdef WITH_ENVIRONMENT
    if (ENVIRONMENT != ENVIRONMENT_NONE) {
        radiance += environment_light(object.material, n, t, wo);
    }
#endif
    return radiance;
}

#endif
