#ifndef BRDF_RGL_GLSL
#define BRDF_RGL_GLSL

#include "common/math.glsl"

// Anisotropic RGL materials (Dupuy and Jakob 2018, "An Adaptive Parameterization for Efficient Material
// Acquisition and Rendering"), evaluated as their file defines them: the half vector's point in the NDF's
// square, that point's variate under the incident direction's warp of visible normals (a piecewise-bilinear
// density, inverted through its cumulative sums), the values interpolated there, times D(m) / (4 sigma(wi))
// when the values hold the warp's Jacobian. The material is packed in a measured table's place
// (RglTable::pack in src/brdf/rgl/mod.rs); mirrors RglTable::eval_local and Grid2D (src/brdf/rgl/warp.rs),
// function by function. Included by brdf/measured.glsl, which defines measured_float.

// The packed header (PACKED_HEADER floats): the material's flags and incident angles, then per grid
// (ndf, sigma, vndf, rgb) its width, height and the offsets of its values, conditional and marginal sums.
const uint RGL_ISOTROPIC = 0u;
const uint RGL_REDUCTION = 1u;
const uint RGL_JACOBIAN = 2u;
const uint RGL_PHI_COUNT = 3u;
const uint RGL_THETA_COUNT = 4u;
const uint RGL_PHI_OFFSET = 5u;
const uint RGL_THETA_OFFSET = 6u;
const uint RGL_NDF = 7u;
const uint RGL_SIGMA = 12u;
const uint RGL_VNDF = 17u;
const uint RGL_RGB = 22u;

uint rgl_uint(uint table, uint i) { return uint(measured_float(table, i) + 0.5); }

struct RglGrid {
    uint table;
    uint width;
    uint height;
    uint values;
    uint conditional;
    uint marginal;
};

RglGrid rgl_grid(uint table, uint header) {
    return RglGrid(table, rgl_uint(table, header), rgl_uint(table, header + 1u), rgl_uint(table, header + 2u),
                   rgl_uint(table, header + 3u), rgl_uint(table, header + 4u));
}

// The grids around a parameter point and their weights (Grid2D::corners): up to two parameters, each linear
// between the two values around it (clamped at the ends), a parameter of one value skipped.
struct RglCorners {
    uvec4 grid;
    vec4 weight;
};

// The value below p among a parameter's `count` values at `offset` (the last excluded), and p's place
// between it and the next, in [0, 1].
vec2 rgl_between(uint table, uint offset, uint count, float p) {
    uint below = 0u;
    for (uint k = 1u; k + 1u < count; ++k) {
        if (measured_float(table, offset + k) <= p) {
            below = k;
        }
    }
    float v0 = measured_float(table, offset + below);
    float v1 = measured_float(table, offset + below + 1u);
    return vec2(float(below), clamp((p - v0) / (v1 - v0), 0.0, 1.0));
}

// The incident direction's corners among the (phi_i, theta_i) grids, `per` grids for each (3 for the
// channels of rgb, whose `channel` is then added).
RglCorners rgl_corners(uint table, float phi_i, float theta_i, uint per, uint channel) {
    uint phis = rgl_uint(table, RGL_PHI_COUNT);
    uint thetas = rgl_uint(table, RGL_THETA_COUNT);
    vec2 phi = phis > 1u ? rgl_between(table, rgl_uint(table, RGL_PHI_OFFSET), phis, phi_i) : vec2(0.0);
    vec2 theta = thetas > 1u ? rgl_between(table, rgl_uint(table, RGL_THETA_OFFSET), thetas, theta_i) : vec2(0.0);
    uint p0 = uint(phi.x);
    uint t0 = uint(theta.x);
    uint p1 = phis > 1u ? p0 + 1u : p0;
    uint t1 = thetas > 1u ? t0 + 1u : t0;
    uvec4 grid = (uvec4(p0, p0, p1, p1) * thetas + uvec4(t0, t1, t0, t1)) * per + channel;
    vec4 weight = vec4(1.0 - phi.y, 1.0 - phi.y, phi.y, phi.y) * vec4(1.0 - theta.y, theta.y, 1.0 - theta.y, theta.y);
    return RglCorners(grid, weight);
}

RglCorners rgl_no_parameter() { return RglCorners(uvec4(0u), vec4(1.0, 0.0, 0.0, 0.0)); }

// An array's entry `index` of each grid (of `per_grid` entries), weighed by the corners (Grid2D::lookup).
float rgl_lookup(uint table, uint array, uint per_grid, RglCorners c, uint index) {
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (c.weight[k] > 0.0) {
            sum += c.weight[k] * measured_float(table, array + c.grid[k] * per_grid + index);
        }
    }
    return sum;
}

// The cell of `position` (clamped into the square): its corner (x, y) and the position within it.
void rgl_cell(RglGrid g, vec2 position, out uvec2 cell, out vec2 f) {
    vec2 scaled = clamp(position, 0.0, 1.0) * vec2(float(g.width - 1u), float(g.height - 1u));
    cell = min(uvec2(scaled), uvec2(g.width - 2u, g.height - 2u));
    f = scaled - vec2(cell);
}

// The values at the cell's corners: (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1).
vec4 rgl_corner_values(RglGrid g, RglCorners c, uvec2 cell) {
    uint cells = g.width * g.height;
    uint i = cell.y * g.width + cell.x;
    return vec4(rgl_lookup(g.table, g.values, cells, c, i), rgl_lookup(g.table, g.values, cells, c, i + 1u),
                rgl_lookup(g.table, g.values, cells, c, i + g.width),
                rgl_lookup(g.table, g.values, cells, c, i + g.width + 1u));
}

// A function's value at `position` (Grid2D::eval).
float rgl_eval(RglGrid g, RglCorners c, vec2 position) {
    uvec2 cell;
    vec2 f;
    rgl_cell(g, position, cell, f);
    vec4 v = rgl_corner_values(g, c, cell);
    return (1.0 - f.y) * ((1.0 - f.x) * v.x + f.x * v.y) + f.y * ((1.0 - f.x) * v.z + f.x * v.w);
}

// A density's cumulative distribution at `position`: the variate its sampling maps to it (Grid2D::invert).
vec2 rgl_invert(RglGrid g, RglCorners c, vec2 position) {
    uvec2 cell;
    vec2 f;
    rgl_cell(g, position, cell, f);
    vec4 v = rgl_corner_values(g, c, cell);
    float c0 = (1.0 - f.y) * v.x + f.y * v.z;
    float c1 = (1.0 - f.y) * v.y + f.y * v.w;
    uint cells = g.width * g.height;
    uint w = g.width;
    float before = (1.0 - f.y) * rgl_lookup(g.table, g.conditional, cells, c, cell.y * w + cell.x) +
                   f.y * rgl_lookup(g.table, g.conditional, cells, c, (cell.y + 1u) * w + cell.x);
    float r0 = rgl_lookup(g.table, g.conditional, cells, c, cell.y * w + w - 1u);
    float r1 = rgl_lookup(g.table, g.conditional, cells, c, (cell.y + 1u) * w + w - 1u);
    float u = (before + f.x * (c0 + 0.5 * f.x * (c1 - c0))) / ((1.0 - f.y) * r0 + f.y * r1);
    float below = rgl_lookup(g.table, g.marginal, g.height, c, cell.y);
    return vec2(u, below + f.y * (r0 + 0.5 * f.y * (r1 - r0)));
}

// theta to the square's coordinate, sqrt(theta / (pi/2)); phi in [-pi, pi] to [0, 1].
float rgl_theta_to_unit(float theta) { return sqrt(max(theta * (2.0 / PI), 0.0)); }
float rgl_phi_to_unit(float phi) { return (phi + PI) / (2.0 * PI); }

// atan(y, x) to within 1e-7 radians. Vulkan lets a device's own atan, asin and acos be far coarser (4096
// ULP; lavapipe's are about 1e-3 off), and an RGL material's warp is steep by the horizon: with them, a
// grazing light's f_r was 1.4% from the reader's. atan(t) on [-1, 1] is Abramowitz and Stegun's 4.4.49, a
// polynomial of degree 15 (error 2e-8); the octant by the larger of |x| and |y|.
float rgl_atan2(float y, float x) {
    float ax = abs(x);
    float ay = abs(y);
    float t = min(ax, ay) / max(max(ax, ay), 1e-30);
    float t2 = t * t;
    float a = t * (0.9999993329 + t2 * (-0.3332985605 + t2 * (0.1994653599 + t2 * (-0.1390853351 + t2 *
              (0.0964200441 + t2 * (-0.0559098861 + t2 * (0.0218612288 + t2 * -0.0040540580)))))));
    a = ay > ax ? 0.5 * PI - a : a;
    a = x < 0.0 ? PI - a : a;
    return y < 0.0 ? -a : a;
}

// The angle of unit d from the normal (0, 0, 1) (elevation in src/brdf/rgl/mod.rs).
float rgl_elevation(vec3 d) { return rgl_atan2(length(d.xy), d.z); }

// x negated where s is positive or zero.
float rgl_against_sign(float x, float s) { return s >= 0.0 ? -x : x; }

// f_r of the material in table `table` for the light `light` and the view `view` in the surface's frame
// (normal +z, tangent +x), both above the horizon. The file's incident direction is the view.
vec3 rgl_eval_local(uint table, vec3 light, vec3 view) {
    vec3 incident = view;
    vec3 outgoing = light;
    uint reduction = rgl_uint(table, RGL_REDUCTION);
    if (reduction >= 2u) {
        float sy = incident.y;
        float sx = reduction == 4u ? incident.x : sy;
        incident.xy = vec2(rgl_against_sign(incident.x, sx), rgl_against_sign(incident.y, sy));
        outgoing.xy = vec2(rgl_against_sign(outgoing.x, sx), rgl_against_sign(outgoing.y, sy));
    }
    vec3 m = normalize(incident + outgoing);
    float theta_i = rgl_elevation(incident);
    float phi_i = rgl_atan2(incident.y, incident.x);
    float phi_m = rgl_atan2(m.y, m.x);
    float relative = rgl_uint(table, RGL_ISOTROPIC) != 0u ? phi_m - phi_i : phi_m;
    vec2 u_m = vec2(rgl_theta_to_unit(rgl_elevation(m)), rgl_phi_to_unit(relative));
    u_m.y -= floor(u_m.y);
    vec2 sample_point = rgl_invert(rgl_grid(table, RGL_VNDF), rgl_corners(table, phi_i, theta_i, 1u, 0u), u_m);
    RglGrid rgb = rgl_grid(table, RGL_RGB);
    vec3 value = vec3(rgl_eval(rgb, rgl_corners(table, phi_i, theta_i, 3u, 0u), sample_point),
                      rgl_eval(rgb, rgl_corners(table, phi_i, theta_i, 3u, 1u), sample_point),
                      rgl_eval(rgb, rgl_corners(table, phi_i, theta_i, 3u, 2u), sample_point));
    if (rgl_uint(table, RGL_JACOBIAN) != 0u) {
        vec2 u_i = vec2(rgl_theta_to_unit(theta_i), rgl_phi_to_unit(phi_i));
        value *= rgl_eval(rgl_grid(table, RGL_NDF), rgl_no_parameter(), u_m) /
                 (4.0 * rgl_eval(rgl_grid(table, RGL_SIGMA), rgl_no_parameter(), u_i));
    }
    return value / outgoing.z;
}

#endif
