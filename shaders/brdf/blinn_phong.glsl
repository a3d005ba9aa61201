#ifndef BRDF_BLINN_PHONG_GLSL
#define BRDF_BLINN_PHONG_GLSL

// Mirrored by src/brdf/blinn_phong.rs.

#include "brdf/lambert.glsl"
#include "brdf/phong.glsl"

// The half vector normalize(wi + wo); defined whenever both directions are above the surface.
vec3 half_vector(vec3 wi, vec3 wo) { return normalize(wi + wo); }

// Blinn 1977, "Models of light reflection for computer synthesized pictures": ks / cos(theta_i) *
// max(0, n . h)^s, the angle between n and the half vector replacing Phong's angle to the mirror direction.
// Needs n.wi > 0 and n.wo > 0 (checked once by brdf_eval).
vec3 blinn_phong_specular(vec3 n, vec3 wi, vec3 wo, vec3 ks, float shininess) {
    float NoH = max(dot(n, half_vector(wi, wo)), 0.0);
    return cosine_lobe(ks, NoH, shininess, dot(n, wi));
}

// Lambert(kd) + Blinn-Phong specular(ks, s).
vec3 blinn_phong(vec3 n, vec3 wi, vec3 wo, vec3 kd, vec3 ks, float shininess) {
    return lambert(kd) + blinn_phong_specular(n, wi, wo, ks, shininess);
}

// Its sampler: a half vector from the cosine-power lobe (n . h)^s about n, reflected (Blinn's lobe is that of
// the half vector's angle).
vec3 blinn_phong_sample(vec3 n, vec3 wo, float shininess, vec2 u) {
    return mirror(cosine_power_sample(n, shininess, u), wo);
}

// The density of blinn_phong_sample drawing wi: the half vector's density over 4 (wo . h), the reflection's
// Jacobian.
float blinn_phong_pdf(vec3 n, vec3 wi, vec3 wo, float shininess) {
    vec3 h = half_vector(wi, wo);
    float WoH = dot(wo, h);
    if (WoH <= 0.0) {
        return 0.0;
    }
    return cosine_power_pdf(n, shininess, h) / (4.0 * WoH);
}

#endif
