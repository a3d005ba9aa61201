#ifndef COMMON_BRDF_GLSL
#define COMMON_BRDF_GLSL

// Dispatch over the closed set of BRDFs; ids mirror src/render/gpu_types.rs.
//
// One shader with a switch rather than one pipeline per BRDF: the branch is uniform across a draw (one
// object, one material), so it costs next to nothing, every model shares the same forward and probe
// passes, and no pipeline permutations need building.

#include "common/scene.glsl"
#include "brdf/lambert.glsl"

const uint BRDF_LAMBERT = 0u;

// f_r(wi, wo) at a surface with unit normal n, without the cosine; wi and wo point away from the surface.
vec3 brdf_eval(Material m, vec3 n, vec3 wi, vec3 wo) {
    switch (m.brdf) {
        case BRDF_LAMBERT:
            return lambert(m.kd.rgb);
        default:
            return vec3(0.0);
    }
}

#endif
