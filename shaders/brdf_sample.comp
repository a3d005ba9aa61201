#version 460

// The sampler probe: a material's own sampler (material_sample of common/sampling.glsl, drawing from the
// lobes the exact mode draws from) run for one view direction, or its density evaluated at given
// directions with f_r cos(theta_i) beside it, so that `vk-render sampling` (src/analysis/sampling/) tests
// the very GLSL the renderer runs. The frame: n = +z, X = +x, Y = +y.

#define MEASURED_BINDING 3
#define ANALYTIC_BINDING 4
#define ANALYTIC_REPORT_BINDING 5
// NaN, infinite and negative values as they are: a sampler's test must see them.
#define ANALYTIC_KEEPS_INVALID
#include "common/sampling.glsl"

layout(local_size_x = 64) in;

// The job: one material and one view direction (xyz), as the albedo probe's.
layout(set = 0, binding = 0, std430) readonly buffer Job {
    Material material;
    vec4 wo;
} job;
// Density mode: the directions (xyz) to evaluate at.
layout(set = 0, binding = 1, std430) readonly buffer Directions { vec4 directions[]; };
// Draw mode: per sample (wi, its density), then (f_r, 0), f_r zero for no sample. Density mode: per
// direction (density, f_r cos(theta_i)).
layout(set = 0, binding = 2, std430) writeonly buffer Results { vec4 results[]; };
// Binding 3: the measured tables (brdf/measured.glsl); 4 and 5: the analytic materials' values and their
// report (common/analytic.glsl).

layout(push_constant) uniform Sampling {
    uint count;  // the items of this dispatch
    uint first;  // draw mode: the index of its first sample
    uint draw;   // 1: draw samples; 0: evaluate the density at `directions`
    uint seed;   // draw mode: the stream of random points
} sampling;

// Jarzynski and Olano 2020, "Hash functions for GPU rendering": pcg2d, their recommended hash of two
// words to two. Independent random points, not the exact mode's low-discrepancy sequence: Pearson's χ²
// assumes independent samples, and a sequence's too even counts would pass a wrong sampler.
uvec2 pcg2d(uvec2 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * 1664525u;
    v.y += v.x * 1664525u;
    v = v ^ (v >> 16u);
    v.x += v.y * 1664525u;
    v.y += v.x * 1664525u;
    v = v ^ (v >> 16u);
    return v;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= sampling.count) {
        return;
    }
    vec3 n = vec3(0.0, 0.0, 1.0);
    vec3 t = vec3(1.0, 0.0, 0.0);
    vec3 wo = job.wo.xyz;
    if (sampling.draw != 0u) {
        vec2 u = vec2(pcg2d(uvec2(sampling.first + i, sampling.seed)) >> 8u) * (1.0 / 16777216.0);
        vec3 wi = normalize(material_sample(job.material, n, t, wo, u));
        bool above = wi.z > 0.0;
        float pdf = above ? material_pdf(job.material, n, t, wi, wo) : 0.0;
        vec3 f = above ? brdf_eval(job.material, n, t, wi, wo) : vec3(0.0);
        results[2u * i] = vec4(wi, pdf);
        results[2u * i + 1u] = vec4(f, 0.0);
    } else {
        vec3 wi = directions[i].xyz;
        vec3 f_cos = wi.z > 0.0 ? brdf_eval(job.material, n, t, wi, wo) * wi.z : vec3(0.0);
        results[i] = vec4(material_pdf(job.material, n, t, wi, wo), f_cos);
    }
}
