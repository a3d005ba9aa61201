#ifndef COMMON_FLOAT64_GLSL
#define COMMON_FLOAT64_GLSL

// GLSL's exponential and trigonometric functions take float alone (GL_ARB_gpu_shader_fp64 gives double the
// arithmetic, sqrt, floor and frexp, not exp or sin): their double-precision versions, for a .brdf file
// evaluated in double (crates/brdf-file/src/glsl.rs turns its float calls into these). Each reduces its
// argument exactly, as fdlibm does (Cody and Waite's constants split in two or three), then sums a
// polynomial whose first dropped term is below 2^-54 of the result. Mirrored by the tests of
// src/render/float64.rs against Rust's f64.

// Infinity and NaN, spelt by their bits (a constant 1.0 / 0.0 is refused by the compiler, and packDouble2x32
// is no constant expression).
#define F64_INFINITY packDouble2x32(uvec2(0u, 0x7ff00000u))
#define F64_NAN packDouble2x32(uvec2(0u, 0x7ff80000u))

const double F64_PI = 3.141592653589793115997963468544185161590576171875LF;
const double F64_PI_2 = 1.5707963267948965579989817342720925807952880859375LF;
const double F64_PI_4 = 0.78539816339744827899949086713604629039764404296875LF;
// ln 2 = LN2_HI + LN2_LO, LN2_HI with its low 32 bits zero, so that k LN2_HI is exact for |k| < 2^20.
const double F64_LN2_HI = 6.93147180369123816490e-01LF;
const double F64_LN2_LO = 1.90821492927058770002e-10LF;
const double F64_LN2 = 0.69314718055994528622676398299518041312694549560546875LF;
// pi/2 = PIO2_1 + PIO2_2 + PIO2_3, each with 33 bits, so that k PIO2_i is exact for |k| < 2^20.
const double F64_PIO2_1 = 1.57079632673412561417e+00LF;
const double F64_PIO2_2 = 6.07710050630396597660e-11LF;
const double F64_PIO2_3 = 2.02226624871116645580e-21LF;

double f64_exp(double x) {
    if (x > 709.782712893384LF) {
        return F64_INFINITY;
    }
    if (x < -745.2LF) {
        return 0.0LF;
    }
    // x = k ln 2 + r, |r| <= ln 2 / 2; e^r by its Taylor series to r^13 (r^14 / 14! < 4e-18).
    double k = round(x / F64_LN2);
    double r = (x - k * F64_LN2_HI) - k * F64_LN2_LO;
    // Nested as 1 + r (1 + r/2 (1 + r/3 (... (1 + r/13)))).
    double p = 1.0LF;
    for (int n = 13; n >= 1; --n) {
        p = 1.0LF + r * p / double(n);
    }
    // 2^k in two steps: ldexp of an exponent past the double's range is undefined in one.
    int half_k = int(k) / 2;
    return ldexp(ldexp(p, half_k), int(k) - half_k);
}

double f64_log(double x) {
    if (x < 0.0LF || isnan(x)) {
        return F64_NAN;
    }
    if (x == 0.0LF) {
        return -F64_INFINITY;
    }
    if (isinf(x)) {
        return x;
    }
    // x = m 2^e, m in [sqrt(1/2), sqrt(2)); ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| < 0.172, by its
    // series to s^25 (s^27 / 27 < 1e-22).
    int e;
    double m = frexp(x, e);
    if (m < 0.70710678118654752440LF) {
        m *= 2.0LF;
        e -= 1;
    }
    double s = (m - 1.0LF) / (m + 1.0LF);
    double s2 = s * s;
    double p = 1.0LF / 25.0LF;
    for (int k = 23; k >= 1; k -= 2) {
        p = p * s2 + 1.0LF / double(k);
    }
    return double(e) * F64_LN2_HI + (2.0LF * s * p + double(e) * F64_LN2_LO);
}

// GLSL's pow: undefined for x < 0, or x = 0 and y <= 0 (NaN and infinity here).
double f64_pow(double x, double y) {
    if (y == 0.0LF) {
        return 1.0LF;
    }
    if (x == 0.0LF) {
        return y > 0.0LF ? 0.0LF : F64_INFINITY;
    }
    return x < 0.0LF ? F64_NAN : f64_exp(y * f64_log(x));
}

double f64_exp2(double x) { return f64_exp(x * F64_LN2); }
double f64_log2(double x) { return f64_log(x) / F64_LN2; }

// sinh's series over x, 1 + z/(2 3) (1 + z/(4 5) (... (1 + z/(2n (2n + 1))))) at z = x^2, to x^(2n); sin's
// over x at z = -x^2.
double f64_odd_series(double z, int n) {
    double p = 1.0LF;
    for (int k = n; k >= 1; --k) {
        p = 1.0LF + z * p / double((2 * k) * (2 * k + 1));
    }
    return p;
}

// sin r and cos r for |r| <= pi/4, by their Taylor series to r^19 and r^20 (the next terms below 1e-19), cos's
// nested as 1 - r^2/(1 2) (1 - r^2/(3 4) (...)).
dvec2 f64_sin_cos_reduced(double r) {
    double r2 = r * r;
    double c = 1.0LF;
    for (int k = 10; k >= 1; --k) {
        c = 1.0LF - r2 * c / double((2 * k - 1) * (2 * k));
    }
    return dvec2(r * f64_odd_series(-r2, 9), c);
}

// (sin x, cos x): x = k pi/2 + r, |r| <= pi/4, exact for |x| < 2^19.
dvec2 f64_sin_cos(double x) {
    double k = round(x / F64_PI_2);
    double r = ((x - k * F64_PIO2_1) - k * F64_PIO2_2) - k * F64_PIO2_3;
    dvec2 sc = f64_sin_cos_reduced(r);
    int quadrant = int(k - 4.0LF * floor(k / 4.0LF));
    if (quadrant == 1) {
        return dvec2(sc.y, -sc.x);
    }
    if (quadrant == 2) {
        return -sc;
    }
    if (quadrant == 3) {
        return dvec2(-sc.y, sc.x);
    }
    return sc;
}

double f64_sin(double x) { return f64_sin_cos(x).x; }
double f64_cos(double x) { return f64_sin_cos(x).y; }
double f64_tan(double x) {
    dvec2 sc = f64_sin_cos(x);
    return sc.x / sc.y;
}

// atan x: |x| > 1 taken to 1 / |x|, then t > tan(pi/8) to (t - 1) / (t + 1) about pi/4, then the angle halved
// (|v| < 0.2), then the series to v^25 (v^27 / 27 < 1e-20).
double f64_atan(double x) {
    if (isnan(x)) {
        return x;
    }
    double t = abs(x);
    bool inverted = t > 1.0LF;
    if (inverted) {
        t = 1.0LF / t;
    }
    bool shifted = t > 0.41421356237309504880LF;
    if (shifted) {
        t = (t - 1.0LF) / (t + 1.0LF);
    }
    double v = t / (1.0LF + sqrt(1.0LF + t * t));
    double v2 = v * v;
    // atan v = v (1 - v^2 / 3 + v^4 / 5 - ...): the sign of 1 / k is + where (k - 1) / 2 is even.
    double p = 1.0LF / 25.0LF;
    for (int k = 23; k >= 1; k -= 2) {
        double term = 1.0LF / double(k);
        p = p * v2 + ((k & 2) == 0 ? term : -term);
    }
    double a = 2.0LF * v * p;
    if (shifted) {
        a += F64_PI_4;
    }
    if (inverted) {
        a = F64_PI_2 - a;
    }
    return x < 0.0LF ? -a : a;
}

// GLSL's atan(y, x): the angle of (x, y), in [-pi, pi].
double f64_atan(double y, double x) {
    if (x == 0.0LF) {
        return y == 0.0LF ? 0.0LF : (y > 0.0LF ? F64_PI_2 : -F64_PI_2);
    }
    if (abs(y) > abs(x)) {
        double a = F64_PI_2 - f64_atan(abs(x / y));
        a = x < 0.0LF ? F64_PI - a : a;
        return y < 0.0LF ? -a : a;
    }
    double a = f64_atan(y / x);
    if (x > 0.0LF) {
        return a;
    }
    return y < 0.0LF ? a - F64_PI : a + F64_PI;
}

double f64_asin(double x) { return f64_atan(x, sqrt((1.0LF - x) * (1.0LF + x))); }
double f64_acos(double x) { return f64_atan(sqrt((1.0LF - x) * (1.0LF + x)), x); }

double f64_sinh(double x) {
    if (abs(x) < 0.5LF) {
        // The series to x^17: e^x - e^-x cancels here.
        return x * f64_odd_series(x * x, 8);
    }
    double e = f64_exp(abs(x));
    double s = 0.5LF * (e - 1.0LF / e);
    return x < 0.0LF ? -s : s;
}

double f64_cosh(double x) {
    double e = f64_exp(abs(x));
    return 0.5LF * (e + 1.0LF / e);
}

double f64_tanh(double x) {
    if (abs(x) > 20.0LF) {
        return sign(x);
    }
    return f64_sinh(x) / f64_cosh(x);
}

double f64_acosh(double x) { return f64_log(x + sqrt((x - 1.0LF) * (x + 1.0LF))); }

double f64_atanh(double x) {
    if (abs(x) < 0.5LF) {
        // 0.5 ln((1 + x) / (1 - x)) cancels here: 2 atanh(s), s = x / (1 + sqrt(1 - x^2)) (tanh's double
        // angle), |s| < 0.27, by its series to s^29.
        double s = x / (1.0LF + sqrt((1.0LF - x) * (1.0LF + x)));
        double s2 = s * s;
        double p = 1.0LF / 29.0LF;
        for (int k = 27; k >= 1; k -= 2) {
            p = p * s2 + 1.0LF / double(k);
        }
        return 2.0LF * s * p;
    }
    return 0.5LF * f64_log((1.0LF + x) / (1.0LF - x));
}

double f64_asinh(double x) {
    double a = abs(x);
    double s = a < 0.5LF ? f64_atanh(a / sqrt(1.0LF + a * a)) : f64_log(a + sqrt(a * a + 1.0LF));
    return x < 0.0LF ? -s : s;
}

double f64_radians(double degrees) { return degrees * (F64_PI / 180.0LF); }
double f64_degrees(double radians) { return radians * (180.0LF / F64_PI); }

// The vector forms, component by component, as GLSL's own are.
#define F64_VECTORS_1(f) \
    dvec2 f(dvec2 v) { return dvec2(f(v.x), f(v.y)); } \
    dvec3 f(dvec3 v) { return dvec3(f(v.x), f(v.y), f(v.z)); } \
    dvec4 f(dvec4 v) { return dvec4(f(v.x), f(v.y), f(v.z), f(v.w)); }
#define F64_VECTORS_2(f) \
    dvec2 f(dvec2 a, dvec2 b) { return dvec2(f(a.x, b.x), f(a.y, b.y)); } \
    dvec3 f(dvec3 a, dvec3 b) { return dvec3(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)); } \
    dvec4 f(dvec4 a, dvec4 b) { return dvec4(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z), f(a.w, b.w)); }

F64_VECTORS_1(f64_exp)
F64_VECTORS_1(f64_log)
F64_VECTORS_2(f64_pow)
F64_VECTORS_1(f64_exp2)
F64_VECTORS_1(f64_log2)
F64_VECTORS_1(f64_sin)
F64_VECTORS_1(f64_cos)
F64_VECTORS_1(f64_tan)
F64_VECTORS_1(f64_atan)
F64_VECTORS_2(f64_atan)
F64_VECTORS_1(f64_asin)
F64_VECTORS_1(f64_acos)
F64_VECTORS_1(f64_sinh)
F64_VECTORS_1(f64_cosh)
F64_VECTORS_1(f64_tanh)
F64_VECTORS_1(f64_asinh)
F64_VECTORS_1(f64_acosh)
F64_VECTORS_1(f64_atanh)
F64_VECTORS_1(f64_radians)
F64_VECTORS_1(f64_degrees)

#endif
