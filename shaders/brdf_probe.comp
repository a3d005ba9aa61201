#version 460

// The BRDF probe: evaluates brdf_eval, the very function the forward pass shades with, for (material, n,
// wi, wo) cases, so that tests can compare every GLSL BRDF with its Rust mirror, and the commands that study a
// model plot and fit it. The cases are a list (case i: material i at directions i) or a grid (every material
// at every directions, as a fit asks for its lobes at one set of directions: each uploaded once).

#define MEASURED_BINDING 3
#define ANALYTIC_BINDING 4
#define ANALYTIC_REPORT_BINDING 5
// The probe reports an analytic model's NaN, infinite and negative values as they are (a fit must see them).
#define ANALYTIC_KEEPS_INVALID
#include "common/brdf.glsl"

layout(local_size_x = 64) in;

struct Directions {
    vec4 n;   // xyz
    vec4 wi;  // xyz
    vec4 wo;  // xyz
};

layout(set = 0, binding = 0, std430) readonly buffer Materials { Material materials[]; };
layout(set = 0, binding = 1, std430) readonly buffer AllDirections { Directions directions[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Results { vec4 results[]; };
// Binding 3: the measured tables (brdf/measured.glsl); 4 and 5: the analytic materials' values and their
// report (common/analytic.glsl).
// The frame of each case is n and default_tangent(n): on n = +z, BRDF Explorer's X = +x and Y = +y.

// This dispatch's cases are first .. first + count - 1 of the grid of materials x grid_directions (0: of the
// list), its results from results[0].
layout(push_constant) uniform Probe {
    uint count;
    uint first;
    uint grid_directions;
} probe;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= probe.count) {
        return;
    }
    uint c = probe.first + i;
    uint material = probe.grid_directions == 0u ? c : c / probe.grid_directions;
    Directions d = directions[probe.grid_directions == 0u ? c : c % probe.grid_directions];
    vec3 n = d.n.xyz;
    results[i] = vec4(brdf_eval(materials[material], n, default_tangent(n), d.wi.xyz, d.wo.xyz), 0.0);
}
