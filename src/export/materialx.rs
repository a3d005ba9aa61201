//! MaterialX 1.39 documents of one material: a `standard_surface` (Autodesk Standard Surface) or an
//! `open_pbr_surface` (OpenPBR Surface) shader node and the `surfacematerial` that uses it. Both mix a
//! dielectric base (a specular layer over a diffuse lobe) and a metal by their metalness, the metal's colour
//! the base colour: GGX with alpha = specular_roughness^2 (their `roughness_anisotropy` and
//! `open_pbr_anisotropy` nodes with no anisotropy), Standard Surface's Fresnel the artistic conductor's
//! (Gulbrandsen 2014) of base_color and an edge colour, OpenPBR's Schlick's with an F82 tint (Hoffman 2019)
//! that specular_color 1 turns off. The dielectric's own specular layer is turned off by an IOR of 1.

use glam::Vec3;

use super::conductor::edge_colour;
use super::{comment, identifier, number, numbers, CourseMaterial, Format};

/// The largest reflectivity MaterialX's artistic_ior takes (its mx_artistic_ior clamps to it).
const ARTISTIC_MAX: f32 = 0.99;

/// The document's text; an error when the material's two colours cannot share the one base colour.
pub(super) fn write(
    name: &str,
    material: &CourseMaterial,
    format: Format,
    notes: &mut Vec<String>,
) -> Result<String, String> {
    if !material.shares_base_colour() {
        return Err(format!(
            "{} has one base colour for its diffuse and metal lobes, and this material's kd {} and f0 {} differ \
             with metalness {} (neither lobe alone): no parameters of it make this lobe. glTF \
             (KHR_materials_specular), Mitsuba and pbrt hold it; the nearest material with one base colour is \
             a fit (vk-render fit SCENE --material NAME --to metallic-roughness --export FORMAT --export-to OUT)",
            format.title(),
            super::triple(material.kd),
            super::triple(material.f0),
            material.metalness
        ));
    }
    let colour = |value| numbers(value, ", ");
    let one = "1, 1, 1".to_string();
    // Standard Surface's oren_nayar_diffuse_bsdf takes sigma itself (MaterialX 1.39's mx_oren_nayar_diffuse);
    // OpenPBR's EON is another model, its roughness in [0, 1]: sigma / pi, which tests/test_export.py finds
    // within 0.01 of the best single factor at sigma 0.3 and 0.6.
    let diffuse_roughness = |scale: f32| number(material.sigma * scale);
    let inputs: Vec<(&str, &str, String)> = match format {
        Format::OpenPbr => {
            if material.sigma > 0.0 && material.metalness < 1.0 {
                notes.push(format!(
                    "OpenPBR's diffuse lobe is the energy-preserving Oren-Nayar (EON, Portsmouth et al. 2025), not \
                     the course's qualitative one: base_diffuse_roughness = sigma / pi = {}",
                    diffuse_roughness(std::f32::consts::FRAC_1_PI)
                ));
            }
            vec![
                ("base_weight", "float", number(1.0)),
                ("base_color", "color3", colour(material.base_colour())),
                ("base_metalness", "float", number(material.metalness)),
                ("base_diffuse_roughness", "float", diffuse_roughness(std::f32::consts::FRAC_1_PI)),
                ("specular_weight", "float", number(1.0)),
                ("specular_color", "color3", one),
                ("specular_roughness", "float", number(material.roughness)),
                ("specular_ior", "float", number(1.0)),
            ]
        }
        _ => {
            standard_surface_notes(material, notes);
            let edge = Vec3::from_array(material.f0.to_array().map(|f0| edge_colour(f0, ARTISTIC_MAX)));
            vec![
                ("base", "float", number(1.0)),
                ("base_color", "color3", colour(material.base_colour())),
                ("metalness", "float", number(material.metalness)),
                ("diffuse_roughness", "float", diffuse_roughness(1.0)),
                ("specular", "float", number(1.0)),
                // The metal's edge colour (its dielectric layer reflects nothing with an IOR of 1).
                ("specular_color", "color3", colour(edge)),
                ("specular_roughness", "float", number(material.roughness)),
                ("specular_IOR", "float", number(1.0)),
            ]
        }
    };
    let node = if format == Format::OpenPbr { "open_pbr_surface" } else { "standard_surface" };
    let material_name = identifier(name);
    let shader_name = format!("SR_{material_name}");
    let mut text = format!(
        "<?xml version=\"1.0\"?>\n<!-- {} -->\n<!-- as {}: see vk-render's docs/export.md for the mapping -->\n\
         <materialx version=\"1.39\">\n  <{node} name=\"{shader_name}\" type=\"surfaceshader\">\n",
        comment(&material.summary(name)),
        format.title()
    );
    for (input, kind, value) in inputs {
        text.push_str(&format!("    <input name=\"{input}\" type=\"{kind}\" value=\"{value}\" />\n"));
    }
    text.push_str(&format!(
        "  </{node}>\n  <surfacematerial name=\"{material_name}\" type=\"material\">\n    <input \
         name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{shader_name}\" />\n  </surfacematerial>\n\
         </materialx>\n"
    ));
    Ok(text)
}

/// Standard Surface's metal Fresnel.
fn standard_surface_notes(material: &CourseMaterial, notes: &mut Vec<String>) {
    if material.metalness > 0.0 {
        notes.push(format!(
            "Standard Surface's metal Fresnel is the artistic conductor's (Gulbrandsen 2014) of reflectivity \
             base_color = F0, equal to Schlick's at normal incidence; its edge colour specular_color is the one whose \
             curve is nearest Schlick's{}",
            if material.f0.max_element() > ARTISTIC_MAX {
                format!("; MaterialX clamps the reflectivity to {ARTISTIC_MAX}")
            } else {
                String::new()
            }
        ));
    }
}
