#version 460
#extension GL_EXT_control_flow_attributes : require

// The albedo probe: integrates f_r(wi, wo) cos(theta_i) over cells of the hemisphere of wi, with brdf_eval,
// the very function the forward pass shades with, so that an albedo, a furnace table and a render can never
// disagree. Each invocation takes one cell (a theta_i x phi_i rectangle) of one job (a material and wo) and
// returns two estimates of its integral (common/albedo_cell.glsl, which the browser's web/albedo.frag shares):
// their difference bounds the error, and the CPU (crates/cubature) splits the cells where it is too large and
// adds the cells in double precision.

#define MEASURED_BINDING 3
#define ANALYTIC_BINDING 4
#define ANALYTIC_REPORT_BINDING 5
#include "common/brdf.glsl"
#include "common/albedo_cell.glsl"

layout(local_size_x = 64) in;

struct AlbedoJob {
    Material material;
    vec4 wo;  // xyz
};

struct AlbedoCell {
    vec4 bounds;  // theta_i from x to y, phi_i from z to w (radians)
    uint job;
    uint pad0;
    uint pad1;
    uint pad2;
};

layout(set = 0, binding = 0, std430) readonly buffer Jobs { AlbedoJob jobs[]; };
layout(set = 0, binding = 1, std430) readonly buffer Cells { AlbedoCell cells[]; };
// Per cell: the Kronrod estimate, then the Gauss estimate.
layout(set = 0, binding = 2, std430) writeonly buffer Results { vec4 results[]; };
// Binding 3: the measured tables (brdf/measured.glsl); 4 and 5: the analytic materials' values and their
// report (common/analytic.glsl).

layout(push_constant) uniform Probe { uint cell_count; } probe;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= probe.cell_count) {
        return;
    }
    AlbedoCell cell = cells[i];
    AlbedoJob job = jobs[cell.job];
    CellEstimate estimate = integrate_cell(job.material, job.wo.xyz, cell.bounds);
    results[2 * i] = vec4(estimate.kronrod, 0.0);
    results[2 * i + 1] = vec4(estimate.gauss, 0.0);
}
