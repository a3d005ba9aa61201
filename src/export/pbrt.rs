//! pbrt-v4's scene text: `MakeNamedMaterial` directives to put in a scene (or `Import`) and use with
//! `NamedMaterial`. The diffuse lobe is `diffuse`, the specular lobe `conductor` with its eta and k
//! (`super::conductor`) and its roughness as alpha itself (`remaproughness` false: pbrt would
//! otherwise take sqrt(roughness) as alpha); `mix` chooses its second material with probability `amount`,
//! which is ours in expectation: (1 - amount) first + amount second.

use super::{comment, conductor, conductor_fresnel, identifier, lambert_for_oren_nayar, number, numbers};
use super::{CourseMaterial, Format};

/// pbrt-v4 takes a conductor as perfectly smooth (a mirror) below this alpha.
const SMOOTH_ALPHA: f32 = 1e-3;

/// The file's text; `notes` gets what pbrt could not hold as ours.
pub(super) fn write(name: &str, material: &CourseMaterial, notes: &mut Vec<String>) -> String {
    lambert_for_oren_nayar(material, Format::Pbrt, notes);
    conductor_fresnel(material, Format::Pbrt, notes);
    if material.metalness > 0.0 && material.alpha() < SMOOTH_ALPHA {
        notes.push(format!(
            "alpha {} is below pbrt-v4's {SMOOTH_ALPHA}, where its conductor is a perfect mirror",
            material.alpha()
        ));
    }
    let id = identifier(name);
    let diffuse = |named: &str| {
        format!(
            "MakeNamedMaterial \"{named}\"\n    \"string type\" [ \"diffuse\" ]\n    \"rgb reflectance\" [ {} ]\n",
            numbers(material.kd, " ")
        )
    };
    let (eta, k) = conductor(material.f0);
    let conductor = |named: &str| {
        format!(
            "MakeNamedMaterial \"{named}\"\n    \"string type\" [ \"conductor\" ]\n    \"rgb eta\" [ {} ]\n    \
             \"rgb k\" [ {} ]\n    \"float roughness\" [ {} ]\n    \"bool remaproughness\" [ false ]\n",
            numbers(eta, " "),
            numbers(k, " "),
            number(material.alpha())
        )
    };
    let materials = if material.metalness <= 0.0 {
        diffuse(&id)
    } else if material.metalness >= 1.0 {
        conductor(&id)
    } else {
        let (first, second) = (format!("{id}_diffuse"), format!("{id}_conductor"));
        format!(
            "{}{}MakeNamedMaterial \"{id}\"\n    \"string type\" [ \"mix\" ]\n    \"string materials\" [ \"{first}\" \
             \"{second}\" ]\n    \"float amount\" [ {} ]\n",
            diffuse(&first),
            conductor(&second),
            number(material.metalness)
        )
    };
    format!(
        "# {}\n# as pbrt-v4's named material \"{id}\" (NamedMaterial \"{id}\"); see vk-render's docs/export.md for the \
         mapping\n{materials}",
        comment(&material.summary(name))
    )
}
