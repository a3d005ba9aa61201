#ifndef COMMON_OUTPUT_GLSL
#define COMMON_OUTPUT_GLSL

// The course's output transform, output.rs's `encode(tonemap(c * exposure, Clamp), Linear)`: NaN and below 0
// give 0, above 1 gives 255, and between, x255 truncated (the course's levels). Each step is one correctly
// rounded product (`precise`: nothing fused), so the levels are the host encoder's on any device. Shared by
// the resolve (resolve.comp) and the browser's resolve (web/resolve.frag).
uint course_level(float c, float exposure) {
    precise float exposed = c * exposure;
    if (!(exposed > 0.0)) {
        return 0u;
    }
    precise float scaled = min(exposed, 1.0) * 255.0;
    return uint(scaled);
}

#endif
