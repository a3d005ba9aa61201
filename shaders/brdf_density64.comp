#version 460

// A model's density and f_r cos(theta_i) in double precision, at given directions for one view: a .brdf file's
// own GLSL with every float made a double (crates/brdf-file/src/glsl.rs, Precision::Double; its exp, pow, sin
// and the like those of common/float64.glsl), or the built-in models' (brdf_eval and material_pdf of these
// very shaders, made double by brdf_file::shader_in_double as the compiler includes them from double/). The integrals the commands state of a model (its density's, its
// directional albedo) are of the model, not of its float32 rounding: a file that writes GGX's D as
// a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2) rounds a^2 - 1 once, and at a^2 = 4e-5 its float D seen head-on
// integrates 4e-4 above the model's. The samples are still drawn in float (brdf_sample.comp), as the renderer
// draws them. Bindings as brdf_sample.comp's, so that the probe's dispatch binds both alike.

#include "common/material.glsl"
#include "common/float64.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) readonly buffer Job {
    Material material;
    vec4 wo;
} job;
layout(set = 0, binding = 1, std430) readonly buffer Directions { dvec4 directions[]; };
// Per direction: (density, f_r cos(theta_i)).
layout(set = 0, binding = 2, std430) writeonly buffer Results { dvec4 results[]; };
// Binding 3 (the measured tables) is not read; 4: the analytic materials' values (common/analytic.glsl's).
layout(set = 0, binding = 4, std430) readonly buffer AnalyticParameters { float analytic_parameters[]; };
float analytic_parameter(uint k) { return analytic_parameters[k]; }

layout(push_constant) uniform Evaluations {
    uint count;
} evaluations;

#ifdef ANALYTIC_BRDF
#include "brdf/analytic.glsl"
#else
// The built-in models, the measured tables left out (they are looked up in float).
#define BRDF_IN_DOUBLE
#include "double/common/sampling.glsl"
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= evaluations.count) {
        return;
    }
    dvec3 n = dvec3(0.0LF, 0.0LF, 1.0LF);
    dvec3 t = dvec3(1.0LF, 0.0LF, 0.0LF);
    dvec3 wo = dvec3(job.wo.xyz);
    dvec3 wi = directions[i].xyz;
#ifdef ANALYTIC_BRDF
    uint first = job.material.analytic;
    dvec3 f_cos = wi.z > 0.0LF ? analytic_brdf(first, n, t, wi, wo) * wi.z : dvec3(0.0LF);
    // As material_pdf of common/sampling.glsl: the file's pdfBRDF as it gives it, else the cosine's.
#ifdef ANALYTIC_HAS_SAMPLER
    double pdf = analytic_pdf(first, n, t, wi, wo);
#else
    double pdf = max(wi.z, 0.0LF) / F64_PI;
#endif
#else
    dvec3 f_cos = wi.z > 0.0LF ? brdf_eval(job.material, n, t, wi, wo) * wi.z : dvec3(0.0LF);
    double pdf = material_pdf(job.material, n, t, wi, wo);
#endif
    results[i] = dvec4(pdf, f_cos);
}
