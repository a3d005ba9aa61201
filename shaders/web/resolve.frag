#version 460
// webgl

// The browser's resolve: WebGL2 has no compute shaders, so resolve.comp's work for the browser's one sample a
// pixel is this pass, drawn over the canvas by background.vert's triangle. Each pixel of the forward pass's
// float target becomes its 8-bit levels through the scene's whole output transform (the renderer's host
// encodes those other than the course's), its rows turned over: the target's first row is the image's top,
// as in Vulkan (the same matrices and gl_FragCoord), and a canvas shows its first row at the bottom.
// Translated for the browser only (build.rs leaves shaders/web/ out of the renderer's SPIR-V).

#include "common/output.glsl"

layout(set = 0, binding = 0) uniform sampler2D colour;

// A term view (`term` 1) is written as output.rs's TermScale writes it: level = 255 (value - low) /
// (high - low), linear, truncated and clamped; the page finds the largest value that `high` needs.
layout(push_constant) uniform Resolve { float exposure; uint tonemap; uint encoding; uint term; float low; float high; } resolve;

layout(location = 0) out vec4 out_levels;

void main() {
    ivec2 size = textureSize(colour, 0);
    ivec2 pixel = ivec2(int(gl_FragCoord.x), size.y - 1 - int(gl_FragCoord.y));
    vec3 c = texelFetch(colour, pixel, 0).rgb;
    float e = resolve.exposure;
    uint t = resolve.tonemap;
    uint k = resolve.encoding;
    // Level k is written as k / 255, which the 8-bit canvas stores as k exactly (round(k / 255 * 255)).
    if (resolve.term != 0u) {
        c = (c - resolve.low) / (resolve.high - resolve.low);
        e = 1.0;
        t = TONEMAP_CLAMP;
        k = ENCODING_LINEAR;
    }
    uvec3 levels = uvec3(output_level(c.r, e, t, k), output_level(c.g, e, t, k), output_level(c.b, e, t, k));
    out_levels = vec4(vec3(levels) / 255.0, 1.0);
}
