//! Studying the reflectance models rather than their pictures: lobes, directional albedos and the white
//! furnace, all computed on the GPU by the probe pass from `brdf_eval`, the very GLSL the renders shade with,
//! so that a plot and a render can never disagree. A layer above [`crate::render`]; [`crate::pictures::chart`] draws
//! what it computes.

pub use crate::render::albedo;
pub mod chi2;
pub mod fit;
pub mod furnace;
pub mod image_fit;
pub mod lobe;
pub mod lobe3d;
pub mod plots;
pub mod sampling;
pub mod slice;

use std::path::PathBuf;

use glam::Vec3;

use crate::brdf::measured::entry_directions;
use crate::brdf::{Brdf, DiffuseModel, MeasuredTable};
use crate::error::{Error, Result};
use crate::render::Renderer;
use crate::scene::Scene;

/// `brdf` as a MERL table (to be written to `path`), as if measured: the probe pass (`brdf_eval`, the GLSL the
/// renders run) at the centre of every entry. `vk-render tabulate` writes a `.brdf` file's so.
///
/// # Errors
/// What the probe pass returns.
pub fn tabulated(renderer: &mut Renderer, brdf: &Brdf, path: PathBuf) -> Result<MeasuredTable> {
    let values = renderer.probe_brdf_grid(std::slice::from_ref(brdf), &entry_directions())?;
    Ok(MeasuredTable::from_entries(path, &values))
}

/// A material of a scene, by its `[material.NAME]`.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedBrdf {
    /// The `NAME` of its `[material.NAME]`.
    pub name: String,
    /// Its BRDF, as the scene defines it.
    pub brdf: Brdf,
}

/// The materials to study: every one the scene defines (by name), or those `names` lists, in its order.
///
/// # Errors
/// `Error::Scene` naming the scene file when a name is not a material of it, or when it defines none.
pub fn select_materials(scene: &Scene, names: Option<&[String]>) -> Result<Vec<NamedBrdf>> {
    let error = |message: String| Error::Scene { file: scene.source.clone(), message };
    let defined = || scene.materials.keys().map(String::as_str).collect::<Vec<_>>().join(", ");
    if scene.materials.is_empty() {
        return Err(error("the scene defines no [material.NAME] to study".into()));
    }
    let Some(names) = names else {
        return Ok(scene
            .materials
            .iter()
            .map(|(name, brdf)| NamedBrdf { name: name.clone(), brdf: brdf.clone() })
            .collect());
    };
    names
        .iter()
        .map(|name| match scene.materials.get(name) {
            Some(brdf) => Ok(NamedBrdf { name: name.clone(), brdf: brdf.clone() }),
            None => Err(error(format!("--material {name}: no such material (the scene defines {})", defined()))),
        })
        .collect()
}

/// Which channel of an RGB value a plot shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// The red channel.
    Red,
    /// The green channel.
    Green,
    /// The blue channel.
    Blue,
    /// Rec. 709 luminance: 0.2126 R + 0.7152 G + 0.0722 B.
    Luminance,
}

impl Channel {
    /// The channel's value.
    pub fn of(self, rgb: [f64; 3]) -> f64 {
        match self {
            Channel::Red => rgb[0],
            Channel::Green => rgb[1],
            Channel::Blue => rgb[2],
            Channel::Luminance => 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2],
        }
    }

    /// How a plot's axis names it.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Red => "red",
            Channel::Green => "green",
            Channel::Blue => "blue",
            Channel::Luminance => "luminance",
        }
    }
}

/// A Vec3 as three f64.
pub fn rgb(value: Vec3) -> [f64; 3] {
    value.as_dvec3().to_array()
}

/// The model and its parameters in one short line, for titles and legends: `cook-torrance f0 = (1, 0.85,
/// 0.57), roughness 0.3, metalness 1`.
pub fn describe(brdf: &Brdf) -> String {
    let colour = |c: Vec3| {
        if c.x == c.y && c.y == c.z {
            format!("{}", c.x)
        } else {
            format!("({}, {}, {})", c.x, c.y, c.z)
        }
    };
    match *brdf {
        Brdf::Lambert { kd } => format!("lambert kd {}", colour(kd)),
        Brdf::OrenNayar { kd, sigma } => format!("oren-nayar kd {}, sigma {sigma}", colour(kd)),
        Brdf::Phong { kd, ks, shininess } => format!("phong kd {}, ks {}, s {shininess}", colour(kd), colour(ks)),
        Brdf::BlinnPhong { kd, ks, shininess } => {
            format!("blinn-phong kd {}, ks {}, s {shininess}", colour(kd), colour(ks))
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse } => format!(
            "cook-torrance kd {}, f0 {}, roughness {roughness}, metalness {metalness}{}",
            colour(kd),
            colour(f0),
            if diffuse == DiffuseModel::Lambert { ", lambert diffuse" } else { "" }
        ),
        Brdf::Measured(ref table) => format!(
            "measured {}",
            table.path().file_name().map_or_else(|| table.path().display().to_string(), |f| f.to_string_lossy().into())
        ),
        Brdf::Analytic(ref material) => material.describe(),
    }
}

/// A CSV table: a header row, then one row per angle: the angle in degrees, then three columns per series,
/// `NAME_r,NAME_g,NAME_b`.
pub fn angle_table(angle: &str, angles: &[f64], series: &[(String, Vec<[f64; 3]>)]) -> String {
    let mut csv = String::from(angle);
    for (name, _) in series {
        csv.push_str(&format!(",{name}_r,{name}_g,{name}_b"));
    }
    csv.push('\n');
    for (row, angle) in angles.iter().enumerate() {
        csv.push_str(&format!("{angle}"));
        for (_, values) in series {
            let [r, g, b] = values[row];
            csv.push_str(&format!(",{r},{g},{b}"));
        }
        csv.push('\n');
    }
    csv
}
