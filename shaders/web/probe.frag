#version 460
// webgl

// The browser's BRDF probe (WebGL2 has no compute shaders: brdf_probe.comp's work as a fragment pass, for
// the explore page's lobe of a student's model: editor.js). Pixel (k, 0) evaluates brdf_eval, the very
// function the forward pass shades with, for the drawn object's material at the k-th pair of directions
// (probe_directions' texel (k, 0) is wi, (k, 1) wo; n = +z, and X = +x, as the probe's frame), into a float
// target: f_r as it is (invalid values kept, as the probe keeps them), and in alpha 1 where an analytic model's
// loops were stopped by their guard (common/analytic.glsl), else 0.

#define ANALYTIC_KEEPS_INVALID
#include "common/scene.glsl"
#include "common/brdf.glsl"

layout(set = 0, binding = 12) uniform sampler2D probe_directions;

layout(location = 0) out vec4 out_value;

void main() {
    ivec2 k = ivec2(int(gl_FragCoord.x), 0);
    vec3 wi = texelFetch(probe_directions, k, 0).xyz;
    vec3 wo = texelFetch(probe_directions, k + ivec2(0, 1), 0).xyz;
    vec3 n = vec3(0.0, 0.0, 1.0);
#ifdef ANALYTIC_BRDF
    analytic_stopped = false;
#endif
    vec3 f = brdf_eval(objects[draw.object_index].material, n, default_tangent(n), wi, wo);
#ifdef ANALYTIC_BRDF
    out_value = vec4(f, analytic_stopped ? 1.0 : 0.0);
#else
    out_value = vec4(f, 0.0);
#endif
}
