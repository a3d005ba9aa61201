#version 460
#extension GL_EXT_control_flow_attributes : require
// webgl

// The browser's albedo probe (WebGL2 has no compute shaders: brdf_albedo.comp's work as a fragment pass, for
// the explore page's albedo of a student's model: editor.js). Pixel (x, y) integrates f_r cos(theta_i) of
// brdf_eval, the very function the forward pass shades with, for the drawn object's material over one cell
// (common/albedo_cell.glsl, the renderer's cell integral): albedo_cells' texel (2x, y) holds the cell's
// bounds (theta_i from x to y, phi_i from z to w), (2x + 1, y) its wo. Two float targets: the Kronrod
// estimate, with alpha 1 where an analytic model's loops were stopped by their guard (common/analytic.glsl),
// and the Gauss one. crates/cubature, run by the page as WebAssembly, chooses the cells and adds them.

#define ANALYTIC_KEEPS_INVALID
#include "common/scene.glsl"
#include "common/brdf.glsl"
#include "common/albedo_cell.glsl"

layout(set = 0, binding = 12) uniform sampler2D albedo_cells;

layout(location = 0) out vec4 out_kronrod;
layout(location = 1) out vec4 out_gauss;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 bounds = texelFetch(albedo_cells, ivec2(2 * pixel.x, pixel.y), 0);
    vec3 wo = texelFetch(albedo_cells, ivec2(2 * pixel.x + 1, pixel.y), 0).xyz;
#ifdef ANALYTIC_BRDF
    analytic_stopped = false;
#endif
    CellEstimate estimate = integrate_cell(objects[draw.object_index].material, wo, bounds);
#ifdef ANALYTIC_BRDF
    out_kronrod = vec4(estimate.kronrod, analytic_stopped ? 1.0 : 0.0);
#else
    out_kronrod = vec4(estimate.kronrod, 0.0);
#endif
    out_gauss = vec4(estimate.gauss, 0.0);
}
