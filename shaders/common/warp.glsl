#ifndef COMMON_WARP_GLSL
#define COMMON_WARP_GLSL

// Directions drawn from a point u of the unit square, each with its density per solid angle (pbrt-v4's
// sampling.h): about an axis, the cosine-weighted hemisphere and a cosine-power lobe. The models' own
// samplers (brdf/*.glsl) are made of them.

#include "common/math.glsl"

// A unit vector at (cos_theta, sin_theta) from `axis` and azimuth phi about it (Duff et al. 2017, "Building
// an orthonormal basis, revisited").
vec3 around_at(vec3 axis, float cos_theta, float sin_theta, float phi) {
    float sign_z = axis.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + axis.z);
    float b = axis.x * axis.y * a;
    vec3 tangent = vec3(1.0 + sign_z * axis.x * axis.x * a, sign_z * b, -sign_z * axis.x);
    vec3 bitangent = vec3(b, sign_z + axis.y * axis.y * a, -axis.y);
    return (tangent * cos(phi) + bitangent * sin(phi)) * sin_theta + axis * cos_theta;
}

// The same at cos_theta, sin_theta from it (exact enough away from the axis).
vec3 around(vec3 axis, float cos_theta, float phi) {
    return around_at(axis, cos_theta, sqrt(max(1.0 - cos_theta * cos_theta, 0.0)), phi);
}

// 1 - exp(x) for x <= 0, without the cancellation of 1 - exp(x) near 0 (GLSL has no expm1): its series
// where |x| is small.
float one_minus_exp(float x) {
    return abs(x) < 1e-3 ? -x * (1.0 + x * (0.5 + x * (1.0 / 6.0))) : 1.0 - exp(x);
}

// Malley's method: the cosine-weighted hemisphere about n, density cos(theta) / pi.
vec3 cosine_sample(vec3 n, vec2 u) { return around(n, sqrt(1.0 - u.x), 2.0 * PI * u.y); }
float cosine_pdf(vec3 n, vec3 wi) { return max(dot(n, wi), 0.0) * INV_PI; }

// A cosine-power lobe about `axis` (Lafortune and Willems 1994, "Using the modified Phong reflectance model
// for physically based rendering"): density (s + 1) / (2 pi) cos^s. cos theta = u^(1 / (s + 1)); sin theta
// from sin^2 = 1 - u^(2 / (s + 1)) without cancellation, for a sharp lobe's cos theta rounds to a few floats
// below 1 (at s = 10^5 a float sin theta from it drew a lobe that Pearson's chi-square told apart).
vec3 cosine_power_sample(vec3 axis, float s, vec2 u) {
    float log_u = log(u.x) / (s + 1.0);
    return around_at(axis, exp(log_u), sqrt(one_minus_exp(2.0 * log_u)), 2.0 * PI * u.y);
}
// Its density at w. cos^s as exp(s ln cos), ln cos = ln(1 - sin^2) / 2 by its series near the axis, sin^2 =
// |axis x w|^2: a sharp lobe lies where the float cos rounds to a few values below 1, and pow(cos, s) of them
// was a staircase whose integral missed 1 by 4% at s = 10^7.
float cosine_power_pdf(vec3 axis, float s, vec3 w) {
    float cos_theta = dot(axis, w);
    if (cos_theta <= 0.0) {
        return 0.0;
    }
    vec3 across = cross(axis, w);
    float x = dot(across, across);
    float log_cos = x < 1e-3 ? -0.5 * x * (1.0 + x * (0.5 + x * (1.0 / 3.0 + x * 0.25))) : log(cos_theta);
    return (s + 1.0) * (0.5 * INV_PI) * exp(s * log_cos);
}

#endif
