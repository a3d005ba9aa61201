#ifndef BRDF_MEASURED_SAMPLER_GLSL
#define BRDF_MEASURED_SAMPLER_GLSL

#include "common/math.glsl"
#include "brdf/measured.glsl"

// A measured material's own sampler: per tabulated view elevation, a density of half vectors in proportion
// to the table's f_r cos(theta_i), interpolated bilinearly between nodes over x = 1 - cos(theta_h) (rows as
// the table's theta_h index) and phi_h from the view's azimuth (0 to 180 degrees, the other side drawn by a
// coin), made by src/brdf/measured_sampler.rs, which says why. The renderer's build only: the browser
// draws no samples.
#ifndef WEBGL

// VIEWS, ROWS and COLUMNS of src/brdf/measured_sampler.rs, and the places of a view's floats.
const uint SAMPLER_VIEWS = 32u;
const uint SAMPLER_ROWS = 90u;
const uint SAMPLER_COLUMNS = 32u;
const uint SAMPLER_NODES_A_ROW = SAMPLER_COLUMNS + 1u;
const uint SAMPLER_PROBABILITIES = SAMPLER_ROWS;             // each row interval's probability
const uint SAMPLER_MARGINAL = 2u * SAMPLER_ROWS;             // each row's integral over phi_h
const uint SAMPLER_NODES = 3u * SAMPLER_ROWS + 1u;           // each node's density, row after row
const uint SAMPLER_VIEW_FLOATS = SAMPLER_NODES + (SAMPLER_ROWS + 1u) * SAMPLER_NODES_A_ROW;
const float SAMPLER_COLUMN_ANGLE = PI / float(SAMPLER_COLUMNS);

// Float i of table `table`'s sampler.
float sampler_float(uint table, uint i) { return measured_tables[table * MEASURED_TABLE_FLOATS + 3u * MERL_ENTRIES + i]; }

// 1 - cos(theta_h) at row r, as 2 sin^2(theta_h / 2). Mirrors row_edge of src/brdf/measured_sampler.rs.
float sampler_row(uint r) {
    float u = float(r) / float(SAMPLER_ROWS);
    float s = sin(0.25 * PI * u * u);
    return 2.0 * s * s;
}

// The frame of the view's azimuth: the tangent towards wo (any, when wo is n) and n x it.
void sampler_frame(vec3 n, vec3 wo, out vec3 t, out vec3 b) {
    vec3 toward = wo - n * dot(n, wo);
    t = dot(toward, toward) > 1e-12 ? normalize(toward) : any_tangent(n);
    b = cross(n, t);
}

// The first of the two tabulated views about wo, and the share of the second: the sampler draws from
// either in proportion to how near wo is.
uint sampler_views(vec3 n, vec3 wo, out float second) {
    float s = acos(clamp(dot(n, wo), 0.0, 1.0)) / (0.5 * PI) * float(SAMPLER_VIEWS - 1u);
    uint first = min(uint(s), SAMPLER_VIEWS - 2u);
    second = clamp(s - float(first), 0.0, 1.0);
    return first;
}

// The row interval whose cumulative probability (from `start`) is the last at or below u: a binary search.
uint sampler_find(uint table, uint start, float u) {
    uint low = 0u;
    uint high = SAMPLER_ROWS - 1u;
    while (low < high) {
        uint middle = (low + high + 1u) / 2u;
        if (sampler_float(table, start + middle) <= u) {
            low = middle;
        } else {
            high = middle - 1u;
        }
    }
    return low;
}

// Where xi falls in [0, 1] under a density that runs linearly from a to b (not both 0): the root of
// (a t + (b - a) t^2 / 2) / ((a + b) / 2) = xi, in the form without cancellation.
float sampler_linear(float a, float b, float xi) {
    return xi * (a + b) / (a + sqrt(max(a * a + xi * (b - a) * (b + a), 0.0)));
}

// A direction from the sampler of the material's table (`measured`) at view wo about n: a half vector from
// one of the two views' distributions (its row interval by the marginal, its place within by the marginal's
// line there, its column by the conditional at that place and its place within by its line), wo reflected
// about it; -n (no sample) when the view's distribution is empty or the reflection falls below h.
vec3 measured_sample(uint field, vec3 n, vec3 wo, vec2 u) {
    uint table = measured_table(field);
    float second;
    uint view = sampler_views(n, wo, second);
    if (u.x < 1.0 - second) {
        u.x /= 1.0 - second;
    } else {
        u.x = (u.x - (1.0 - second)) / second;
        view += 1u;
    }
    float side = u.y < 0.5 ? 1.0 : -1.0;
    u.y = u.y < 0.5 ? 2.0 * u.y : 2.0 * u.y - 1.0;
    uint base = view * SAMPLER_VIEW_FLOATS;
    uint row = sampler_find(table, base, u.x);
    float probability = sampler_float(table, base + SAMPLER_PROBABILITIES + row);
    if (probability <= 0.0) {
        return -n;
    }
    float xi = clamp((u.x - sampler_float(table, base + row)) / probability, 0.0, 1.0);
    float t = sampler_linear(sampler_float(table, base + SAMPLER_MARGINAL + row),
                             sampler_float(table, base + SAMPLER_MARGINAL + row + 1u), xi);
    // The conditional over phi_h at t: the two rows' nodes mixed, a line between each pair.
    uint low = base + SAMPLER_NODES + row * SAMPLER_NODES_A_ROW;
    uint high = low + SAMPLER_NODES_A_ROW;
    float total = 0.0;
    float previous = mix(sampler_float(table, low), sampler_float(table, high), t);
    for (uint j = 1u; j < SAMPLER_NODES_A_ROW; ++j) {
        float next = mix(sampler_float(table, low + j), sampler_float(table, high + j), t);
        total += previous + next;
        previous = next;
    }
    float target = u.y * total;
    float left = mix(sampler_float(table, low), sampler_float(table, high), t);
    uint column = 0u;
    float right = left;
    for (; column < SAMPLER_COLUMNS; ++column) {
        right = mix(sampler_float(table, low + column + 1u), sampler_float(table, high + column + 1u), t);
        float interval = left + right;
        if (target < interval || column == SAMPLER_COLUMNS - 1u) {
            break;
        }
        target -= interval;
        left = right;
    }
    if (left + right <= 0.0) {
        return -n;
    }
    float s = sampler_linear(left, right, clamp(target / (left + right), 0.0, 1.0));
    float x = mix(sampler_row(row), sampler_row(row + 1u), t);
    float phi = (float(column) + s) * SAMPLER_COLUMN_ANGLE;
    vec3 frame_t, frame_b;
    sampler_frame(n, wo, frame_t, frame_b);
    float sin_theta = sqrt(max(x * (2.0 - x), 0.0));
    vec3 h = sin_theta * cos(phi) * frame_t + side * sin_theta * sin(phi) * frame_b + (1.0 - x) * n;
    float WoH = dot(wo, h);
    return WoH > 0.0 ? 2.0 * WoH * h - wo : -n;
}

// The density per solid angle of measured_sample drawing wi above the surface: the two views' densities of
// its half vector (the bilinear patchwork at its x and phi_h), mixed as drawn, over the reflection's
// Jacobian 4 (wo . h).
float measured_sample_pdf(uint field, vec3 n, vec3 wi, vec3 wo) {
    if (dot(n, wi) <= 0.0) {
        return 0.0;
    }
    uint table = measured_table(field);
    vec3 h = normalize(wi + wo);
    // 1 - cos(theta_h) as |h - n|^2 / 2 (2 sin^2(theta_h / 2)), which keeps its digits near the normal.
    vec3 off = h - n;
    float x = 0.5 * dot(off, off);
    float theta_h = 2.0 * asin(min(0.5 * length(off), 1.0));
    uint row = min(uint(sqrt(theta_h / (0.5 * PI)) * float(SAMPLER_ROWS)), SAMPLER_ROWS - 1u);
    // The row interval whose edges hold x: rounding may put the estimate one off.
    if (x < sampler_row(row) && row > 0u) {
        row -= 1u;
    } else if (x >= sampler_row(row + 1u) && row + 1u < SAMPLER_ROWS) {
        row += 1u;
    }
    float t = clamp((x - sampler_row(row)) / (sampler_row(row + 1u) - sampler_row(row)), 0.0, 1.0);
    vec3 frame_t, frame_b;
    sampler_frame(n, wo, frame_t, frame_b);
    float place = atan(abs(dot(h, frame_b)), dot(h, frame_t)) / SAMPLER_COLUMN_ANGLE;
    uint column = min(uint(place), SAMPLER_COLUMNS - 1u);
    float s = clamp(place - float(column), 0.0, 1.0);
    float second;
    uint view = sampler_views(n, wo, second);
    float density = 0.0;
    for (uint k = 0u; k < 2u; ++k) {
        float share = k == 0u ? 1.0 - second : second;
        if (share > 0.0) {
            uint low = (view + k) * SAMPLER_VIEW_FLOATS + SAMPLER_NODES + row * SAMPLER_NODES_A_ROW + column;
            uint high = low + SAMPLER_NODES_A_ROW;
            density += share * mix(mix(sampler_float(table, low), sampler_float(table, low + 1u), s),
                                   mix(sampler_float(table, high), sampler_float(table, high + 1u), s), t);
        }
    }
    return density / (4.0 * max(dot(wo, h), 1e-12));
}

#endif
#endif
