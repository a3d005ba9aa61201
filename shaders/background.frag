#version 460
// webgl
// variant: WITH_ENVIRONMENT

// The background where no object covers a sample: the scene's background colour, or (the WITH_ENVIRONMENT
// variant) the environment seen along the pixel's camera ray, at its centre, as the CPU reference sees it.

#ifdef WITH_ENVIRONMENT
#include "common/environment_map.glsl"
#else
#include "common/scene.glsl"
#endif

layout(location = 0) out vec4 out_radiance;

void main() {
#ifdef WITH_ENVIRONMENT
    if (ENVIRONMENT != ENVIRONMENT_NONE) {
        vec3 ray = normalize((frame.pixel_rays * vec4(gl_FragCoord.xy, 1.0, 0.0)).xyz);
        out_radiance = vec4(environment_radiance(ray), 1.0);
        return;
    }
#endif
    out_radiance = frame.background;
}
