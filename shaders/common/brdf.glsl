#ifndef COMMON_BRDF_GLSL
#define COMMON_BRDF_GLSL

// Dispatch over the closed set of BRDFs; ids mirror src/render/gpu_types.rs.
//
// The forward pass fixes the BRDF when it builds a pipeline (BRDF_SPECIALIZED, a specialization constant):
// a CPU rasterizer such as lavapipe runs both sides of a branch with the lanes that do not take it masked
// off, so a switch over the material's id would evaluate every model for every fragment. The probe passes
// fix it too, one pipeline per BRDF (src/render/probe.rs): with every case live, lavapipe compiles them all,
// the measured lookup's among them, for every pipeline.
//
// An analytic model (a user's .brdf file, src/brdf/analytic/) is compiled in only where ANALYTIC_BRDF is
// defined, at run time, with brdf/analytic.glsl made from the file: one compilation per file and entry
// shader, its pipelines specialized to BRDF_ANALYTIC. The shaders compiled at build time do not have it.
//
// BRDF_IN_DOUBLE: this file made double (brdf_density64.comp's built-in models) leaves the measured tables
// out, which are looked up in float whatever evaluates them.

#include "common/material.glsl"
#include "brdf/lambert.glsl"
#include "brdf/oren_nayar.glsl"
#include "brdf/phong.glsl"
#include "brdf/blinn_phong.glsl"
#include "brdf/cook_torrance.glsl"
#ifndef BRDF_IN_DOUBLE
#include "brdf/measured.glsl"
#endif
#ifdef ANALYTIC_BRDF
#include "common/analytic.glsl"
#endif

const uint BRDF_LAMBERT = 0u;
const uint BRDF_OREN_NAYAR = 1u;
const uint BRDF_PHONG = 2u;
const uint BRDF_BLINN_PHONG = 3u;
const uint BRDF_COOK_TORRANCE = 4u;
const uint BRDF_MEASURED = 5u;
const uint BRDF_ANALYTIC = 6u;
// An anisotropic RGL file (brdf/rgl.glsl), its floats in a measured table's place: an id of its own, so that
// the measured tables' pipelines do not compile its evaluation.
const uint BRDF_RGL = 7u;
const uint BRDF_FROM_MATERIAL = 0xFFFFFFFFu;

layout(constant_id = 0) const uint BRDF_SPECIALIZED = BRDF_FROM_MATERIAL;
// The same for the diffuse lobe under Cook-Torrance (DIFFUSE_* of cook_torrance.glsl).
layout(constant_id = 3) const uint DIFFUSE_SPECIALIZED = BRDF_FROM_MATERIAL;

// The material's BRDF id: the pipeline's when it fixes one, so that a branch on it is settled when the
// pipeline is built.
uint brdf_id(Material m) { return BRDF_SPECIALIZED == BRDF_FROM_MATERIAL ? m.brdf : BRDF_SPECIALIZED; }

// The tangent of a surface of unit normal n whose shape gives none (spheres, meshes without texture
// coordinates, the probe's frame): BRDF Explorer's lit sphere's, normalize(+y x n), which is +x on the
// probe's frame n = +z; +x at the poles, where +y x n vanishes. Mirrors default_tangent in
// src/brdf/analytic/mod.rs. Only an analytic model reads the tangent.
vec3 default_tangent(vec3 n) {
    vec3 t = vec3(n.z, 0.0, -n.x);  // +y x n
    return dot(t, t) > 1e-12 ? normalize(t) : vec3(1.0, 0.0, 0.0);
}

// The tangent at a point of unit normal n whose vertices give one (a mesh's, from its texture coordinates by
// MikkTSpace): the interpolated vertex tangent made perpendicular to n (which the viewer may have flipped or
// bent); default_tangent(n) where there is none (zero) or it is along n. Mirrors surface_tangent in
// src/brdf/analytic/mod.rs.
vec3 surface_tangent(vec3 n, vec3 vertex_tangent) {
    vec3 t = vertex_tangent - n * dot(n, vertex_tangent);
    return dot(t, t) > 1e-8 * dot(vertex_tangent, vertex_tangent) ? normalize(t) : default_tangent(n);
}

// A plane's tangent: the world's +x projected on it; the world's +z for a plane facing +-x. Mirrors
// plane_tangent in src/brdf/analytic/mod.rs.
vec3 plane_tangent(vec3 n) {
    vec3 along_x = vec3(1.0, 0.0, 0.0) - n * n.x;
    return dot(along_x, along_x) > 1e-12 ? normalize(along_x) : normalize(vec3(0.0, 0.0, 1.0) - n * n.z);
}

// f_r(wi, wo) at a surface with unit normal n and unit tangent t (the frame X = t, Y = n x t, which only an
// analytic model reads), without the cosine; wi and wo point away from the surface. Mirrors Brdf::eval in
// src/brdf/mod.rs. Reflection only: zero when wi or wo is at or below the horizon; every model relies on
// this check, made here once.
vec3 brdf_eval(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    if (dot(n, wi) <= 0.0 || dot(n, wo) <= 0.0) {
        return vec3(0.0);
    }
    switch (brdf_id(m)) {
        case BRDF_LAMBERT:
            return lambert(m.kd.rgb);
        case BRDF_OREN_NAYAR:
            return oren_nayar(n, wi, wo, m.kd.rgb, m.sigma);
        case BRDF_PHONG:
            return phong(n, wi, wo, m.kd.rgb, m.ks.rgb, m.shininess);
        case BRDF_BLINN_PHONG:
            return blinn_phong(n, wi, wo, m.kd.rgb, m.ks.rgb, m.shininess);
        case BRDF_COOK_TORRANCE:
            return cook_torrance(n, wi, wo, m.kd.rgb, m.f0.rgb, m.roughness, m.metalness,
                                 DIFFUSE_SPECIALIZED == BRDF_FROM_MATERIAL ? m.diffuse : DIFFUSE_SPECIALIZED);
#ifndef BRDF_IN_DOUBLE
        case BRDF_MEASURED:
            return measured(m.measured, n, wi, wo);
        case BRDF_RGL:
            return measured_rgl(m.measured, n, t, wi, wo);
#endif
#ifdef ANALYTIC_BRDF
        case BRDF_ANALYTIC:
            return analytic_checked(m.analytic, n, t, wi, wo);
#endif
        default:
            return vec3(0.0);
    }
}

// The diffuse and the specular lobe of brdf_eval apart (they add up to it): Lambert and Oren-Nayar are all
// diffuse; Phong and Blinn-Phong are Lambert plus their lobe; Cook-Torrance weighs its lobes by metalness; a
// measurement or an analytic model is not split into lobes and counts whole as diffuse.
// Mirror Brdf::eval_diffuse and Brdf::eval_specular in src/brdf/mod.rs; the diffuse and specular views show
// what each reflects.
vec3 brdf_eval_diffuse(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    if (dot(n, wi) <= 0.0 || dot(n, wo) <= 0.0) {
        return vec3(0.0);
    }
    switch (m.brdf) {
        case BRDF_OREN_NAYAR:
            return oren_nayar(n, wi, wo, m.kd.rgb, m.sigma);
        case BRDF_COOK_TORRANCE:
            return (1.0 - m.metalness) * (m.diffuse == DIFFUSE_LAMBERT ? lambert(m.kd.rgb)
                                                                        : oren_nayar(n, wi, wo, m.kd.rgb, m.roughness));
        case BRDF_MEASURED:
        case BRDF_RGL:
        case BRDF_ANALYTIC:
            return brdf_eval(m, n, t, wi, wo);
        default:
            return lambert(m.kd.rgb);
    }
}

vec3 brdf_eval_specular(Material m, vec3 n, vec3 wi, vec3 wo) {
    if (dot(n, wi) <= 0.0 || dot(n, wo) <= 0.0) {
        return vec3(0.0);
    }
    switch (m.brdf) {
        case BRDF_PHONG:
            return phong_specular(n, wi, wo, m.ks.rgb, m.shininess);
        case BRDF_BLINN_PHONG:
            return blinn_phong_specular(n, wi, wo, m.ks.rgb, m.shininess);
        case BRDF_COOK_TORRANCE:
            return m.metalness * cook_torrance_specular(n, wi, wo, m.f0.rgb, m.roughness);
        default:
            return vec3(0.0);
    }
}

#endif
