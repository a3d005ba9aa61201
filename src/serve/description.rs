//! The catalogue as `GET /api/scenes` describes it (and a site's `data/scenes.json`): each scene's size,
//! materials with the controls the explore page gives their parameters, objects, lights and camera, and
//! what the page needs to render it in the browser.

use std::collections::BTreeMap;

use serde::Serialize;

use vk_render::brdf::{Brdf, ParameterValue};

use super::browser::{self, BrowserScene};
use super::catalogue::{Catalogue, Entry};

/// Every scene of `catalogue`, by id.
pub fn describe(catalogue: &Catalogue) -> Vec<SceneDescription> {
    catalogue.entries().map(describe_scene).collect()
}

/// A scene as the API describes it.
#[derive(Serialize)]
pub struct SceneDescription {
    pub id: String,
    pub title: String,
    pub figure: bool,
    pub width: u32,
    pub height: u32,
    pub materials: BTreeMap<String, MaterialDescription>,
    pub objects: Vec<ObjectDescription>,
    pub lights: Vec<LightDescription>,
    pub camera: CameraDescription,
    pub environment: bool,
    /// What the page needs to render the scene in the browser.
    pub browser: BrowserScene,
}

#[derive(Serialize)]
pub struct MaterialDescription {
    /// The model's name as scene files write it.
    pub model: &'static str,
    /// The analytic model's file name, for a `.brdf` material.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    pub parameters: Vec<ParameterDescription>,
}

/// One parameter a control sets: the `set` key, its value now and the range the control spans.
#[derive(Serialize)]
pub struct ParameterDescription {
    pub name: String,
    /// The key of `--set` and of the API's `set`.
    pub key: String,
    /// "number", "colour" or "bool".
    pub kind: &'static str,
    pub value: serde_json::Value,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max: Option<f32>,
    /// Whether the control moves on a log scale (a shininess from 0.5 to 20000).
    pub log: bool,
}

#[derive(Serialize)]
pub struct ObjectDescription {
    pub index: usize,
    pub shape: &'static str,
    pub material: String,
}

#[derive(Serialize)]
pub struct LightDescription {
    pub index: usize,
    pub position: [f32; 3],
    pub power: f32,
    pub color: [f32; 3],
}

#[derive(Serialize)]
pub struct CameraDescription {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    pub fov_y: f32,
}

fn describe_scene(entry: &Entry) -> SceneDescription {
    let scene = &entry.scene;
    let materials = scene.materials.iter().map(|(name, brdf)| (name.clone(), describe_material(name, brdf))).collect();
    let objects = scene
        .objects
        .iter()
        .enumerate()
        .map(|(index, object)| ObjectDescription {
            index,
            shape: object.shape.kind(),
            material: object.material.clone(),
        })
        .collect();
    let lights = scene
        .lights
        .iter()
        .enumerate()
        .map(|(index, light)| LightDescription {
            index,
            position: light.position.to_array(),
            power: light.power,
            color: light.color.to_array(),
        })
        .collect();
    let camera = &scene.camera;
    SceneDescription {
        id: entry.id.clone(),
        title: entry.title.clone(),
        figure: entry.figure,
        width: scene.image.width,
        height: scene.image.height,
        materials,
        objects,
        lights,
        camera: CameraDescription {
            position: camera.position.to_array(),
            look_at: camera.look_at.to_array(),
            up: camera.up.to_array(),
            fov_y: camera.fov_y,
        },
        environment: scene.environment.is_some(),
        browser: browser::describe(entry),
    }
}

/// The ranges the explore page's controls span for the course's models: a reflectance from 0 to 1, the
/// shape parameters over the ranges `vk-render fit` searches.
fn built_in_range(name: &str) -> (f32, f32, bool) {
    match name {
        "sigma" => (0.0, 1.5, false),
        "shininess" => (0.5, 20000.0, true),
        "roughness" => (0.02, 1.0, false),
        _ => (0.0, 1.0, false),
    }
}

impl ParameterDescription {
    /// A control of `kind` for `key`, at `value`, spanning `range` (its bounds and whether on a log scale).
    fn new(
        name: &str,
        key: String,
        kind: &'static str,
        value: serde_json::Value,
        range: Option<(f32, f32, bool)>,
    ) -> Self {
        Self {
            name: name.into(),
            key,
            kind,
            value,
            min: range.map(|r| r.0),
            max: range.map(|r| r.1),
            log: range.is_some_and(|r| r.2),
        }
    }
}

/// A colour's control spans each component from 0 to 1.
const COLOUR_RANGE: (f32, f32, bool) = (0.0, 1.0, false);

fn describe_material(material: &str, brdf: &Brdf) -> MaterialDescription {
    let key = |name: &str| format!("material.{material}.{name}");
    let number = |name: &str, value: f32| {
        ParameterDescription::new(name, key(name), "number", serde_json::json!(value), Some(built_in_range(name)))
    };
    let rgb = |name: &str, value: glam::Vec3| {
        ParameterDescription::new(name, key(name), "colour", serde_json::json!(value.to_array()), Some(COLOUR_RANGE))
    };
    let (parameters, file) = match brdf {
        Brdf::Lambert { kd } => (vec![rgb("kd", *kd)], None),
        Brdf::OrenNayar { kd, sigma } => (vec![rgb("kd", *kd), number("sigma", *sigma)], None),
        Brdf::Phong { kd, ks, shininess } | Brdf::BlinnPhong { kd, ks, shininess } => {
            (vec![rgb("kd", *kd), rgb("ks", *ks), number("shininess", *shininess)], None)
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, .. } => (
            vec![rgb("kd", *kd), rgb("f0", *f0), number("roughness", *roughness), number("metalness", *metalness)],
            None,
        ),
        Brdf::Measured(_) => (Vec::new(), None),
        Brdf::Analytic(analytic) => {
            let parameters = analytic
                .values()
                .map(|(parameter, value)| {
                    let (name, key) = (&parameter.name, key(&format!("params.{}", parameter.name)));
                    let (kind, range) = parameter.kind.control();
                    let value = match value {
                        ParameterValue::Float(v) => serde_json::json!(v),
                        ParameterValue::Bool(b) => serde_json::json!(b),
                        ParameterValue::Color(c) => serde_json::json!(c.to_array()),
                    };
                    ParameterDescription::new(name, key, kind, value, range.map(|(min, max)| (min, max, false)))
                })
                .collect();
            (parameters, Some(analytic.model().name()))
        }
    };
    MaterialDescription { model: brdf.name(), file, parameters }
}
