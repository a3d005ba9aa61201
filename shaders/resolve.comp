#version 460

// The resolve: the forward pass's samples of each pixel averaged, as the course averages its pixel samples,
// and written straight into the host's read-back buffer (no resolved image, no copy), either as linear
// radiance (four floats a pixel) or, for the course's own output transform, as the 8-bit levels that
// output.rs's `encode` gives (four bytes a pixel): the host then neither reads four times the bytes nor
// encodes them, and lavapipe's own resolve (its blitter, writing a float image) is not run.
//
// Every step is exact in float32 and so gives the host's bytes on any device: the sum of the samples in
// order and its product by 1/SAMPLES (a power of two), which is lavapipe's resolve to the bit; then
// exposure, clamp, x255 and truncation, one correctly rounded product each (`precise`: nothing fused).
//
// The BACKGROUND builds also write the background where no object covers a sample: the forward pass then
// neither draws the background nor writes those samples' colour, and their depth is still UNCOVERED_DEPTH
// (forward.rs's Background::Resolved). Their colour is the background's triangle's, to the bit.
//
// variant: SINGLE_SAMPLE
// variant: BACKGROUND
// variant: BACKGROUND+SINGLE_SAMPLE

#include "common/output.glsl"

// Along a row: each invocation a pixel (radiance) or four (levels); each row of workgroups a row of pixels.
layout(local_size_x = 64) in;

// The colour target's samples per pixel.
layout(constant_id = 0) const int SAMPLES = 4;
// Write the course's 8-bit levels rather than the radiance.
layout(constant_id = 1) const bool LEVELS = false;
// The levels' byte order: B, G, R, A rather than R, G, B, A (a window's surface).
layout(constant_id = 2) const bool BGRA = false;

#ifdef SINGLE_SAMPLE
#define TARGET sampler2D
#else
#define TARGET sampler2DMS
#endif
// The forward pass's colour and depth targets.
layout(set = 0, binding = 0) uniform TARGET colour;
#ifdef BACKGROUND
layout(set = 0, binding = 2) uniform TARGET depth;
// forward.rs's UNCOVERED_DEPTH.
const float UNCOVERED_DEPTH = -1.0;
#endif
// Radiance: a pixel's four floats (their bits) each, rows from the top; levels: four pixels each, one word
// a pixel, its bytes in memory order, each row padded to a whole number of texels (so that no invocation
// divides to find its pixel: llvmpipe divides integers lane by lane). One 16-byte store an invocation:
// llvmpipe stores to a buffer lane by lane, word by word.
layout(set = 0, binding = 1, std430) writeonly buffer Texels { uvec4 texels[]; };

layout(push_constant) uniform Resolve {
    uvec2 size;
    float exposure;
    float pad;
    // The background's colour (the frame's, as background.frag writes it).
    vec4 background;
} resolve;

// Sample `s` of the pixel (its level of detail 0 with one sample).
vec4 sample_at(ivec2 pixel, int s) {
#ifdef SINGLE_SAMPLE
    s = 0;
#endif
#ifdef BACKGROUND
    if (texelFetch(depth, pixel, s).r == UNCOVERED_DEPTH) {
        return resolve.background;
    }
#endif
    return texelFetch(colour, pixel, s);
}

// The mean of the pixel's samples, summed in sample order.
vec4 pixel_mean(ivec2 pixel) {
    precise vec4 sum = sample_at(pixel, 0);
    for (int s = 1; s < SAMPLES; s++) {
        sum += sample_at(pixel, s);
    }
    precise vec4 mean = sum * (1.0 / float(SAMPLES));
    return mean;
}


// The levels of `pixel`, packed as R, G, B, 255 (B, G, R, 255) in memory order; 0 past the row's end.
uint packed_levels(ivec2 pixel) {
    if (pixel.x >= int(resolve.size.x)) {
        return 0u;
    }
    vec4 mean = pixel_mean(pixel);
    float e = resolve.exposure;
    uvec3 levels = uvec3(course_level(mean.r, e), course_level(mean.g, e), course_level(mean.b, e));
    if (BGRA) {
        levels = levels.bgr;
    }
    return levels.x | (levels.y << 8) | (levels.z << 16) | (255u << 24);
}

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (LEVELS) {
        uint row_texels = (resolve.size.x + 3u) / 4u;
        if (id.x >= row_texels || id.y >= resolve.size.y) {
            return;
        }
        ivec2 first = ivec2(4u * id.x, id.y);
        texels[id.y * row_texels + id.x] = uvec4(packed_levels(first), packed_levels(first + ivec2(1, 0)),
                                                 packed_levels(first + ivec2(2, 0)), packed_levels(first + ivec2(3, 0)));
    } else if (id.x < resolve.size.x && id.y < resolve.size.y) {
        texels[id.y * resolve.size.x + id.x] = floatBitsToUint(pixel_mean(ivec2(id)));
    }
}
