#version 460
// webgl

// The background: one triangle over the whole target (a 4 x 4 square's corner, clipped), at the far end
// of reverse-Z depth (0). Drawn first, with every test passing, it writes every sample's colour and depth,
// which is what clearing them would do: lavapipe fills a cleared float target sample by sample in C (2.5
// ms of Figure 1's 10 at 600 x 400 x 4), where the fragment shader writes eight pixels at a time.

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(2.0 * corner - 1.0, 0.0, 1.0);
}
