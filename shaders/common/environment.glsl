#ifndef COMMON_ENVIRONMENT_GLSL
#define COMMON_ENVIRONMENT_GLSL

// The light an environment reflects towards wo: the integral over the hemisphere of L_env(wi) f_r(wi, wo)
// cos(theta_i), with f_r brdf_eval itself (or one of its lobes, for the diffuse and specular views). Not
// occluded by the scene's objects. Two modes (src/scene/mod.rs, EnvironmentMode):
// - exact: Monte Carlo, SAMPLES_PER_PASS samples a pass from low-discrepancy sequences, drawn in fixed
//   shares from the cosine-weighted hemisphere, the material's lobe and the environment's luminance, each
//   weighed by the shares' mixed density (Veach and Guibas 1995's balance heuristic), which keeps every
//   weight bounded. src/render/exact.rs averages the passes until the error is below its bound.
// - fast: a split sum (Karis 2013): per lobe, the material's directional albedo at n . wo, from a table the
//   albedo probe integrated (src/render/mod.rs, albedo_table), times the environment averaged over a
//   cosine-power lobe (src/environment/prefilter.rs): the cosine about n for the diffuse lobe; for the
//   specular one, about the mirror of wo, exponent s for Phong (exact but for the horizon), s / 4 for
//   Blinn-Phong (a half vector's angle is half the reflected direction's), and for GGX a quarter of its
//   Blinn-Phong exponent 2 / alpha^2 - 2 (Walter et al. 2007's correspondence).

#include "common/environment_map.glsl"
#include "common/sampling.glsl"
#include "common/views.glsl"

// The prefiltered layers: 2^k for k < PREFILTERED_LOBES, then the map itself.
layout(set = 0, binding = 6) uniform sampler2DArray environment_prefiltered;
const float PREFILTERED_LOBES = 11.0;

struct AlbedoEntry {
    vec4 diffuse;   // rgb: the diffuse lobe's directional albedo
    vec4 specular;  // rgb: the specular lobe's
};
const uint ALBEDO_TABLE_SIZE = 32u;
#ifdef WEBGL
// The browser draws the fast mode alone (its exact mode's sampling table and its loops over thousands of
// samples a pixel are the server's), and has no storage buffers: the albedo table of the one object drawn is
// a uniform block, which the page binds to each object's range of one buffer, as the objects' block.
layout(set = 0, binding = 8, std140) uniform EnvironmentAlbedo { AlbedoEntry environment_albedo[ALBEDO_TABLE_SIZE]; };
#else
// ALBEDO_TABLE_SIZE entries an object, entry k at cos(theta_o) = (k + 1/2) / ALBEDO_TABLE_SIZE.
layout(set = 0, binding = 8, std430) readonly buffer EnvironmentAlbedo { AlbedoEntry environment_albedo[]; };

// The sampling table (src/environment/sampling.rs, src/render/environment.rs): its width and height ((0, 0)
// for a constant environment, which is not importance-sampled) and the samples a pass of the exact mode takes,
// then, in 32-bit words: the marginal over rows (height + 1 floats), each row's conditional over its columns
// (width + 1 floats each), each cell's probability (width x height floats), the marginal's guide
// (guide_buckets(height) + 1 intervals) and each row's (guide_buckets(width) + 1 each). The sizes and the count
// bound loops: they are read here rather than from the frame's uniform buffer (see common/scene.glsl), and are
// not constants either: with the count known when the shader is compiled, its loops unrolled into code that
// ran 16% slower on lavapipe.
layout(set = 0, binding = 7, std430) readonly buffer EnvironmentSampling {
    uvec2 sampling_size;
    uint samples_per_pass;
    uint sampling_pad;
    uint environment_table[];
};

// The f_r the view integrates.
vec3 view_brdf(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
#ifdef TERM_VIEWS
    if (VIEW == VIEW_DIFFUSE) {
        return brdf_eval_diffuse(m, n, t, wi, wo);
    }
    if (VIEW == VIEW_SPECULAR) {
        return brdf_eval_specular(m, n, wi, wo);
    }
#endif
    return brdf_eval(m, n, t, wi, wo);
}

float table_float(uint k) {
    return uintBitsToFloat(environment_table[k]);
}

// sampling.rs's `buckets`: the guide of a table of n intervals has the power of two at least n.
uint guide_buckets(uint n) {
    return n <= 1u ? 1u : 1u << uint(findMSB(n - 1u) + 1);
}

// Where each part of the table starts.
uint conditional_start(uvec2 size) {
    return size.y + 1u;
}
uint probabilities_start(uvec2 size) {
    return conditional_start(size) + size.y * (size.x + 1u);
}
uint marginal_guide_start(uvec2 size) {
    return probabilities_start(size) + size.x * size.y;
}
uint conditional_guide_start(uvec2 size) {
    return marginal_guide_start(size) + guide_buckets(size.y) + 1u;
}

// The last i in [0, count) with cdf[i] <= u, cdf the count + 1 floats from word cdf_start: a binary search
// between the cutpoints of u's bucket of the table's guide (guide_start), which hold that interval
// (u times a power of two is exact: the bucket is the one the cutpoints were computed for). The same interval
// as a search of the whole table (src/environment/sampling.rs tests it), in a few reads instead of log2(count).
uint cdf_interval(uint cdf_start, uint count, uint guide_start, float u) {
    uint buckets = guide_buckets(count);
    uint bucket = min(uint(u * float(buckets)), buckets - 1u);
    uint low = environment_table[guide_start + bucket];
    uint high = min(environment_table[guide_start + bucket + 1u] + 1u, count);
    while (low + 1u < high) {
        uint middle = (low + high) / 2u;
        if (table_float(cdf_start + middle) <= u) {
            low = middle;
        } else {
            high = middle;
        }
    }
    return low;
}

// A world direction drawn in proportion to the table: a row, a column in it, then uniformly in (u, v).
vec3 environment_sample(vec2 u) {
    uvec2 size = sampling_size;
    uint j = cdf_interval(0u, size.y, marginal_guide_start(size), u.x);
    float row_low = table_float(j), row_high = table_float(j + 1u);
    float v = (float(j) + clamp((u.x - row_low) / max(row_high - row_low, 1e-30), 0.0, 1.0)) / float(size.y);
    uint row = conditional_start(size) + j * (size.x + 1u);
    uint i = cdf_interval(row, size.x, conditional_guide_start(size) + j * (guide_buckets(size.x) + 1u), u.y);
    float column_low = table_float(row + i), column_high = table_float(row + i + 1u);
    float s = (float(i) + clamp((u.y - column_low) / max(column_high - column_low, 1e-30), 0.0, 1.0)) / float(size.x);
    return to_world(map_direction(vec2(s, v)));
}

// The density of environment_sample drawing world direction d: uniform over its cell in (u, v), whose solid
// angle is 2 pi^2 sin(theta) du dv; the cell's probability is the table's.
float environment_pdf(vec3 d) {
    uvec2 size = sampling_size;
    vec3 m = to_map(d);
    vec2 uv = map_uv(m);
    uint i = min(uint(uv.x * float(size.x)), size.x - 1u);
    uint j = min(uint(uv.y * float(size.y)), size.y - 1u);
    float sin_theta = max(sqrt(max(1.0 - m.y * m.y, 0.0)), 1e-6);
    float probability = table_float(probabilities_start(size) + j * size.x + i);
    return probability * float(size.x * size.y) / (2.0 * PI * PI * sin_theta);
}

// One pass of the exact mode at the fragment's pixel: the mean of SAMPLES_PER_PASS samples, each strategy
// taking a fixed share of them (the multi-sample balance heuristic: choosing a strategy at random per
// sample would add the variance of the choice), from the start of its sequence, randomly shifted for the
// pass: passes are independent, so the spread of their means is the error of their mean.
vec3 environment_exact(Material m, vec3 n, vec3 t, vec3 wo) {
    uint count = samples_per_pass;
    uint lobe_count = has_sampler(m) ? (count * 7u) / 16u : 0u;
    // The environment takes half of what a diffuse material samples, 5/16 beside a lobe (7/16).
    uint environment_count = sampling_size.x == 0u ? 0u : (lobe_count > 0u ? (count * 5u) / 16u : count / 2u);
    uint cosine_count = count - lobe_count - environment_count;
    vec3 shares = vec3(cosine_count, lobe_count, environment_count) / float(count);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint pass_index = frame.environment_first_sample / count;
    uint counts[3] = uint[](cosine_count, lobe_count, environment_count);
    vec3 sum = vec3(0.0);
    for (uint strategy = 0u; strategy < 3u; ++strategy) {
        for (uint k = 0u; k < counts[strategy]; ++k) {
            vec2 u = sequence_point(pixel, 3u * pass_index + strategy, k);
            vec3 wi = strategy == 0u ? cosine_sample(n, u)
                                     : (strategy == 1u ? lobe_sample(m, n, t, wo, u) : environment_sample(u));
            float NoL = dot(n, wi);
            if (NoL <= 0.0) {
                continue;
            }
            float pdf = shares.x * cosine_pdf(n, wi);
            if (lobe_count > 0u) {
                pdf += shares.y * lobe_pdf(m, n, t, wi, wo);
            }
            if (environment_count > 0u) {
                pdf += shares.z * environment_pdf(wi);
            }
            if (pdf > 0.0) {
                sum += environment_radiance(wi) * view_brdf(m, n, t, wi, wo) * (NoL / pdf);
            }
        }
    }
    return sum / float(count);
}
#endif

// Where the prefiltered layers hold world direction d: u as the map's, v onto their rows, which run from
// pole to pole (src/environment/prefilter.rs), the first row's centre at v = 0 and the last's at v = 1.
vec2 layer_uv(vec3 d) {
    vec2 uv = map_uv(to_map(d));
    float rows = float(textureSize(environment_prefiltered, 0).y);
    return vec2(uv.x, (uv.y * (rows - 1.0) + 0.5) / rows);
}

// The environment averaged over the cosine lobe about world direction d: the irradiance over pi (layer 0).
vec3 irradiance_over_pi(vec3 d) {
    return frame.environment.z * textureLod(environment_prefiltered, vec3(layer_uv(d), 0.0), 0.0).rgb;
}

// The environment averaged over the cosine-power lobe of exponent s about world direction d: the layers
// around log2(s), read linearly between; past the last lobe, towards the map itself.
vec3 prefiltered(vec3 d, float s) {
    vec2 uv = layer_uv(d);
    float level = log2(max(s, 1.0));
    float layer = level <= PREFILTERED_LOBES - 1.0 ? level
                                                  : PREFILTERED_LOBES - 1.0 + min((level - PREFILTERED_LOBES + 1.0) / 4.0, 1.0);
    float below = floor(layer);
    vec3 low = textureLod(environment_prefiltered, vec3(uv, below), 0.0).rgb;
    vec3 high = textureLod(environment_prefiltered, vec3(uv, min(below + 1.0, PREFILTERED_LOBES)), 0.0).rgb;
    return frame.environment.z * mix(low, high, layer - below);
}

// The cosine-power exponent whose lobe about the mirror direction stands for the material's specular lobe.
float lobe_exponent(Material m) {
    switch (brdf_id(m)) {
        case BRDF_PHONG:
            return m.shininess;
        case BRDF_BLINN_PHONG:
            return m.shininess / 4.0;
        default: {
            float alpha = max(ggx_alpha(m.roughness), 1e-4);
            return (2.0 / (alpha * alpha) - 2.0) / 4.0;
        }
    }
}

// The object's albedo table at n . wo, linear between entries.
AlbedoEntry environment_albedo_at(uint object_index, float NoV) {
    float x = clamp(NoV * float(ALBEDO_TABLE_SIZE) - 0.5, 0.0, float(ALBEDO_TABLE_SIZE - 1u));
    uint k = min(uint(x), ALBEDO_TABLE_SIZE - 2u);
    float t = x - float(k);
    AlbedoEntry a = environment_albedo[object_index * ALBEDO_TABLE_SIZE + k];
    AlbedoEntry b = environment_albedo[object_index * ALBEDO_TABLE_SIZE + k + 1u];
    return AlbedoEntry(mix(a.diffuse, b.diffuse, t), mix(a.specular, b.specular, t));
}

// The fast mode's split sum.
vec3 environment_fast(Material m, vec3 n, vec3 wo, uint object_index) {
    AlbedoEntry albedo = environment_albedo_at(object_index, dot(n, wo));
    vec3 light = vec3(0.0);
    if (VIEW != VIEW_SPECULAR) {
        light += albedo.diffuse.rgb * irradiance_over_pi(n);
    }
    if (VIEW != VIEW_DIFFUSE && has_lobe(m)) {
        light += albedo.specular.rgb * prefiltered(mirror(n, wo), lobe_exponent(m));
    }
    return light;
}

// The environment's light at a point of the object drawn, in the pipeline's mode.
vec3 environment_light(Material m, vec3 n, vec3 t, vec3 wo) {
#ifndef WEBGL
    if (ENVIRONMENT == ENVIRONMENT_EXACT) {
        return environment_exact(m, n, t, wo);
    }
#endif
    if (ENVIRONMENT == ENVIRONMENT_FAST) {
        return environment_fast(m, n, wo, draw.object_index);
    }
    return vec3(0.0);
}

#endif
