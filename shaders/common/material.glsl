#ifndef COMMON_MATERIAL_GLSL
#define COMMON_MATERIAL_GLSL

// Mirrored byte for byte by GpuMaterial in src/render/gpu_types.rs.

// A material: which BRDF (see brdf.glsl) and every model's parameters.
struct Material {
    vec4 kd;         // rgb
    vec4 ks;         // rgb
    vec4 f0;         // rgb
    uint brdf;       // BRDF_*
    float shininess;
    float sigma;
    float roughness;
    float metalness;
    uint diffuse;    // DIFFUSE_* under a Cook-Torrance lobe
    uint measured;   // under BRDF_MEASURED: the material's table in MeasuredTables (brdf/measured.glsl)
    uint analytic;   // under BRDF_ANALYTIC: its first value in analytic_parameters (common/analytic.glsl)
};

#endif
