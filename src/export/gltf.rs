//! glTF 2.0: a document of one material, its metallic-roughness parameters and, where needed,
//! KHR_materials_specular and KHR_materials_ior. The lobe is the specification's Appendix B: material =
//! mix(dielectric, metal, metallic), the metal GGX (alpha = roughness^2) with Schlick's Fresnel from
//! baseColor, the dielectric KHR_materials_specular's fresnel_mix of Lambert's lobe and the same GGX.

use glam::Vec3;
use serde_json::{json, Map, Value};

use super::{lambert_for_oren_nayar, CourseMaterial, Format};

/// The document's text; `notes` gets what glTF could not hold as ours.
pub(super) fn write(name: &str, material: &CourseMaterial, notes: &mut Vec<String>) -> String {
    lambert_for_oren_nayar(material, Format::Gltf, notes);
    let m = material.metalness;
    let mut extensions = Map::new();
    let (base_colour, metallic) = if material.shares_base_colour() {
        // metal = Schlick(baseColor) GGX, weighed by metallic as ours by metalness; the dielectric's own
        // specular reflection (F0 0.04) turned off, leaving Lambert's lobe of baseColor.
        if m < 1.0 {
            extensions.insert("KHR_materials_specular".into(), json!({ "specularFactor": 0.0 }));
        }
        (material.base_colour(), m)
    } else {
        // A dielectric whose specular layer is ours: with ior 0 its F0 is specularColorFactor itself (the
        // extension's conversion of specular-glossiness materials), its weight specularFactor. fresnel_mix
        // weighs the diffuse lobe by 1 - specularFactor max(F); baseColor makes it (1 - metalness) kd where
        // F = F0, at normal incidence on the half vector.
        extensions.insert(
            "KHR_materials_specular".into(),
            json!({ "specularFactor": decimal(m), "specularColorFactor": material.f0.to_array().map(decimal) }),
        );
        extensions.insert("KHR_materials_ior".into(), json!({ "ior": 0.0 }));
        let base = (1.0 - m) * material.kd / (1.0 - m * material.f0.max_element());
        let clamped = base.clamp(Vec3::ZERO, Vec3::ONE);
        notes.push(format!(
            "glTF has one base colour for its diffuse and metal lobes, and this material's kd and f0 differ: it is \
             written as a dielectric whose specular layer (KHR_materials_specular, KHR_materials_ior) is the \
             specular lobe; glTF weighs its diffuse lobe by 1 - {m} max(F), which is 1 - metalness only where F \
             is F0, so baseColor is (1 - metalness) kd / (1 - metalness max(F0)) = {}{}, and the diffuse lobe is \
             darker than ours towards grazing half angles",
            super::triple(clamped),
            if clamped == base { "" } else { " (clamped to 1)" }
        ));
        (clamped, 0.0)
    };
    let mut gltf_material = json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [decimal(base_colour.x), decimal(base_colour.y), decimal(base_colour.z), 1.0],
            "metallicFactor": decimal(metallic),
            "roughnessFactor": decimal(material.roughness),
        },
        "extras": { "source": material.summary(name) },
    });
    let used: Vec<String> = extensions.keys().cloned().collect();
    if !extensions.is_empty() {
        gltf_material["extensions"] = Value::Object(extensions);
    }
    let mut document = json!({
        "asset": { "version": "2.0", "generator": concat!("vk-render ", env!("CARGO_PKG_VERSION")) },
        "materials": [gltf_material],
    });
    if !used.is_empty() {
        document["extensionsUsed"] = json!(used);
    }
    format!("{document:#}\n")
}

/// An f32 as the f64 of its shortest decimal, so that the JSON reads 0.3 and not 0.30000001192092896.
fn decimal(value: f32) -> f64 {
    super::number(value).parse().unwrap_or(f64::from(value))
}
