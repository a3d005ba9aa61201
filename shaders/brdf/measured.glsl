#ifndef BRDF_MEASURED_GLSL
#define BRDF_MEASURED_GLSL

#include "common/math.glsl"

// Measured materials: MERL tables (Matusik, Pfister, Brand and McMillan 2003, "A Data-Driven Reflectance
// Model"), indexed as the database's reader, BRDFRead.cpp, indexes them, and interpolated trilinearly between
// the entries' centres. Mirrors src/brdf/measured.rs, function by function.

// Every table the scene's materials use, one after the other (a material's `measured` is its table's place),
// f_r of each entry red, green and blue interleaved; a negative value was not measured. The binding is the
// including shader's (set 0).
#ifndef MEASURED_BINDING
#error "MEASURED_BINDING: define the binding of the measured tables before including brdf/measured.glsl"
#endif
// BRDF_SAMPLING_RES_THETA_H, _THETA_D and _PHI_D / 2 of BRDFRead.cpp.
const uint MERL_THETA_H_BINS = 90u;
const uint MERL_THETA_D_BINS = 90u;
const uint MERL_PHI_D_BINS = 180u;
const uint MERL_ENTRIES = MERL_THETA_H_BINS * MERL_THETA_D_BINS * MERL_PHI_D_BINS;

#ifdef WEBGL
// The browser's build: a float texture of MEASURED_TEXTURE_WIDTH texels a row (WebGL2's least texture
// size: every browser takes it), one entry (rgb) a texel (src/serve/pages/webgl.js makes it).
const uint MEASURED_TEXTURE_WIDTH = 2048u;
layout(set = 0, binding = MEASURED_BINDING) uniform sampler2D measured_tables;
vec3 measured_texel(uint table, uint index) {
    uint entry = table * MERL_ENTRIES + index;
    return texelFetch(measured_tables, ivec2(entry % MEASURED_TEXTURE_WIDTH, entry / MEASURED_TEXTURE_WIDTH), 0).rgb;
}
// Float i of a table's place (an anisotropic RGL material's packed floats: three a texel).
float measured_float(uint table, uint i) { return measured_texel(table, i / 3u)[i % 3u]; }
#else
// The renderer's build: each table's entries, then its sampler's floats (brdf/measured_sampler.glsl,
// src/brdf/measured_sampler.rs: SAMPLER_FLOATS).
const uint MEASURED_SAMPLER_FLOATS = 104768u;
const uint MEASURED_TABLE_FLOATS = 3u * MERL_ENTRIES + MEASURED_SAMPLER_FLOATS;
layout(set = 0, binding = MEASURED_BINDING, std430) readonly buffer MeasuredTables { float measured_tables[]; };
vec3 measured_texel(uint table, uint index) {
    uint i = table * MEASURED_TABLE_FLOATS + 3u * index;
    return vec3(measured_tables[i], measured_tables[i + 1u], measured_tables[i + 2u]);
}
float measured_float(uint table, uint i) { return measured_tables[table * MEASURED_TABLE_FLOATS + i]; }
#endif

#include "brdf/rgl.glsl"

// A material's `measured`: its table's place (a MERL table, or under BRDF_RGL an anisotropic RGL material's
// floats, brdf/rgl.glsl), and MEASURED_SAMPLED when the exact mode draws from the table's own sampler (the
// scene's `sampler`, true unless set false).
const uint MEASURED_SAMPLED = 0x80000000u;
uint measured_table(uint field) { return field & ~MEASURED_SAMPLED; }

// A unit vector perpendicular to unit n.
vec3 any_tangent(vec3 n) {
    vec3 axis = abs(n.x) < 0.5 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(axis - n * dot(n, axis));
}

// (theta_h, theta_d, phi_d) of Rusinkiewicz's half and difference vectors (1998, "A new change of variables for
// efficient BRDF representation"), as std_coords_to_half_diff_coords of BRDFRead.cpp: wi in the frame where h
// lies in the xz-plane, turned by -theta_h about y. phi_d in (-pi, pi].
vec3 half_diff_angles(vec3 n, vec3 wi, vec3 wo) {
    vec3 h = normalize(wi + wo);
    float NoH = clamp(dot(n, h), -1.0, 1.0);
    // When h is n, phi_h is undefined (the reader takes 0) and any tangent is one.
    vec3 toward_h = h - n * NoH;
    vec3 t = dot(toward_h, toward_h) > 1e-12 ? normalize(toward_h) : any_tangent(n);
    vec3 b = cross(n, t);
    float sin_theta_h = length(cross(n, h));
    float x = dot(wi, t * NoH - n * sin_theta_h);
    float y = dot(wi, b);
    return vec3(atan(sin_theta_h, NoH), acos(clamp(dot(wi, h), -1.0, 1.0)), atan(y, x));
}

// The table's continuous coordinates, entry k's centre at k: theta_h's index is sqrt(theta_h / 90 degrees) * 90
// (theta_half_index), theta_d's theta_d / 90 degrees * 90, phi_d's phi_d / 180 degrees * 180 once folded to
// [0, 180) degrees by reciprocity (phi_diff_index adds 180 degrees to a negative phi_d).
vec3 measured_coordinates(vec3 angles) {
    float phi_d = angles.z < 0.0 ? angles.z + PI : angles.z;
    return vec3(sqrt(max(angles.x, 0.0) / (0.5 * PI)) * float(MERL_THETA_H_BINS) - 0.5,
                angles.y / (0.5 * PI) * float(MERL_THETA_D_BINS) - 0.5,
                phi_d / PI * float(MERL_PHI_D_BINS) - 0.5);
}

// Entry (theta_h, theta_d, phi_d) of table `table`: phi_d + 180 (theta_d + 90 theta_h) (lookup_brdf_val).
vec3 measured_entry(uint table, uint theta_h, uint theta_d, uint phi_d) {
    return measured_texel(table, phi_d + MERL_PHI_D_BINS * (theta_d + MERL_THETA_D_BINS * theta_h));
}

// Trilinear between the eight entries around c, theta_h and theta_d held at their first and last entries'
// centres, phi_d wrapping round (180 degrees is 0 again); per channel, the measured corners only, their weights
// renormalised, and 0 where none is.
vec3 measured_lookup(uint table, vec3 c) {
    float th = clamp(c.x, 0.0, float(MERL_THETA_H_BINS - 1u));
    float td = clamp(c.y, 0.0, float(MERL_THETA_D_BINS - 1u));
    vec3 corner = floor(vec3(th, td, c.z));
    vec3 f = vec3(th, td, c.z) - corner;
    uint h[2] = uint[](uint(corner.x), min(uint(corner.x) + 1u, MERL_THETA_H_BINS - 1u));
    uint d[2] = uint[](uint(corner.y), min(uint(corner.y) + 1u, MERL_THETA_D_BINS - 1u));
    // corner.z is -1 below the first entry's centre: 179, the last, by the wrap (a whole turn added first,
    // since % of a negative number is undefined in GLSL).
    uint p0 = uint(corner.z + float(MERL_PHI_D_BINS)) % MERL_PHI_D_BINS;
    uint p[2] = uint[](p0, (p0 + 1u) % MERL_PHI_D_BINS);
    vec3 sum = vec3(0.0);
    vec3 weight = vec3(0.0);
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            for (int k = 0; k < 2; ++k) {
                vec3 v = measured_entry(table, h[i], d[j], p[k]);
                vec3 measured = vec3(greaterThanEqual(v, vec3(0.0)));
                float w = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y) * (k == 0 ? 1.0 - f.z : f.z);
                sum += w * measured * v;
                weight += w * measured;
            }
        }
    }
    return mix(vec3(0.0), sum / max(weight, vec3(1e-30)), greaterThan(weight, vec3(0.0)));
}

// f_r(wi, wo) of the material's table (its `measured`) about n, both above the horizon. Mirrors
// MeasuredTable::eval.
vec3 measured(uint field, vec3 n, vec3 wi, vec3 wo) {
    return measured_lookup(measured_table(field), measured_coordinates(half_diff_angles(n, wi, wo)));
}

// f_r(wi, wo) of an anisotropic RGL material in the table's place (its `measured`) about n with the tangent
// t, in the frame X = t, Y = n x t, both above the horizon. Mirrors MeasuredTable::eval_in_frame.
vec3 measured_rgl(uint field, vec3 n, vec3 t, vec3 wi, vec3 wo) {
    vec3 b = cross(n, t);
    return rgl_eval_local(measured_table(field), vec3(dot(wi, t), dot(wi, b), dot(wi, n)),
                          vec3(dot(wo, t), dot(wo, b), dot(wo, n)));
}

#endif
