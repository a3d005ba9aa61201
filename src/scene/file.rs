//! The scene file as written: serde structures that mirror SCENE_FORMAT version 1 key for key.
//!
//! Unknown keys and wrong types are caught here by serde (with the line, through toml's spans);
//! ranges and cross-references are checked in `validate.rs`, which turns these into `Scene`.

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;

/// A whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    #[serde(default)]
    pub image: ImageSection,
    #[serde(default)]
    pub camera: CameraSection,
    #[serde(default, rename = "light")]
    pub lights: Vec<LightSection>,
    #[serde(default, rename = "material")]
    pub materials: BTreeMap<String, MaterialSection>,
    #[serde(default, rename = "object")]
    pub objects: Vec<ObjectSection>,
    pub environment: Option<EnvironmentSection>,
}

/// `[image]`: integers are kept signed so that 0 or -3 is reported as out of range, not as a type error.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImageSection {
    pub width: i64,
    pub height: i64,
    pub samples: i64,
    pub background: Rgb,
    pub tonemap: String,
    pub exposure: f32,
    pub encoding: String,
    pub shadow_map_size: i64,
    pub shadow_filter: String,
    pub view: String,
}

impl Default for ImageSection {
    fn default() -> Self {
        Self {
            width: 600,
            height: 400,
            samples: 4,
            background: Rgb([0.5; 3]),
            tonemap: "clamp".into(),
            exposure: 1.0,
            encoding: "linear".into(),
            shadow_map_size: super::DEFAULT_SHADOW_MAP_SIZE.into(),
            shadow_filter: "hard".into(),
            view: "radiance".into(),
        }
    }
}

/// `[camera]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraSection {
    pub position: Xyz,
    pub look_at: Xyz,
    pub up: Xyz,
    pub fov_y: f32,
}

impl Default for CameraSection {
    fn default() -> Self {
        Self { position: Xyz([0.0, 0.0, 0.0]), look_at: Xyz([0.0, 0.0, 1.0]), up: Xyz([0.0, 1.0, 0.0]), fov_y: 60.0 }
    }
}

/// One `[[light]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSection {
    #[serde(rename = "type", default = "default_light_type")]
    pub kind: String,
    pub position: Xyz,
    #[serde(default = "white")]
    pub color: Rgb,
    #[serde(default = "one")]
    pub power: f32,
    #[serde(default = "yes")]
    pub shadows: bool,
}

fn default_light_type() -> String {
    "point".into()
}
fn white() -> Rgb {
    Rgb([1.0; 3])
}
fn one() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}

/// `[environment]`: a map or a built-in, exactly one of the two.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentSection {
    pub map: Option<String>,
    pub builtin: Option<String>,
    #[serde(default = "one")]
    pub intensity: f32,
    #[serde(default)]
    pub rotation: f32,
    #[serde(default = "yes")]
    pub visible: bool,
    #[serde(default = "exact")]
    pub mode: String,
}

fn exact() -> String {
    "exact".into()
}

/// One `[material.NAME]`: every parameter of every model, each checked against the model in validation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    pub brdf: String,
    pub kd: Option<Rgb>,
    pub ks: Option<Rgb>,
    pub f0: Option<Rgb>,
    pub shininess: Option<f32>,
    pub sigma: Option<f32>,
    pub roughness: Option<f32>,
    pub metalness: Option<f32>,
    pub diffuse: Option<String>,
    pub file: Option<String>,
    /// An analytic material's parameter values, by the names its `.brdf` file declares.
    pub params: Option<toml::Table>,
    /// A measured material: whether the exact mode draws from the table's own sampler (true unless set).
    pub sampler: Option<bool>,
}

/// One `[[object]]`: the keys of every shape, each checked against the shape in validation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSection {
    pub shape: String,
    pub material: String,
    pub center: Option<Xyz>,
    pub radius: Option<f32>,
    pub point: Option<Xyz>,
    pub normal: Option<Xyz>,
    pub path: Option<String>,
    pub scale: Option<f32>,
    pub rotate: Option<Xyz>,
    pub translate: Option<Xyz>,
}

/// A point or a direction: exactly three numbers `[x, y, z]`, a list of another length being an error
/// (not truncated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Xyz(pub [f32; 3]);

impl<'de> Deserialize<'de> for Xyz {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct XyzVisitor;

        impl<'de> Visitor<'de> for XyzVisitor {
            type Value = Xyz;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a list of three numbers [x, y, z]")
            }

            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Xyz, A::Error> {
                three_numbers(seq, &self).map(Xyz)
            }
        }

        deserializer.deserialize_seq(XyzVisitor)
    }
}

/// Exactly three numbers from a list, `expected` naming what the list is in errors.
fn three_numbers<'de, A: SeqAccess<'de>>(mut seq: A, expected: &dyn de::Expected) -> Result<[f32; 3], A::Error> {
    let mut values = [0.0f32; 3];
    for (i, value) in values.iter_mut().enumerate() {
        *value = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, expected))?;
    }
    let mut count = 3;
    while seq.next_element::<de::IgnoredAny>()?.is_some() {
        count += 1;
    }
    if count > 3 {
        return Err(de::Error::invalid_length(count, expected));
    }
    Ok(values)
}

/// A linear RGB colour: `[r, g, b]`, or a single number for a grey.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb(pub [f32; 3]);

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct RgbVisitor;

        impl<'de> Visitor<'de> for RgbVisitor {
            type Value = Rgb;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a colour: a number (grey) or an array of three numbers [r, g, b]")
            }

            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Rgb, E> {
                Ok(Rgb([v as f32; 3]))
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Rgb, E> {
                Ok(Rgb([v as f32; 3]))
            }

            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Rgb, A::Error> {
                three_numbers(seq, &self).map(Rgb)
            }
        }

        deserializer.deserialize_any(RgbVisitor)
    }
}
