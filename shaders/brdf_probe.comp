#version 460

// The BRDF probe: evaluates brdf_eval, the very function the forward pass shades with, for a list of
// (material, n, wi, wo) cases, so that tests can compare every GLSL BRDF with its Rust mirror.

#define MEASURED_BINDING 2
#define ANALYTIC_BINDING 3
#define ANALYTIC_REPORT_BINDING 4
// The probe reports an analytic model's NaN, infinite and negative values as they are (a fit must see them).
#define ANALYTIC_KEEPS_INVALID
#include "common/brdf.glsl"

layout(local_size_x = 64) in;

struct ProbeCase {
    Material material;
    vec4 n;   // xyz
    vec4 wi;  // xyz
    vec4 wo;  // xyz
};

layout(set = 0, binding = 0, std430) readonly buffer Cases { ProbeCase cases[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Results { vec4 results[]; };
// Binding 2: the measured tables (brdf/measured.glsl); 3 and 4: the analytic materials' values and their
// report (common/analytic.glsl).
// The frame of each case is n and default_tangent(n): on n = +z, BRDF Explorer's X = +x and Y = +y.

layout(push_constant) uniform Probe { uint case_count; } probe;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= probe.case_count) {
        return;
    }
    ProbeCase c = cases[i];
    vec3 n = c.n.xyz;
    results[i] = vec4(brdf_eval(c.material, n, default_tangent(n), c.wi.xyz, c.wo.xyz), 0.0);
}
