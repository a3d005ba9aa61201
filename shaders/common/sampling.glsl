#ifndef COMMON_SAMPLING_GLSL
#define COMMON_SAMPLING_GLSL

// Directions drawn for the exact mode's Monte Carlo integration (common/environment.glsl): the points of a
// low-discrepancy sequence, and the material's own sampler: its model's lobe (each model's `_sample` and
// `_pdf` beside its evaluation, brdf/*.glsl) mixed with the cosine, with the density of each draw. Mirrored,
// independently written, by the CPU reference (src/reference/environment.rs). Made double
// (BRDF_IN_DOUBLE, brdf_density64.comp) it leaves the measured tables' sampler out, as brdf.glsl their
// evaluation.

#include "common/math.glsl"
#include "common/warp.glsl"
#include "common/brdf.glsl"
#ifndef BRDF_IN_DOUBLE
#include "brdf/measured_sampler.glsl"
#endif

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
#if !defined(WEBGL) && !defined(BRDF_IN_DOUBLE)
    if (brdf_id(m) == BRDF_MEASURED) {
        return (m.measured & MEASURED_SAMPLED) != 0u;
    }
#endif
    return has_lobe(m);
}

// A direction from the material's own sampler: its model's lobe (phong_sample, blinn_phong_sample,
// cook_torrance_sample), a .brdf file's sampleBRDF (t its X), or a measured table's half vectors, reflected.
vec3 lobe_sample(Material m, vec3 n, vec3 t, vec3 wo, vec2 u) {
    switch (brdf_id(m)) {
#ifdef ANALYTIC_HAS_SAMPLER
        case BRDF_ANALYTIC:
            return normalize(analytic_sample(m.analytic, n, t, wo, u));
#endif
#if !defined(WEBGL) && !defined(BRDF_IN_DOUBLE)
        case BRDF_MEASURED:
            return measured_sample(m.measured, n, wo, u);
#endif
        case BRDF_PHONG:
            return phong_sample(n, wo, m.shininess, u);
        case BRDF_BLINN_PHONG:
            return blinn_phong_sample(n, wo, m.shininess, u);
        default:
            return cook_torrance_sample(n, wo, m.roughness, u);
    }
}

// The density of lobe_sample drawing wi; a .brdf file's pdfBRDF as it gives it.
float lobe_pdf(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    switch (brdf_id(m)) {
#ifdef ANALYTIC_HAS_SAMPLER
        case BRDF_ANALYTIC:
            return analytic_pdf(m.analytic, n, t, wi, wo);
#endif
#if !defined(WEBGL) && !defined(BRDF_IN_DOUBLE)
        case BRDF_MEASURED:
            return measured_sample_pdf(m.measured, n, wi, wo);
#endif
        case BRDF_PHONG:
            return phong_pdf(n, wi, wo, m.shininess);
        case BRDF_BLINN_PHONG:
            return blinn_phong_pdf(n, wi, wo, m.shininess);
        default:
            return cook_torrance_pdf(n, wi, wo, m.roughness);
    }
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
