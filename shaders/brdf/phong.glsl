#ifndef BRDF_PHONG_GLSL
#define BRDF_PHONG_GLSL

// Mirrored by src/brdf/phong.rs.

#include "brdf/lambert.glsl"
#include "common/warp.glsl"

// The smallest cos(theta_i) the specular lobes divide by: keeps f finite at grazing incidence, where the
// integrand lobe * cos(theta_i) then fades to 0 over the last 1e-6 of the cosine.
const float MIN_COS_THETA_I = 1e-6;

// The mirror direction of wi about n: reflect(-wi, n) = 2 (n . wi) n - wi.
vec3 mirror(vec3 n, vec3 wi) { return 2.0 * dot(n, wi) * n - wi; }

// x^s for x >= 0 with 0^0 = 1 (GLSL's pow leaves 0^0 undefined).
float pow_lobe(float x, float s) {
    if (x > 0.0) {
        return pow(x, s);
    }
    return s == 0.0 ? 1.0 : 0.0;
}

// ks / cos(theta_i) * cos_alpha^s: the course's specular lobe, shared by Phong and Blinn-Phong, which differ
// only in the angle alpha they measure. The division by cos(theta_i) makes the lighting model a BRDF.
vec3 cosine_lobe(vec3 ks, float cos_alpha, float shininess, float NoL) {
    return ks * (pow_lobe(cos_alpha, shininess) / max(NoL, MIN_COS_THETA_I));
}

// Phong 1975, "Illumination for computer generated pictures": ks / cos(theta_i) * max(0, wo . r)^s, r the
// mirror of wi. Needs n.wi > 0 and n.wo > 0 (checked once by brdf_eval).
vec3 phong_specular(vec3 n, vec3 wi, vec3 wo, vec3 ks, float shininess) {
    float cos_alpha = max(dot(wo, mirror(n, wi)), 0.0);
    return cosine_lobe(ks, cos_alpha, shininess, dot(n, wi));
}

// The course's plastic: Lambert(kd) + Phong specular(ks, s).
vec3 phong(vec3 n, vec3 wi, vec3 wo, vec3 kd, vec3 ks, float shininess) {
    return lambert(kd) + phong_specular(n, wi, wo, ks, shininess);
}

// Its sampler: the lobe times cos(theta_i) is ks (wo . r)^s exactly, r the mirror of wi, so wi is drawn from
// the cosine-power lobe about the mirror of wo (Lafortune and Willems 1994).
vec3 phong_sample(vec3 n, vec3 wo, float shininess, vec2 u) {
    return cosine_power_sample(mirror(n, wo), shininess, u);
}

// The density of phong_sample drawing wi.
float phong_pdf(vec3 n, vec3 wi, vec3 wo, float shininess) {
    return cosine_power_pdf(mirror(n, wo), shininess, wi);
}

#endif
