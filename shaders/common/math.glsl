#ifndef COMMON_MATH_GLSL
#define COMMON_MATH_GLSL

const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;

float saturate(float x) { return clamp(x, 0.0, 1.0); }

#endif
