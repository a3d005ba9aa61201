#version 460

// The scene's background colour, where no object covers a sample.

#include "common/scene.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    out_radiance = frame.background;
}
