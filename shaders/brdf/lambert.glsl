#ifndef BRDF_LAMBERT_GLSL
#define BRDF_LAMBERT_GLSL

#include "common/math.glsl"

// Lambert 1760, "Photometria": perfectly diffuse, f_r = kd / pi in every direction.
vec3 lambert(vec3 kd) { return kd * INV_PI; }

#endif
