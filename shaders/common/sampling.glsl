#ifndef COMMON_SAMPLING_GLSL
#define COMMON_SAMPLING_GLSL

// Directions drawn for the exact mode's Monte Carlo integration (common/environment.glsl): the points of a
// low-discrepancy sequence, and each model's lobe drawn in proportion to (nearly) what it reflects, with
// the density of each draw. Mirrored, independently written, by the CPU reference (src/reference.rs).

#include "common/math.glsl"
#include "common/brdf.glsl"
#include "brdf/measured_sampler.glsl"

// Roberts 2018, "The unreasonable effectiveness of quasirandom sequences": point i of the R2 sequence is
// fract(offset + i alpha), alpha = (1/g, 1/g^2) with g the plastic number (1.32471...). In 32-bit fixed
// point, so that it stays exact however far the passes go (as floats, i alpha loses its fraction past a few
// thousand samples).
const uvec2 R2_ALPHA = uvec2(3242174889u, 2447445413u);

// The 32-bit hash of Jarzynski and Olano 2020, "Hash functions for GPU rendering" (PCG): the random shift
// of the sequence (Cranley and Patterson 1976) for each pixel, pass and strategy, so that neighbours do not
// share their error and passes are independent estimates whose spread is the error's.
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Point `index` of the sequence shifted for `stream` (a pass's strategy) at the pixel, in [0, 1)^2.
vec2 sequence_point(uvec2 pixel, uint stream, uint index) {
    uint seed = pcg_hash(pixel.x + pcg_hash(pixel.y + pcg_hash(stream)));
    uvec2 fixed_point = uvec2(seed, pcg_hash(seed)) + index * R2_ALPHA;
    return vec2(fixed_point >> 8u) * (1.0 / 16777216.0);
}

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

// Whether the material has a specular lobe to draw directions from (the fast mode prefilters it too).
bool has_lobe(Material m) {
    switch (brdf_id(m)) {
        case BRDF_PHONG:
        case BRDF_BLINN_PHONG:
            return max(m.ks.r, max(m.ks.g, m.ks.b)) > 0.0;
        case BRDF_COOK_TORRANCE:
            return m.metalness > 0.0;
        default:
            return false;
    }
}

// Whether the material has a sampler of its own, beside the cosine: a specular lobe, a .brdf file's
// isFunc section (its sampleBRDF and pdfBRDF, crates/brdf-file/src/glsl.rs), or a measured table's
// (brdf/measured_sampler.glsl) unless the scene turned it off.
bool has_sampler(Material m) {
#ifdef ANALYTIC_HAS_SAMPLER
    if (brdf_id(m) == BRDF_ANALYTIC) {
        return true;
    }
#endif
#ifndef WEBGL
    if (brdf_id(m) == BRDF_MEASURED) {
        return (m.measured & MEASURED_SAMPLED) != 0u;
    }
#endif
    return has_lobe(m);
}

// A direction from the material's own sampler: about the mirror of wo for Phong (its lobe times cos is
// (wi . r)^s exactly), a half vector for Blinn-Phong ((n . h)^s) and Cook-Torrance (GGX's visible
// normals), reflected; a .brdf file's sampleBRDF (t its X); a measured table's half vectors, reflected.
vec3 lobe_sample(Material m, vec3 n, vec3 t, vec3 wo, vec2 u) {
#ifdef ANALYTIC_HAS_SAMPLER
    if (brdf_id(m) == BRDF_ANALYTIC) {
        return normalize(analytic_sample(m.analytic, n, t, wo, u));
    }
#endif
#ifndef WEBGL
    if (brdf_id(m) == BRDF_MEASURED) {
        return measured_sample(m.measured, n, wo, u);
    }
#endif
    if (brdf_id(m) == BRDF_PHONG) {
        return cosine_power_sample(mirror(n, wo), m.shininess, u);
    }
    vec3 h = brdf_id(m) == BRDF_BLINN_PHONG ? cosine_power_sample(n, m.shininess, u)
                                        : ggx_visible_normal_sample(n, wo, m.roughness * m.roughness, u);
    return mirror(h, wo);
}

// The density of lobe_sample drawing wi (a half vector's density over 4 (wo . h), the reflection's
// Jacobian); a .brdf file's pdfBRDF as it gives it.
float lobe_pdf(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
#ifdef ANALYTIC_HAS_SAMPLER
    if (brdf_id(m) == BRDF_ANALYTIC) {
        return analytic_pdf(m.analytic, n, t, wi, wo);
    }
#endif
#ifndef WEBGL
    if (brdf_id(m) == BRDF_MEASURED) {
        return measured_sample_pdf(m.measured, n, wi, wo);
    }
#endif
    if (brdf_id(m) == BRDF_PHONG) {
        return cosine_power_pdf(mirror(n, wo), m.shininess, wi);
    }
    vec3 h = half_vector(wi, wo);
    float WoH = dot(wo, h);
    if (WoH <= 0.0) {
        return 0.0;
    }
    if (brdf_id(m) == BRDF_BLINN_PHONG) {
        return cosine_power_pdf(n, m.shininess, h) / (4.0 * WoH);
    }
    // The visible normals' density G1(wo) (wo . h) D(h) / (n . wo), over 4 (wo . h).
    float alpha = m.roughness * m.roughness;
    float NoV = max(dot(n, wo), 1e-6);
    return dot(n, h) > 0.0 ? ggx_g1(NoV, alpha) * d_ggx(n, h, alpha) / (4.0 * NoV) : 0.0;
}

// A measured table's sampler is its estimate from a few points per cell: the cosine keeps a tenth of the
// draws (Hesterberg 1995's defensive mixture), so that wherever the table reflects, the density is not zero
// and a draw's weight f_r cos / pdf stays below 10 pi f_r.
const float MEASURED_SHARE = 0.9;

// The luminance of a reflectance (Rec. 709), which the material's sampler shares its draws by.
float reflectance_luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// How often the material's own sampler draws from its lobe rather than the cosine: in proportion to the
// lobe's reflectance beside the diffuse one's (ks against kd for the course's plastics, the metal's share of
// f0 against the rest's kd for Cook-Torrance), as renderers share a layered material's samples; always for a
// .brdf file's sampler, which is the whole of its own; MEASURED_SHARE for a measured table's.
float lobe_share(Material m) {
    if (!has_sampler(m)) {
        return 0.0;
    }
    if (brdf_id(m) == BRDF_ANALYTIC) {
        return 1.0;
    }
    if (brdf_id(m) == BRDF_MEASURED) {
        return MEASURED_SHARE;
    }
    float lobe = brdf_id(m) == BRDF_COOK_TORRANCE ? m.metalness * reflectance_luminance(m.f0.rgb)
                                                 : reflectance_luminance(m.ks.rgb);
    float diffuse = brdf_id(m) == BRDF_COOK_TORRANCE ? (1.0 - m.metalness) * reflectance_luminance(m.kd.rgb)
                                                    : reflectance_luminance(m.kd.rgb);
    return lobe + diffuse > 0.0 ? lobe / (lobe + diffuse) : 1.0;
}

// The material's own sampler, which `vk-render sampling` tests: one draw from the lobe (lobe_sample, as the
// exact mode draws it) with probability lobe_share, else from the cosine, u.x reused for the choice. A
// direction below the surface is no sample. The frame's tangent t is for the models that read one.
vec3 material_sample(Material m, vec3 n, vec3 t, vec3 wo, vec2 u) {
    float share = lobe_share(m);
    if (u.x < share) {
        return lobe_sample(m, n, t, wo, vec2(u.x / share, u.y));
    }
    return cosine_sample(n, vec2((u.x - share) / (1.0 - share), u.y));
}

// The density per solid angle of material_sample drawing wi: zero below the surface, where the built-in
// samplers draw nothing; a .brdf file's pdfBRDF there as it gives it, for the test to hold it to zero.
float material_pdf(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    if (brdf_id(m) == BRDF_ANALYTIC) {
        return has_sampler(m) ? lobe_pdf(m, n, t, wi, wo) : cosine_pdf(n, wi);
    }
    if (dot(n, wi) <= 0.0) {
        return 0.0;
    }
    float share = lobe_share(m);
    float pdf = (1.0 - share) * cosine_pdf(n, wi);
    return share > 0.0 ? pdf + share * lobe_pdf(m, n, t, wi, wo) : pdf;
}

#endif
