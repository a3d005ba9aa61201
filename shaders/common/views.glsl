#ifndef COMMON_VIEWS_GLSL
#define COMMON_VIEWS_GLSL

// What an image shows (View in src/scene/mod.rs): the radiance, the render, or one term of the shading,
// each light's term summed over the lights, so that a student sees which term of theirs differs. Fixed when
// the pipeline is built (a specialization constant): the radiance's pipelines run the code they always ran.
//
// The terms' code is compiled into the entry files' TERM_VIEWS variants alone (as the environment's is into
// WITH_ENVIRONMENT's): lavapipe reads and optimizes every function of a shader before the specialization
// constants settle which runs, and the radiance's pipelines, which every figure, sweep and preview frame
// uses, were built 30% slower for the terms' mere presence.

#include "common/brdf.glsl"

layout(constant_id = 4) const uint VIEW = 0u;

const uint VIEW_RADIANCE = 0u;
const uint VIEW_NORMAL = 1u;
const uint VIEW_N_DOT_L = 2u;
const uint VIEW_BRDF = 3u;
const uint VIEW_D = 4u;
const uint VIEW_G = 5u;
const uint VIEW_F = 6u;
const uint VIEW_DIFFUSE = 7u;
const uint VIEW_SPECULAR = 8u;

// Whether the view weighs each light by what reaches the point (a radiance), shadows included.
bool view_is_radiance() { return VIEW == VIEW_RADIANCE || VIEW == VIEW_DIFFUSE || VIEW == VIEW_SPECULAR; }

#ifdef TERM_VIEWS
// A Cook-Torrance material's D, G or F for one light; 0 for the other models, which have none (the scene
// warns which objects are black).
vec3 microfacet_term(Material m, vec3 n, vec3 wi, vec3 wo) {
    float NoL = dot(n, wi);
    float NoV = dot(n, wo);
    if (m.brdf != BRDF_COOK_TORRANCE || NoL <= 0.0 || NoV <= 0.0) {
        return vec3(0.0);
    }
    vec3 h = half_vector(wi, wo);
    if (VIEW == VIEW_D) {
        return vec3(d_ggx(n, h, ggx_alpha(m.roughness)));
    }
    if (VIEW == VIEW_G) {
        return vec3(g_smith_schlick(NoV, NoL, smith_schlick_k(m.roughness)));
    }
    return f_schlick(clamp(dot(wo, h), 0.0, 1.0), m.f0.rgb);
}

// What one light adds to the view at a point of normal n seen from wo: `incident` is the light's radiance
// there unshadowed, `visible` the fraction the shadow lets through; n . wi = NoL > 0.
vec3 light_view(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo, vec3 incident, float NoL, float visible) {
    switch (VIEW) {
        case VIEW_N_DOT_L:
            return vec3(NoL);
        case VIEW_BRDF:
            return brdf_eval(m, n, t, wi, wo);
        case VIEW_D:
        case VIEW_G:
        case VIEW_F:
            return microfacet_term(m, n, wi, wo);
        case VIEW_DIFFUSE:
            return brdf_eval_diffuse(m, n, t, wi, wo) * incident * (NoL * visible);
        case VIEW_SPECULAR:
            return brdf_eval_specular(m, n, wi, wo) * incident * (NoL * visible);
        default:
            return brdf_eval(m, n, t, wi, wo) * incident * (NoL * visible);
    }
}
#else
// The radiance's variant: forward.rs builds the TERM_VIEWS variant for every other view.
vec3 light_view(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo, vec3 incident, float NoL, float visible) {
    return brdf_eval(m, n, t, wi, wo) * incident * (NoL * visible);
}
#endif

#endif
