#ifndef BRDF_COOK_TORRANCE_GLSL
#define BRDF_COOK_TORRANCE_GLSL

// Cook-Torrance with GGX, Smith-Schlick and Schlick (the Unreal Engine 4 choices, Karis 2013).
// Mirrored by src/brdf/cook_torrance.rs.

#include "common/math.glsl"
#include "brdf/lambert.glsl"
#include "brdf/oren_nayar.glsl"
#include "brdf/blinn_phong.glsl"
#include "common/warp.glsl"

// GGX's alpha from the course's roughness: alpha = roughness^2 (Burley 2012, the perceptual remapping the
// Unreal Engine 4 took). The one place it is made. Mirrors ggx_alpha in src/brdf/cook_torrance.rs.
float ggx_alpha(float roughness) { return roughness * roughness; }

// Trowbridge and Reitz 1975; Walter et al. 2007, "Microfacet models for refraction through rough surfaces":
// D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2), alpha = ggx_alpha(roughness). The denominator is written
// (1 - (n.h)^2) + (n.h)^2 alpha^2 with 1 - (n.h)^2 = |n x h|^2: as given, it cancels to 0 in float when h is
// near n and alpha is small, and D becomes infinite.
float d_ggx(vec3 n, vec3 h, float alpha) {
    float NoH = dot(n, h);
    float a2 = alpha * alpha;
    vec3 NxH = cross(n, h);
    float d = dot(NxH, NxH) + NoH * NoH * a2;
    return a2 / (PI * d * d);
}

// Karis 2013: k = (roughness + 1)^2 / 8, Schlick's k remapped for analytic lights.
float smith_schlick_k(float roughness) { return (roughness + 1.0) * (roughness + 1.0) / 8.0; }

// Schlick 1994, "An inexpensive BRDF model for physically-based rendering", approximating Smith 1967:
// V = G / (4 (n.wo)(n.wi)), G = G1(n.wo) G1(n.wi), G1(x) = x / (x (1 - k) + k). The cosines cancel, so V
// stays finite at grazing angles where G and the denominator both vanish.
float v_smith_schlick(float NoV, float NoL, float k) {
    return 0.25 / ((NoV * (1.0 - k) + k) * (NoL * (1.0 - k) + k));
}

// The shadowing-masking term itself: G = G1(n.wo) G1(n.wi) = 4 (n.wo)(n.wi) V (the G view shows it).
float g_smith_schlick(float NoV, float NoL, float k) {
    return 4.0 * NoV * NoL * v_smith_schlick(NoV, NoL, k);
}

// Schlick 1994: F = F0 + (1 - F0)(1 - h.wo)^5.
vec3 f_schlick(float VoH, vec3 f0) {
    float m = clamp(1.0 - VoH, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (vec3(1.0) - f0) * (m2 * m2 * m);
}

// Cook and Torrance 1982, "A reflectance model for computer graphics": D F G / (4 (n.wo)(n.wi)).
// Needs n.wi > 0 and n.wo > 0 (checked once by brdf_eval).
vec3 cook_torrance_specular(vec3 n, vec3 wi, vec3 wo, vec3 f0, float roughness) {
    float NoL = dot(n, wi);
    float NoV = dot(n, wo);
    vec3 h = half_vector(wi, wo);
    float VoH = clamp(dot(wo, h), 0.0, 1.0);
    return d_ggx(n, h, ggx_alpha(roughness)) * v_smith_schlick(NoV, NoL, smith_schlick_k(roughness)) * f_schlick(VoH, f0);
}

const uint DIFFUSE_OREN_NAYAR = 0u;
const uint DIFFUSE_LAMBERT = 1u;

// f = (1 - metalness) f_diffuse + metalness f_specular, the diffuse lobe Oren-Nayar with sigma = roughness
// (the course) or Lambert.
vec3 cook_torrance(vec3 n, vec3 wi, vec3 wo, vec3 kd, vec3 f0, float roughness, float metalness, uint diffuse) {
    vec3 f_diffuse = diffuse == DIFFUSE_LAMBERT ? lambert(kd) : oren_nayar(n, wi, wo, kd, roughness);
    return (1.0 - metalness) * f_diffuse + metalness * cook_torrance_specular(n, wi, wo, f0, roughness);
}

// GGX's visible normals (Heitz 2018, "Sampling the GGX distribution of visible normals"): half vectors
// in proportion to G1(wo) max(0, wo . h) D(h) / (n . wo), so that a sample's weight f cos / pdf is nearly
// F alone, even at grazing views. Drawn as Dupuy and Benyoub 2023 draw them ("Sampling visible GGX normals
// with spherical caps"): in the view stretched to alpha = 1 (v), a point of the unit sphere's cap z >= -v.z
// drawn uniformly, plus v, is a visible normal. Each term straight from u, 1 - z = u.x (1 + v.z) and
// z + v.z = (1 - u.x)(1 + v.z), for where they are a few floats is a sharp lobe's tail: Heitz's
// 1 - p1^2 - p2^2 there sent 10 samples in 10^6 of GGX at alpha = 10^-4 seen at 85 degrees tens of degrees
// off, which Pearson's chi-square caught.
vec3 ggx_visible_normal_sample(vec3 n, vec3 wo, float alpha, vec2 u) {
    vec3 t = around(n, 0.0, 0.0);
    vec3 b = cross(n, t);
    vec3 v = normalize(vec3(alpha * dot(wo, t), alpha * dot(wo, b), dot(wo, n)));
    float one_minus_z = u.x * (1.0 + v.z);
    float sin_theta = sqrt(max(one_minus_z * (2.0 - one_minus_z), 0.0));
    float phi = 2.0 * PI * u.y;
    vec3 h = vec3(sin_theta * cos(phi) + v.x, sin_theta * sin(phi) + v.y, (1.0 - u.x) * (1.0 + v.z));
    h = normalize(vec3(alpha * h.x, alpha * h.y, h.z));
    return h.x * t + h.y * b + h.z * n;
}

// Smith's G1 for GGX (Walter et al. 2007), the visible normals' normalization.
float ggx_g1(float NoV, float alpha) {
    float a2 = alpha * alpha;
    return 2.0 * NoV / (NoV + sqrt(a2 + (1.0 - a2) * NoV * NoV));
}

// Its sampler: a visible normal of GGX's, reflected (the diffuse lobe is the material's cosine strategy's).
vec3 cook_torrance_sample(vec3 n, vec3 wo, float roughness, vec2 u) {
    return mirror(ggx_visible_normal_sample(n, wo, ggx_alpha(roughness), u), wo);
}

// The density of cook_torrance_sample drawing wi: the visible normals' density G1(wo) (wo . h) D(h) / (n . wo)
// over 4 (wo . h), the reflection's Jacobian.
float cook_torrance_pdf(vec3 n, vec3 wi, vec3 wo, float roughness) {
    vec3 h = half_vector(wi, wo);
    float WoH = dot(wo, h);
    if (WoH <= 0.0) {
        return 0.0;
    }
    float alpha = ggx_alpha(roughness);
    float NoV = max(dot(n, wo), 1e-6);
    return dot(n, h) > 0.0 ? ggx_g1(NoV, alpha) * d_ggx(n, h, alpha) / (4.0 * NoV) : 0.0;
}

#endif
