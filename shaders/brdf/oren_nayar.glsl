#ifndef BRDF_OREN_NAYAR_GLSL
#define BRDF_OREN_NAYAR_GLSL

// Mirrored by src/brdf/oren_nayar.rs.

#include "brdf/lambert.glsl"

// A = 1 - 0.5 sigma^2 / (sigma^2 + 0.33) (Oren and Nayar 1994, qualitative model).
float oren_nayar_a(float sigma) {
    float s2 = sigma * sigma;
    return 1.0 - 0.5 * s2 / (s2 + 0.33);
}

// B = 0.45 sigma^2 / (sigma^2 + 0.09) (Oren and Nayar 1994, qualitative model).
float oren_nayar_b(float sigma) {
    float s2 = sigma * sigma;
    return 0.45 * s2 / (s2 + 0.09);
}

// cos(phi_i - phi_o): the cosine between wi and wo projected on the tangent plane; 0 when either is along
// the normal (its azimuth is undefined, and beta = 0 cancels the term anyway).
float cos_phi_difference(vec3 n, vec3 wi, vec3 wo) {
    vec3 wi_t = wi - n * dot(n, wi);
    vec3 wo_t = wo - n * dot(n, wo);
    float lengths = sqrt(dot(wi_t, wi_t) * dot(wo_t, wo_t));
    // 1e-12 = (1e-6)^2: both projections shorter than 1e-6 mean a direction within 1e-6 rad of the normal.
    return lengths <= 1e-12 ? 0.0 : dot(wi_t, wo_t) / lengths;
}

// Oren and Nayar 1994, "Generalization of Lambert's reflectance model":
// f_r = kd/pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)), alpha = max(theta_i, theta_o),
// beta = min(theta_i, theta_o). Needs n.wi > 0 and n.wo > 0 (checked once by brdf_eval).
vec3 oren_nayar(vec3 n, vec3 wi, vec3 wo, vec3 kd, float sigma) {
    float NoL = dot(n, wi);
    float NoV = dot(n, wo);
    // The larger angle has the smaller cosine.
    float cos_alpha = min(min(NoL, NoV), 1.0);
    float cos_beta = min(max(NoL, NoV), 1.0);
    float sin_alpha = sqrt(1.0 - cos_alpha * cos_alpha);
    // cos_beta >= cos_alpha > 0, so tan(beta) is finite.
    float tan_beta = sqrt(1.0 - cos_beta * cos_beta) / cos_beta;
    float cos_phi = max(cos_phi_difference(n, wi, wo), 0.0);
    return lambert(kd) * (oren_nayar_a(sigma) + oren_nayar_b(sigma) * cos_phi * sin_alpha * tan_beta);
}

#endif
