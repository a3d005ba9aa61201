#version 460
// webgl
// variant: WITH_ENVIRONMENT
// variant: TERM_VIEWS
// variant: WITH_ENVIRONMENT+TERM_VIEWS

// The forward pass of meshes and planes: each fragment shaded at the interpolated point and normal.
// Spheres have their own pass, forward_sphere.frag.

#include "common/shading.glsl"

layout(location = 0) in vec4 in_world_position;
layout(location = 1) in vec3 in_world_normal;
layout(location = 2) in vec3 in_world_tangent;

layout(location = 0) out vec4 out_radiance;

void main() {
    ObjectData object = objects[draw.object_index];
#ifdef WEBGL
    // The browser: SwiftShader's WebGL2 interpolates nothing right across the infinite plane's triangles,
    // whose vertices lie at infinity or, when the camera is level with the plane's point, on the camera's
    // plane (every attribute came out as one vertex's, the depth too). A plane's point is found instead where
    // the pixel centre's camera ray meets it (where the interpolation puts it, to rounding), with its depth,
    // as spheres are; its normal is the plane's, which every vertex has.
    if (object.flags.y == TANGENT_PLANE) {
        vec3 eye = frame.camera_position.xyz;
        vec3 ray = (frame.pixel_rays * vec4(gl_FragCoord.xy, 1.0, 0.0)).xyz;
        vec3 normal = normalize(mat3(object.normal_matrix) * vec3(0.0, 1.0, 0.0));
        float t = dot(object.model[3].xyz - eye, normal) / dot(ray, normal);
        vec3 p = eye + t * ray;
        vec4 clip = frame.view_projection * vec4(p, 1.0);
        // At the horizon, past 1e7 units, as world_point below: nil.
        if (!(t > 0.0) || t * length(ray) > 1e7) {
            gl_FragDepth = 0.0;
            out_radiance = vec4(0.0, 0.0, 0.0, 1.0);
            return;
        }
        gl_FragDepth = clip.z / clip.w;
        out_radiance = vec4(pixel_value(object, p, normal, vec3(0.0)), 1.0);
        return;
    }
    gl_FragDepth = gl_FragCoord.z;
#endif
    // Past 1e7 units a point light's 1/d^2 is nil.
    vec3 p;
    if (!world_point(in_world_position, p)) {
        out_radiance = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    out_radiance = vec4(pixel_value(object, p, normalize(in_world_normal), in_world_tangent), 1.0);
}
