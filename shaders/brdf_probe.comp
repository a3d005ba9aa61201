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

// The directions, packed as float32: 9 a case in a list (n, wi, wo), 6 in a grid (wi, wo; n = +z). Mesa 22's
// lavapipe reads a storage buffer one lane and one component at a time, so the 12 floats of three vec4 and a
// vec4 result cost a fit's probe a sixth of its time (docs/tests.md).
layout(set = 0, binding = 0, std430) readonly buffer Materials { Material materials[]; };
layout(set = 0, binding = 1, std430) readonly buffer AllDirections { float directions[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Results { float results[]; };
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
    bool grid = probe.grid_directions != 0u;
    uint material = grid ? c / probe.grid_directions : c;
    uint at = grid ? 6u * (c % probe.grid_directions) : 9u * c;
    vec3 n = vec3(0.0, 0.0, 1.0);
    if (!grid) {
        n = vec3(directions[at], directions[at + 1u], directions[at + 2u]);
        at += 3u;
    }
    vec3 wi = vec3(directions[at], directions[at + 1u], directions[at + 2u]);
    vec3 wo = vec3(directions[at + 3u], directions[at + 4u], directions[at + 5u]);
    vec3 f = brdf_eval(materials[material], n, default_tangent(n), wi, wo);
    results[3u * i] = f.x;
    results[3u * i + 1u] = f.y;
    results[3u * i + 2u] = f.z;
}
