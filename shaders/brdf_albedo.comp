#version 460
#extension GL_EXT_control_flow_attributes : require

// The albedo probe: integrates f_r(wi, wo) cos(theta_i) over cells of the hemisphere of wi, with brdf_eval,
// the very function the forward pass shades with, so that an albedo, a furnace table and a render can never
// disagree. Each invocation takes one cell (a theta_i x phi_i rectangle) of one job (a material and wo) and
// returns two estimates of its integral: the 15-point Gauss-Kronrod rule in both angles, and the 7-point
// Gauss rule embedded in it (Piessens et al. 1983, QUADPACK): their difference bounds the error, and the
// CPU (src/analysis/albedo.rs) splits the cells where it is too large and adds the cells in double precision.
//
// The frame: n = +z, X = +x, wo in the xz-plane (phi_o = 0), wi = (sin t cos p, sin t sin p, cos t).

#define MEASURED_BINDING 3
#define ANALYTIC_BINDING 4
#define ANALYTIC_REPORT_BINDING 5
#include "common/brdf.glsl"

layout(local_size_x = 64) in;

// The loops over the nodes are not unrolled: 15 x 15 copies of a user's BRDF (and of its report of invalid
// values), or of a measured table's lookup, made a shader lavapipe took minutes to compile when the dispatch
// first ran (a MERL copy's albedo: 465 s on a cold shader cache).
#define NODE_LOOP [[dont_unroll]]

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

// The 15 Kronrod nodes on [-1, 1], their weights, and the weights of the 7-point Gauss rule on the same
// nodes (zero where a Kronrod node is not a Gauss node).
const float NODES[15] = float[](
    -0.991455371120812639, -0.949107912342758525, -0.864864423359769073, -0.741531185599394440,
    -0.586087235467691130, -0.405845151377397167, -0.207784955007898468, 0.0,
    0.207784955007898468, 0.405845151377397167, 0.586087235467691130, 0.741531185599394440,
    0.864864423359769073, 0.949107912342758525, 0.991455371120812639);
const float KRONROD[15] = float[](
    0.022935322010529225, 0.063092092629978553, 0.104790010322250184, 0.140653259715525919,
    0.169004726639267903, 0.190350578064785410, 0.204432940075298892, 0.209482141084727828,
    0.204432940075298892, 0.190350578064785410, 0.169004726639267903, 0.140653259715525919,
    0.104790010322250184, 0.063092092629978553, 0.022935322010529225);
const float GAUSS[15] = float[](
    0.0, 0.129484966168869693, 0.0, 0.279705391489276668, 0.0, 0.381830050505118945, 0.0,
    0.417959183673469388,
    0.0, 0.381830050505118945, 0.0, 0.279705391489276668, 0.0, 0.129484966168869693, 0.0);

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= probe.cell_count) {
        return;
    }
    AlbedoCell cell = cells[i];
    AlbedoJob job = jobs[cell.job];
    vec3 n = vec3(0.0, 0.0, 1.0);
    vec2 theta_mid = vec2(0.5 * (cell.bounds.x + cell.bounds.y), 0.5 * (cell.bounds.y - cell.bounds.x));
    vec2 phi_mid = vec2(0.5 * (cell.bounds.z + cell.bounds.w), 0.5 * (cell.bounds.w - cell.bounds.z));
    vec3 kronrod = vec3(0.0);
    vec3 gauss = vec3(0.0);
    NODE_LOOP for (int a = 0; a < 15; ++a) {
        float theta = theta_mid.x + theta_mid.y * NODES[a];
        float sin_theta = sin(theta);
        float cos_theta = cos(theta);
        // The solid angle's sin(theta) and the integrand's cos(theta_i).
        float measure = sin_theta * cos_theta;
        vec3 kronrod_ring = vec3(0.0);
        vec3 gauss_ring = vec3(0.0);
        NODE_LOOP for (int b = 0; b < 15; ++b) {
            float phi = phi_mid.x + phi_mid.y * NODES[b];
            vec3 wi = vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
            vec3 f = brdf_eval(job.material, n, vec3(1.0, 0.0, 0.0), wi, job.wo.xyz);
            kronrod_ring += KRONROD[b] * f;
            gauss_ring += GAUSS[b] * f;
        }
        kronrod += KRONROD[a] * measure * kronrod_ring;
        gauss += GAUSS[a] * measure * gauss_ring;
    }
    float scale = theta_mid.y * phi_mid.y;
    results[2 * i] = vec4(scale * kronrod, 0.0);
    results[2 * i + 1] = vec4(scale * gauss, 0.0);
}
