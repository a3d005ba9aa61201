#ifndef COMMON_OUTPUT_GLSL
#define COMMON_OUTPUT_GLSL

// The output transform of output.rs (exposure, `tonemap`, the clamp, `encode`) for one channel, in 8-bit
// levels. The renderer's resolve (resolve.comp) applies the course's own (clamp, linear: course_level), the
// host encodes the others; the browser's resolve (web/resolve.frag) applies every one. Each step of the
// course's is one correctly rounded product (`precise`: nothing fused), so its levels are the host encoder's
// on any device.

// Scene's `tonemap` and `encoding` (src/scene/mod.rs, Tonemap and Encoding; ids of src/serve/browser.rs).
const uint TONEMAP_CLAMP = 0u;
const uint TONEMAP_REINHARD = 1u;
const uint TONEMAP_ACES = 2u;
const uint ENCODING_LINEAR = 0u;
const uint ENCODING_SRGB = 1u;

// output.rs's `tonemap`: nothing (the course), c / (1 + c), or Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
float tone_curve(float c, uint curve) {
    if (curve == TONEMAP_REINHARD) {
        return c / (1.0 + c);
    }
    if (curve == TONEMAP_ACES) {
        return c * (2.51 * c + 0.03) / (c * (2.43 * c + 0.59) + 0.14);
    }
    return c;
}

// output.rs's `encode(tonemap(c * exposure, curve), encoding)`: NaN and below 0 give 0, above 1 gives 255; the
// course's linear encoding x255 truncated, sRGB's transfer function (IEC 61966-2-1) x255 rounded to nearest.
uint output_level(float c, float exposure, uint curve, uint encoding) {
    precise float exposed = c * exposure;
    float toned = tone_curve(exposed, curve);
    if (!(toned > 0.0)) {
        return 0u;
    }
    float v = min(toned, 1.0);
    if (encoding == ENCODING_SRGB) {
        v = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
        return uint(floor(v * 255.0 + 0.5));
    }
    precise float scaled = v * 255.0;
    return uint(scaled);
}

// The course's levels: exposure, clamp, x255, truncation.
uint course_level(float c, float exposure) {
    return output_level(c, exposure, TONEMAP_CLAMP, ENCODING_LINEAR);
}

#endif
