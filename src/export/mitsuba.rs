//! Mitsuba 3's scene XML: a `<scene>` holding one BSDF whose id is the material's name, to `<include>` in a
//! scene and `<ref>` from its shapes. The diffuse lobe is `diffuse`, the specular lobe `roughconductor` with
//! the GGX distribution and alpha itself (not a roughness: roughness^2), its Fresnel a conductor's of eta and
//! k (`super::conductor`); `blendbsdf` weighs them as ours: (1 - weight) first + weight second.

use super::{comment, conductor, conductor_fresnel, identifier, lambert_for_oren_nayar, number, numbers};
use super::{CourseMaterial, Format};

/// The file's text; `notes` gets what Mitsuba could not hold as ours.
pub(super) fn write(name: &str, material: &CourseMaterial, notes: &mut Vec<String>) -> String {
    lambert_for_oren_nayar(material, Format::Mitsuba, notes);
    conductor_fresnel(material, Format::Mitsuba, notes);
    let id = identifier(name);
    let diffuse = |attributes: &str, indent: &str| {
        format!(
            "{indent}<bsdf type=\"diffuse\"{attributes}>\n{indent}    <rgb name=\"reflectance\" value=\"{}\"/>\n\
             {indent}</bsdf>\n",
            numbers(material.kd, ", ")
        )
    };
    let (eta, k) = conductor(material.f0);
    let conductor = |attributes: &str, indent: &str| {
        format!(
            "{indent}<bsdf type=\"roughconductor\"{attributes}>\n\
             {indent}    <string name=\"distribution\" value=\"ggx\"/>\n\
             {indent}    <float name=\"alpha\" value=\"{}\"/>\n\
             {indent}    <rgb name=\"eta\" value=\"{}\"/>\n\
             {indent}    <rgb name=\"k\" value=\"{}\"/>\n{indent}</bsdf>\n",
            number(material.alpha()),
            numbers(eta, ", "),
            numbers(k, ", ")
        )
    };
    let own = format!(" id=\"{id}\"");
    let bsdf = if material.metalness <= 0.0 {
        diffuse(&own, "    ")
    } else if material.metalness >= 1.0 {
        conductor(&own, "    ")
    } else {
        format!(
            "    <bsdf type=\"blendbsdf\"{own}>\n        <float name=\"weight\" value=\"{}\"/>\n{}{}    </bsdf>\n",
            number(material.metalness),
            diffuse("", "        "),
            conductor("", "        ")
        )
    };
    format!(
        "<!-- {} -->\n<!-- as Mitsuba 3's BSDF \"{id}\": <include filename=\"...\"/> it, then <ref id=\"{id}\"/>; see \
         vk-render's docs/export.md for the mapping -->\n<scene version=\"3.0.0\">\n{bsdf}</scene>\n",
        comment(&material.summary(name))
    )
}
