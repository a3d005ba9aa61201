#ifndef COMMON_ANALYTIC_GLSL
#define COMMON_ANALYTIC_GLSL

// Analytic models (users' .brdf files, src/brdf/analytic/): their materials' values, and a report of the
// values no BRDF may give. brdf/analytic.glsl is made from the file at run time (crates/brdf-file/src/glsl.rs):
// the file's parameters as globals, its shader, and analytic_brdf(first, n, t, wi, wo). Mirrored by
// src/render/analytic.rs.

#if !defined(ANALYTIC_BINDING) || !defined(ANALYTIC_REPORT_BINDING)
#error "define ANALYTIC_BINDING and ANALYTIC_REPORT_BINDING before including common/analytic.glsl"
#endif

// Every analytic material's values, one after the other: a material's `analytic` is where its own begin.
#ifdef WEBGL
// The browser (no storage buffers): a uniform block of vec4s, four values each (std140 would pad a float
// array's every element to 16 bytes), of WebGL2's least uniform block size, 16 kB; the page writes it.
const uint ANALYTIC_VALUE_VECTORS = 1024u;
layout(set = 0, binding = ANALYTIC_BINDING, std140) uniform AnalyticParameters { vec4 analytic_values[ANALYTIC_VALUE_VECTORS]; };
float analytic_parameter(uint k) { return analytic_values[k / 4u][k % 4u]; }
// Whether the model's loops ran past their bound in its last evaluation: the browser's editor guards every
// loop of a student's file (brdf_file's WebGL wrapper), since one that never ends would hang the browser's
// GPU, and every page on it.
bool analytic_stopped;
#else
layout(set = 0, binding = ANALYTIC_BINDING, std430) readonly buffer AnalyticParameters { float analytic_parameters[]; };
float analytic_parameter(uint k) { return analytic_parameters[k]; }

// Where a BRDF gave NaN, an infinity or a negative value: how many evaluations did, and the first one's
// material, directions (in its frame: X, Y, N) and value. The forward pass binds each object's own report (a
// dynamic offset), so that no two draws write the same memory; the host reads them after the work. The
// browser has no atomics and reports nothing: the server's `render` does.
layout(set = 0, binding = ANALYTIC_REPORT_BINDING, std430) buffer AnalyticReport {
    uint invalid_count;
    uint invalid_material;
    uint invalid_pad0;
    uint invalid_pad1;
    vec4 invalid_wi;
    vec4 invalid_wo;
    vec4 invalid_value;
};
#endif

#include "brdf/analytic.glsl"

// The largest finite float.
const float FLOAT_MAX = 3.40282347e38;

// Whether each channel is NaN, infinite or negative: not in [0, FLOAT_MAX] (a NaN fails every comparison).
bvec3 invalid_channels(vec3 f) {
    return not(bvec3(f.x >= 0.0 && f.x <= FLOAT_MAX, f.y >= 0.0 && f.y <= FLOAT_MAX, f.z >= 0.0 && f.z <= FLOAT_MAX));
}

// The model's f_r, its invalid values reported (the first one's case recorded) and, in the images, taken as
// 0 (BRDF Explorer takes max(f, 0)); the probe keeps them as they are (ANALYTIC_KEEPS_INVALID), for the
// commands that study a model to see them.
vec3 analytic_checked(uint first, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    vec3 f = analytic_brdf(first, n, t, wi, wo);
    bvec3 invalid = invalid_channels(f);
    if (any(invalid)) {
#ifndef WEBGL
        if (atomicAdd(invalid_count, 1u) == 0u) {
            vec3 b = cross(n, t);
            invalid_material = first;
            invalid_wi = vec4(dot(wi, t), dot(wi, b), dot(wi, n), 0.0);
            invalid_wo = vec4(dot(wo, t), dot(wo, b), dot(wo, n), 0.0);
            invalid_value = vec4(f, 0.0);
        }
#endif
#ifndef ANALYTIC_KEEPS_INVALID
        f = mix(f, vec3(0.0), invalid);
#endif
    }
    return f;
}

#endif
