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
        }
    }
}

/// `[camera]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraSection {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    pub fov_y: f32,
}

impl Default for CameraSection {
    fn default() -> Self {
        Self { position: [0.0, 0.0, 0.0], look_at: [0.0, 0.0, 1.0], up: [0.0, 1.0, 0.0], fov_y: 60.0 }
    }
}

/// One `[[light]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSection {
    #[serde(rename = "type", default = "default_light_type")]
    pub kind: String,
    pub position: [f32; 3],
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
}

/// One `[[object]]`: the keys of every shape, each checked against the shape in validation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSection {
    pub shape: String,
    pub material: String,
    pub center: Option<[f32; 3]>,
    pub radius: Option<f32>,
    pub point: Option<[f32; 3]>,
    pub normal: Option<[f32; 3]>,
    pub path: Option<String>,
    pub scale: Option<f32>,
    pub rotate: Option<[f32; 3]>,
    pub translate: Option<[f32; 3]>,
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

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Rgb, A::Error> {
                let mut rgb = [0.0f32; 3];
                for (i, channel) in rgb.iter_mut().enumerate() {
                    *channel = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(Rgb(rgb))
            }
        }

        deserializer.deserialize_any(RgbVisitor)
    }
}
