//! The mappings by hand: each format's parameters for materials whose values are known.

use glam::Vec3;

use super::*;

fn gold() -> Brdf {
    Brdf::CookTorrance {
        kd: Vec3::new(1.0, 0.85, 0.57),
        f0: Vec3::new(1.0, 0.85, 0.57),
        roughness: 0.3,
        metalness: 1.0,
        diffuse: DiffuseModel::OrenNayar,
    }
}

fn mixed() -> Brdf {
    Brdf::CookTorrance {
        kd: Vec3::new(0.5, 0.25, 0.125),
        f0: Vec3::new(0.9, 0.6, 0.3),
        roughness: 0.5,
        metalness: 0.25,
        diffuse: DiffuseModel::Lambert,
    }
}

#[test]
fn a_metal_in_gltf_is_metallic_with_its_f0_as_base_colour() {
    let exported = export("gold", &gold(), Format::Gltf).unwrap();
    let document: serde_json::Value = serde_json::from_str(&exported.text).unwrap();
    let pbr = &document["materials"][0]["pbrMetallicRoughness"];
    assert_eq!(pbr["baseColorFactor"], serde_json::json!([1.0, 0.85, 0.57, 1.0]));
    assert_eq!(pbr["metallicFactor"], 1.0);
    assert_eq!(pbr["roughnessFactor"], 0.3);
    assert_eq!(document["asset"]["version"], "2.0");
    assert!(document.get("extensionsUsed").is_none(), "{}", exported.text);
}

#[test]
fn a_mixed_material_in_gltf_is_a_dielectric_whose_specular_layer_is_ours() {
    let exported = export("mixed", &mixed(), Format::Gltf).unwrap();
    let document: serde_json::Value = serde_json::from_str(&exported.text).unwrap();
    let material = &document["materials"][0];
    let specular = &material["extensions"]["KHR_materials_specular"];
    assert_eq!(specular["specularFactor"], 0.25);
    assert_eq!(specular["specularColorFactor"], serde_json::json!([0.9, 0.6, 0.3]));
    assert_eq!(material["extensions"]["KHR_materials_ior"]["ior"], 0.0);
    assert_eq!(material["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    // (1 - 0.25) kd / (1 - 0.25 * 0.9) = kd * 0.75 / 0.775.
    let base = material["pbrMetallicRoughness"]["baseColorFactor"][0].as_f64().unwrap();
    assert!((base - 0.5 * 0.75 / 0.775).abs() < 1e-6, "{base}");
    assert!(exported.notes.iter().any(|n| n.contains("one base colour")), "{:?}", exported.notes);
}

#[test]
fn mitsuba_and_pbrt_take_alpha_itself_and_mix_by_metalness() {
    let mitsuba = export("mixed", &mixed(), Format::Mitsuba).unwrap().text;
    assert!(mitsuba.contains("<float name=\"alpha\" value=\"0.25\"/>"), "{mitsuba}");
    assert!(mitsuba.contains("<bsdf type=\"blendbsdf\" id=\"mixed\">"), "{mitsuba}");
    assert!(mitsuba.contains("<float name=\"weight\" value=\"0.25\"/>"), "{mitsuba}");
    assert!(mitsuba.contains("<rgb name=\"reflectance\" value=\"0.5, 0.25, 0.125\"/>"), "{mitsuba}");
    let pbrt = export("mixed", &mixed(), Format::Pbrt).unwrap().text;
    assert!(pbrt.contains("\"float roughness\" [ 0.25 ]"), "{pbrt}");
    assert!(pbrt.contains("\"bool remaproughness\" [ false ]"), "{pbrt}");
    assert!(pbrt.contains("\"string materials\" [ \"mixed_diffuse\" \"mixed_conductor\" ]"), "{pbrt}");
    assert!(pbrt.contains("\"float amount\" [ 0.25 ]"), "{pbrt}");
}

#[test]
fn materialx_writes_both_shaders_and_refuses_two_colours_with_a_metalness_between() {
    let leaf = export("gold leaf", &gold(), Format::MaterialX).unwrap().text;
    assert!(leaf.contains("<standard_surface name=\"SR_gold_leaf\" type=\"surfaceshader\">"), "{leaf}");
    assert!(leaf.contains("<input name=\"specular_roughness\" type=\"float\" value=\"0.3\" />"), "{leaf}");
    assert!(leaf.contains("<surfacematerial name=\"gold_leaf\" type=\"material\">"), "{leaf}");
    let open = export("gold", &gold(), Format::OpenPbr).unwrap();
    assert!(open.text.contains("<open_pbr_surface name=\"SR_gold\""), "{}", open.text);
    assert!(open.text.contains("<input name=\"base_metalness\" type=\"float\" value=\"1\" />"), "{}", open.text);
    let refused = export("mixed", &mixed(), Format::OpenPbr).unwrap_err();
    assert!(refused.contains("one base colour") && refused.contains("glTF"), "{refused}");
}

#[test]
fn the_models_with_no_lobe_in_these_formats_are_refused_naming_the_fit() {
    let phong = Brdf::Phong { kd: Vec3::splat(0.5), ks: Vec3::splat(0.2), shininess: 30.0 };
    let refused = export("plastic", &phong, Format::Gltf).unwrap_err();
    assert!(refused.contains("a phong material") && refused.contains("--export"), "{refused}");
}

#[test]
fn names_become_identifiers_and_comments_lose_double_hyphens() {
    assert_eq!(identifier("gold-leaf 2"), "gold_leaf_2");
    assert_eq!(identifier("3d"), "m_3d");
    assert_eq!(comment("a--b\nc"), "a- -b c");
    assert_eq!(number(-0.0), "0");
    assert_eq!(number(0.3), "0.3");
}
