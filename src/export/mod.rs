//! A material of the course's models written for the renderers people use: glTF 2.0, MaterialX
//! (standard_surface and OpenPBR), Mitsuba 3 and pbrt-v4, one module each. Each format names the same GGX
//! lobe differently (a roughness squared, alpha itself, a remapped roughness); the mapping is written here once
//! per format and tabled in docs/export.md, with the sources of each format's definition.
//!
//! What is exported is the course's structure, `(1 - metalness) diffuse + metalness specular`
//! ([`CourseMaterial`]): Lambert, Oren-Nayar and Cook-Torrance. Phong, Blinn-Phong, measured tables and
//! `.brdf` files have no lobe in these formats; `vk-render fit --to cook-torrance --export` writes their
//! nearest Cook-Torrance instead. Where a format's lobe differs from ours (its Smith G, its Fresnel, its lack
//! of a rough diffuse), the export says so in its [`Exported::notes`]; python/tests/test_export.py evaluates
//! every export by the format's own definition and bounds the difference.

mod conductor;
mod gltf;
mod materialx;
mod mitsuba;
mod pbrt;

use glam::Vec3;

use crate::brdf::{ggx_alpha, Brdf, DiffuseModel};

/// The models exported, by their names in scene files.
pub const EXPORTED_MODELS: [&str; 3] = ["lambert", "oren-nayar", "cook-torrance"];

/// A format a material is exported to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// glTF 2.0's metallic-roughness material, with KHR_materials_specular and KHR_materials_ior where needed.
    Gltf,
    /// A MaterialX document with Autodesk Standard Surface (`standard_surface`).
    MaterialX,
    /// A MaterialX document with OpenPBR Surface (`open_pbr_surface`).
    OpenPbr,
    /// Mitsuba 3's scene XML: `diffuse`, `roughconductor` and `blendbsdf`.
    Mitsuba,
    /// pbrt-v4's scene text: `MakeNamedMaterial` with `diffuse`, `conductor` and `mix`.
    Pbrt,
}

impl Format {
    /// Every format, in the order the guide lists them.
    pub const ALL: [Format; 5] = [Format::Gltf, Format::MaterialX, Format::OpenPbr, Format::Mitsuba, Format::Pbrt];

    /// The name the command line takes.
    pub fn name(self) -> &'static str {
        match self {
            Format::Gltf => "gltf",
            Format::MaterialX => "materialx",
            Format::OpenPbr => "openpbr",
            Format::Mitsuba => "mitsuba",
            Format::Pbrt => "pbrt",
        }
    }

    /// The format of a command-line name.
    pub fn named(name: &str) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The format as the messages and the files' headers name it.
    pub fn title(self) -> &'static str {
        match self {
            Format::Gltf => "glTF 2.0",
            Format::MaterialX => "MaterialX standard_surface",
            Format::OpenPbr => "MaterialX open_pbr_surface (OpenPBR)",
            Format::Mitsuba => "Mitsuba 3",
            Format::Pbrt => "pbrt-v4",
        }
    }
}

/// A material of the course's models as its two lobes: `(1 - metalness) diffuse + metalness specular`, the
/// diffuse lobe Lambert's (`sigma` 0) or Oren-Nayar's, the specular lobe GGX with Schlick's Fresnel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CourseMaterial {
    /// The diffuse lobe's reflectance.
    pub kd: Vec3,
    /// Oren-Nayar's sigma in radians; 0 is Lambert.
    pub sigma: f32,
    /// The specular lobe's weight; the diffuse lobe's is 1 - metalness.
    pub metalness: f32,
    /// The specular lobe's Fresnel reflectance at normal incidence.
    pub f0: Vec3,
    /// The specular lobe's roughness r: GGX's alpha is r^2.
    pub roughness: f32,
}

impl CourseMaterial {
    /// The lobes of a built-in model; the other models are refused, naming what to do instead.
    pub fn of(brdf: &Brdf) -> Result<CourseMaterial, String> {
        let diffuse_only =
            |kd: Vec3, sigma: f32| CourseMaterial { kd, sigma, metalness: 0.0, f0: Vec3::ZERO, roughness: 1.0 };
        match *brdf {
            Brdf::Lambert { kd } => Ok(diffuse_only(kd, 0.0)),
            Brdf::OrenNayar { kd, sigma } => Ok(diffuse_only(kd, sigma)),
            Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse } => Ok(CourseMaterial {
                kd,
                sigma: if diffuse == DiffuseModel::OrenNayar { roughness } else { 0.0 },
                metalness,
                f0,
                roughness,
            }),
            _ => Err(format!(
                "a {} material has no lobe in these formats: fit it first, and export the fit (vk-render fit SCENE \
                 --material NAME --to cook-torrance --export FORMAT --export-to OUT)",
                brdf.name()
            )),
        }
    }

    /// GGX's alpha ([`ggx_alpha`]).
    pub fn alpha(&self) -> f32 {
        ggx_alpha(self.roughness)
    }

    /// Whether a format with one base colour for its diffuse and its metal lobes (glTF, Standard Surface,
    /// OpenPBR) holds the material exactly: a lobe alone, or the same colour in both.
    pub fn shares_base_colour(&self) -> bool {
        self.metalness <= 0.0 || self.metalness >= 1.0 || self.kd == self.f0
    }

    /// The colour of the one base colour when [`CourseMaterial::shares_base_colour`].
    fn base_colour(&self) -> Vec3 {
        if self.metalness <= 0.0 {
            self.kd
        } else {
            self.f0
        }
    }

    /// The line that says what the file holds, for its header: the lobes the material has.
    fn summary(&self, name: &str) -> String {
        let diffuse = format!(
            "{} diffuse with kd {}",
            if self.sigma > 0.0 { format!("Oren-Nayar (sigma {})", self.sigma) } else { "Lambert".into() },
            triple(self.kd)
        );
        let specular = format!(
            "GGX specular with F0 {} and roughness {} (alpha {})",
            triple(self.f0),
            self.roughness,
            self.alpha()
        );
        let lobes = if self.metalness <= 0.0 {
            diffuse
        } else if self.metalness >= 1.0 {
            specular
        } else {
            format!("(1 - metalness) {diffuse} + metalness {specular}, metalness {}", self.metalness)
        };
        format!("vk-render export of the material {name}: {lobes}")
    }
}

/// An exported material: the file's text, and what the format could not hold as ours.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The file's whole text.
    pub text: String,
    /// One sentence per difference between the format's lobe and ours, for the user to read.
    pub notes: Vec<String>,
}

/// The material `name` of model `brdf` written in `format`; an error says why a material cannot be.
pub fn export(name: &str, brdf: &Brdf, format: Format) -> Result<Exported, String> {
    let material = CourseMaterial::of(brdf)?;
    let mut notes = Vec::new();
    let text = match format {
        Format::Gltf => gltf::write(name, &material, &mut notes),
        Format::MaterialX | Format::OpenPbr => materialx::write(name, &material, format, &mut notes)?,
        Format::Mitsuba => mitsuba::write(name, &material, &mut notes),
        Format::Pbrt => pbrt::write(name, &material, &mut notes),
    };
    if material.metalness > 0.0 {
        notes.push(format!(
            "the specular lobe's shadowing is {}'s Smith G for GGX, not the course's Smith-Schlick approximation \
             (k = (roughness + 1)^2 / 8)",
            format.title()
        ));
    }
    Ok(Exported { text, notes })
}

/// The note for a format with no rough diffuse lobe, when the material has one.
fn lambert_for_oren_nayar(material: &CourseMaterial, format: Format, notes: &mut Vec<String>) {
    if material.sigma > 0.0 && material.metalness < 1.0 {
        notes.push(format!(
            "the diffuse lobe is Oren-Nayar's (sigma {}): {} has no rough diffuse lobe, so it is written as \
             Lambert's with the same kd",
            material.sigma,
            format.title()
        ));
    }
}

/// The largest F0 the conductors of Mitsuba and pbrt are made for (Gulbrandsen's eta and k diverge at 1).
const CONDUCTOR_MAX: f32 = 0.9999;

/// The eta and k of Mitsuba's and pbrt's conductor for the specular lobe: Fresnel F0 at normal incidence,
/// nearest Schlick's curve elsewhere.
fn conductor(f0: Vec3) -> (Vec3, Vec3) {
    conductor::nearest_schlick(f0, CONDUCTOR_MAX)
}

/// The note for a format whose conductor Fresnel stands for Schlick's.
fn conductor_fresnel(material: &CourseMaterial, format: Format, notes: &mut Vec<String>) {
    if material.metalness > 0.0 {
        notes.push(format!(
            "the specular lobe's Fresnel is {}'s conductor's, its eta and k those of reflectivity F0 (at most \
             {CONDUCTOR_MAX}) whose curve is nearest Schlick's (Gulbrandsen 2014)",
            format.title()
        ));
    }
}

/// A name as an identifier every format takes (MaterialX's are the strictest): letters, digits and `_`, not
/// starting with a digit.
fn identifier(name: &str) -> String {
    let mut id: String = name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert_str(0, "m_");
    }
    id
}

/// A value as the files write it: the shortest decimal that reads back as the same f32.
fn number(value: f32) -> String {
    // -0 written as 0, which every parser takes.
    format!("{}", if value == 0.0 { 0.0 } else { value })
}

/// Three values separated by `separator`.
fn numbers(value: Vec3, separator: &str) -> String {
    value.to_array().map(number).join(separator)
}

/// A colour for the headers: `(r, g, b)`.
fn triple(value: Vec3) -> String {
    format!("({})", numbers(value, ", "))
}

/// Text safe inside an XML comment or a `#` line: no `--`, no line breaks.
fn comment(text: &str) -> String {
    text.replace("--", "- -").replace(['\n', '\r'], " ")
}

#[cfg(test)]
mod tests;
