#ifndef COMMON_ALBEDO_CELL_GLSL
#define COMMON_ALBEDO_CELL_GLSL

// One cell of a directional albedo's cubature (crates/cubature decides the cells): f_r(wi, wo) cos(theta_i)
// of brdf_eval integrated over a theta_i x phi_i rectangle by the 15-point Gauss-Kronrod rule in both angles,
// and by the 7-point Gauss rule embedded in it (Piessens et al. 1983, QUADPACK), whose difference bounds the
// error. Shared by the renderer's albedo probe (brdf_albedo.comp) and the browser's (web/albedo.frag).
//
// The frame: n = +z, X = +x, wo in the xz-plane (phi_o = 0), wi = (sin t cos p, sin t sin p, cos t).
// The including entry enables GL_EXT_control_flow_attributes.

// The loops over the nodes are not unrolled: 15 x 15 copies of a user's BRDF (and of its report of invalid
// values), or of a measured table's lookup, made a shader lavapipe took minutes to compile when the dispatch
// first ran (a MERL copy's albedo: 465 s on a cold shader cache).
#define NODE_LOOP [[dont_unroll]]

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

// sin(x) and cos(x) for x in [0, pi] to float precision (an absolute error near 1e-7), by the Taylor series
// of y = x - pi/2 to its y^14 term (the next term is below 1e-9 there): sin x = cos y, cos x = -sin y. The
// GPU's own are allowed an absolute error of 2^-11 (Vulkan's and GLSL ES's precision tables), and
// SwiftShader's made a Lambertian albedo 4e-5 low, four times the cubature's tolerance.
vec2 node_sin_cos(float x) {
    float y = x - 1.57079632679489662;
    float y2 = y * y;
    float sin_y = y * (1.0 + y2 * (-1.0 / 6.0 + y2 * (1.0 / 120.0 + y2 * (-1.0 / 5040.0 + y2 * (1.0 / 362880.0
        + y2 * (-1.0 / 39916800.0 + y2 * (1.0 / 6227020800.0)))))));
    float cos_y = 1.0 + y2 * (-0.5 + y2 * (1.0 / 24.0 + y2 * (-1.0 / 720.0 + y2 * (1.0 / 40320.0
        + y2 * (-1.0 / 3628800.0 + y2 * (1.0 / 479001600.0 + y2 * (-1.0 / 87178291200.0)))))));
    return vec2(cos_y, -sin_y);
}

// A cell's two estimates of its integral, RGB.
struct CellEstimate {
    vec3 kronrod;
    vec3 gauss;
};

// The integral of f_r cos(theta_i) of `material` seen from `wo` over the cell theta_i from bounds.x to
// bounds.y, phi_i from bounds.z to bounds.w (radians).
CellEstimate integrate_cell(Material material, vec3 wo, vec4 bounds) {
    vec3 n = vec3(0.0, 0.0, 1.0);
    vec2 theta_mid = vec2(0.5 * (bounds.x + bounds.y), 0.5 * (bounds.y - bounds.x));
    vec2 phi_mid = vec2(0.5 * (bounds.z + bounds.w), 0.5 * (bounds.w - bounds.z));
    vec3 kronrod = vec3(0.0);
    vec3 gauss = vec3(0.0);
    NODE_LOOP for (int a = 0; a < 15; ++a) {
        vec2 theta = node_sin_cos(theta_mid.x + theta_mid.y * NODES[a]);
        float sin_theta = theta.x;
        float cos_theta = theta.y;
        // The solid angle's sin(theta) and the integrand's cos(theta_i).
        float measure = sin_theta * cos_theta;
        vec3 kronrod_ring = vec3(0.0);
        vec3 gauss_ring = vec3(0.0);
        NODE_LOOP for (int b = 0; b < 15; ++b) {
            vec2 phi = node_sin_cos(phi_mid.x + phi_mid.y * NODES[b]);
            vec3 wi = vec3(sin_theta * phi.y, sin_theta * phi.x, cos_theta);
            vec3 f = brdf_eval(material, n, vec3(1.0, 0.0, 0.0), wi, wo);
            kronrod_ring += KRONROD[b] * f;
            gauss_ring += GAUSS[b] * f;
        }
        kronrod += KRONROD[a] * measure * kronrod_ring;
        gauss += GAUSS[a] * measure * gauss_ring;
    }
    float scale = theta_mid.y * phi_mid.y;
    return CellEstimate(scale * kronrod, scale * gauss);
}

#endif
