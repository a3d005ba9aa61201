//! The catalogue of mistakes `vk-render check` knows, found in students' forks of the practical's skeleton.
//! Each is one entry: a one-sentence explanation, the formula as it should be and as the image suggests it
//! is, a scene of the practical where it shows, and how to make it: edits of the GLSL (a variant of the very
//! shaders, not a copy), a change of the scene, or of the output's rounding. Adding a mistake is adding one.

use glam::Vec3;

use crate::brdf::Brdf;
use crate::scene::{Encoding, Scene};

/// One known mistake.
#[derive(Clone, Copy, Debug)]
pub struct Mistake {
    /// A short name, for reports and `--list`.
    pub name: &'static str,
    /// What went wrong, in one sentence.
    pub explanation: &'static str,
    /// The formula as it should be.
    pub should_be: &'static str,
    /// The formula as the image suggests it is.
    pub looks_like: &'static str,
    /// A scene of the practical where it shows.
    pub shows_on: ShowsOn,
    /// How to make it.
    pub variant: Variant,
}

/// A scene of the practical (assets/scenes/NAME.toml, by NAME) and overrides that bring a mistake out.
pub type ShowsOn = (&'static str, &'static [&'static str]);

/// How a mistake is made.
#[derive(Clone, Copy, Debug)]
pub enum Variant {
    /// Text edits of the shaders: in `file` (under shaders/), `from` (found exactly once) becomes `to`.
    Shader(&'static [ShaderEdit]),
    /// A change of the scene (a material, the encoding).
    Scene(fn(&mut Scene)),
    /// The course's output transform, but rounding to the nearest level instead of truncating.
    Rounding,
}

/// One edit of a shader file.
#[derive(Clone, Copy, Debug)]
pub struct ShaderEdit {
    /// The file, relative to `shaders/`.
    pub file: &'static str,
    /// Text found exactly once in the file.
    pub from: &'static str,
    /// What it becomes.
    pub to: &'static str,
}

const fn edit(file: &'static str, from: &'static str, to: &'static str) -> ShaderEdit {
    ShaderEdit { file, from, to }
}

/// Every mistake, in the order of the practical.
pub const CATALOGUE: &[Mistake] = &[
    Mistake {
        name: "lambert-without-pi",
        explanation: "Lambert's BRDF lost its 1/pi, so the diffuse surfaces are pi times too bright.",
        should_be: "f_r = kd / pi",
        looks_like: "f_r = kd",
        shows_on: ("fig1-lambert", &[]),
        variant: Variant::Shader(&[edit("brdf/lambert.glsl", "kd * INV_PI", "kd")]),
    },
    Mistake {
        name: "oren-nayar-b-without-kd-over-pi",
        explanation: "Oren-Nayar's B term lost its kd/pi factor to operator precedence: kd/pi multiplies A only.",
        should_be: "f_r = kd/pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta))",
        looks_like: "f_r = kd/pi A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)",
        shows_on: ("fig2-oren-nayar-sigma-0.6", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/oren_nayar.glsl",
            "lambert(kd) * (oren_nayar_a(sigma) + oren_nayar_b(sigma) * cos_phi * sin_alpha * tan_beta)",
            "lambert(kd) * oren_nayar_a(sigma) + oren_nayar_b(sigma) * cos_phi * sin_alpha * tan_beta",
        )]),
    },
    Mistake {
        name: "oren-nayar-world-azimuths",
        explanation: "Oren-Nayar's phi_i - phi_o was taken from world-space azimuths instead of the tangent plane.",
        should_be: "cos(phi_i - phi_o) of wi and wo projected on the tangent plane",
        looks_like: "cos(phi_i - phi_o) of their world x and y",
        shows_on: ("fig2-oren-nayar-sigma-0.6", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/oren_nayar.glsl",
            "    vec3 wi_t = wi - n * dot(n, wi);\n    vec3 wo_t = wo - n * dot(n, wo);",
            "    vec3 wi_t = vec3(wi.xy, 0.0);\n    vec3 wo_t = vec3(wo.xy, 0.0);",
        )]),
    },
    Mistake {
        name: "oren-nayar-wo-reflected",
        explanation: "Oren-Nayar's cos(phi_i - phi_o) was computed from wi and wo themselves, not their projections.",
        should_be: "cos(phi_i - phi_o) of wi and wo projected on the tangent plane",
        looks_like: "cos(phi_i - phi_o) = wi . wo",
        shows_on: ("fig2-oren-nayar-sigma-0.6", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/oren_nayar.glsl",
            "return lengths <= 1e-12 ? 0.0 : dot(wi_t, wo_t) / lengths;",
            "return dot(wi, wo);",
        )]),
    },
    Mistake {
        name: "sigma-in-degrees",
        explanation: "Oren-Nayar's sigma was taken as degrees and converted, so the surface is nearly Lambertian.",
        should_be: "sigma in radians (0.6)",
        looks_like: "sigma = radians(0.6) = 0.0105",
        shows_on: ("fig2-oren-nayar-sigma-0.6", &[]),
        variant: Variant::Shader(&[edit(
            "brdf/oren_nayar.glsl",
            "    float NoL = dot(n, wi);\n    float NoV = dot(n, wo);\n    // The larger",
            "    sigma = radians(sigma);\n    float NoL = dot(n, wi);\n    float NoV = dot(n, wo);\n    // The larger",
        )]),
    },
    Mistake {
        name: "phong-without-cos-theta-i",
        explanation: "The specular lobe lost its division by cos(theta_i), so it fades towards grazing light.",
        should_be: "ks cos(alpha)^s / cos(theta_i)",
        looks_like: "ks cos(alpha)^s",
        shows_on: ("fig3-plastic-s-16", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/phong.glsl",
            "ks * (pow_lobe(cos_alpha, shininess) / max(NoL, MIN_COS_THETA_I))",
            "ks * pow_lobe(cos_alpha, shininess)",
        )]),
    },
    Mistake {
        name: "phong-divided-by-cos-theta-o",
        explanation: "Phong's lobe was divided by cos(theta_o) instead of cos(theta_i): wi and wo were swapped.",
        should_be: "ks cos(alpha)^s / cos(theta_i)",
        looks_like: "ks cos(alpha)^s / cos(theta_o)",
        shows_on: ("fig3-plastic-s-16", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/phong.glsl",
            "cosine_lobe(ks, cos_alpha, shininess, dot(n, wi))",
            "cosine_lobe(ks, cos_alpha, shininess, dot(n, wo))",
        )]),
    },
    Mistake {
        name: "phong-wrong-reflection",
        explanation: "Phong reflected the light direction with the wrong sign convention, so its highlight is gone.",
        should_be: "r = 2 (n . wi) n - wi, cos(alpha) = wo . r",
        looks_like: "r = reflect(wi, n) = wi - 2 (n . wi) n",
        shows_on: ("fig3-plastic-s-16", &[]),
        variant: Variant::Shader(&[edit(
            "brdf/phong.glsl",
            "max(dot(wo, mirror(n, wi)), 0.0)",
            "max(dot(wo, reflect(wi, n)), 0.0)",
        )]),
    },
    Mistake {
        name: "blinn-phong-h-not-normalised",
        explanation: "Blinn-Phong's half vector was not normalised, so n . h exceeds 1 and the highlight blows up.",
        should_be: "h = (wi + wo) / |wi + wo|",
        looks_like: "h = wi + wo",
        shows_on: ("fig6-blinn-phong", &[]),
        variant: Variant::Shader(&[edit(
            "brdf/blinn_phong.glsl",
            "max(dot(n, half_vector(wi, wo)), 0.0)",
            "max(dot(n, wi + wo), 0.0)",
        )]),
    },
    Mistake {
        name: "cook-torrance-multiplied",
        explanation: "Cook-Torrance multiplied by cos(theta_o) cos(theta_i) where it divides by them.",
        should_be: "D F G / (4 cos(theta_o) cos(theta_i))",
        looks_like: "D F G / 4 * cos(theta_o) * cos(theta_i)",
        shows_on: ("fig4-gold-metalness-1.0", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/cook_torrance.glsl",
            "return 0.25 / ((NoV * (1.0 - k) + k) * (NoL * (1.0 - k) + k));",
            "return 0.25 * NoV * NoV * NoL * NoL / ((NoV * (1.0 - k) + k) * (NoL * (1.0 - k) + k));",
        )]),
    },
    Mistake {
        name: "schlick-without-exponent",
        explanation: "Schlick's Fresnel lost its exponent 5, so the reflectance rises far too early towards grazing.",
        should_be: "F = F0 + (1 - F0) (1 - h . wo)^5",
        looks_like: "F = F0 + (1 - F0) (1 - h . wo)",
        shows_on: ("fig4-gold-metalness-1.0", &["light.0.position=[3.0, 0.5, 3.0]", "material.gold.roughness=0.6"]),
        variant: Variant::Shader(&[edit("brdf/cook_torrance.glsl", "(m2 * m2 * m)", "(m)")]),
    },
    Mistake {
        name: "smith-k-from-alpha",
        explanation: "Smith-Schlick's k was taken as alpha^2 instead of Karis's (roughness + 1)^2 / 8.",
        should_be: "k = (roughness + 1)^2 / 8",
        looks_like: "k = alpha^2 = roughness^4",
        shows_on: ("fig4-gold-metalness-1.0", &["light.0.position=[3.0, 2.0, 0.0]"]),
        variant: Variant::Shader(&[edit(
            "brdf/cook_torrance.glsl",
            "return (roughness + 1.0) * (roughness + 1.0) / 8.0;",
            "return roughness * roughness * roughness * roughness;",
        )]),
    },
    Mistake {
        name: "cosine-not-clamped",
        explanation: "The integrator's cosine was not clamped, so lights behind a surface subtract from it.",
        should_be: "L = sum over lights of f_r E max(0, n . wi)",
        looks_like: "L = sum over lights of f_r E (n . wi)",
        shows_on: ("fig5-golden-bunny", &["light.0.shadows=false", "light.1.shadows=false", "material.gold.metalness=0"]),
        variant: Variant::Shader(&[
            edit("common/shading.glsl", "        if (NoL <= 0.0) {\n            continue;  // the light is behind the surface\n        }\n", ""),
            edit("common/brdf.glsl", "vec3 brdf_eval(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {\n    if (dot(n, wi) <= 0.0 || dot(n, wo) <= 0.0) {", "vec3 brdf_eval(Material m, vec3 n, vec3 t, vec3 wi, vec3 wo) {\n    if (dot(n, wo) <= 0.0) {"),
        ]),
    },
    Mistake {
        name: "no-distance-falloff",
        explanation: "The light's radiance was not divided by the squared distance.",
        should_be: "E = power / d^2",
        looks_like: "E = power",
        shows_on: ("fig1-lambert", &[]),
        variant: Variant::Shader(&[edit("common/shading.glsl", "lights[i].radiance.rgb / d2, NoL", "lights[i].radiance.rgb, NoL")]),
    },
    Mistake {
        name: "radiance-applied-twice",
        explanation: "The light's radiance was applied twice.",
        should_be: "L = f_r E cos(theta_i), E = power / d^2",
        looks_like: "L = f_r E E cos(theta_i)",
        shows_on: ("fig1-lambert", &[]),
        variant: Variant::Shader(&[edit(
            "common/shading.glsl",
            "lights[i].radiance.rgb / d2, NoL",
            "lights[i].radiance.rgb / d2 * (lights[i].radiance.rgb / d2), NoL",
        )]),
    },
    Mistake {
        name: "gamma-applied",
        explanation: "The image was gamma (sRGB) encoded, where the course writes linear values.",
        should_be: "level = floor(255 clamp(L))",
        looks_like: "level = round(255 srgb(clamp(L)))",
        shows_on: ("fig1-lambert", &[]),
        variant: Variant::Scene(|scene| scene.image.encoding = Encoding::Srgb),
    },
    Mistake {
        name: "rounding",
        explanation: "The levels were rounded to the nearest instead of truncated as the course does.",
        should_be: "level = floor(255 clamp(L))",
        looks_like: "level = round(255 clamp(L))",
        shows_on: ("fig1-lambert", &[]),
        variant: Variant::Rounding,
    },
    Mistake {
        name: "gold-comma-operator",
        explanation: "The gold was written (1.f, 0.85f, 0.57f) inside one constructor argument: C++'s comma operator made it a grey of 0.57.",
        should_be: "kd = F0 = (1, 0.85, 0.57)",
        looks_like: "kd = F0 = (0.57, 0.57, 0.57)",
        shows_on: ("fig4-gold-metalness-1.0", &[]),
        variant: Variant::Scene(grey_gold),
    },
];

/// Every Cook-Torrance material's kd and F0 made the grey their last component is.
fn grey_gold(scene: &mut Scene) {
    for object in &mut scene.objects {
        if let Brdf::CookTorrance { ref mut kd, ref mut f0, .. } = object.brdf {
            *kd = Vec3::splat(kd.z);
            *f0 = Vec3::splat(f0.z);
        }
    }
}
