//! The scenes a server offers, made once at start: the practical's figures and every scene file of the
//! folders given with `--scenes`, each by its id (its file's stem). A request names a scene by id and only
//! by id: nothing a client sends is ever a path.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Context;
use serde::Serialize;

use vk_render::brdf::{Brdf, ParameterValue};
use vk_render::figures::FIGURES;
use vk_render::{Override, Scene};

/// One scene of the catalogue.
pub struct Entry {
    pub id: String,
    /// The figure's label, or the file's name.
    pub title: String,
    /// The scene file's text, parsed again with each request's overrides.
    text: String,
    /// Where it was read from (mesh and material files are found beside it).
    path: PathBuf,
    /// The scene as its file says (no overrides).
    pub scene: Scene,
    /// Whether it is one of the practical's figures (a check without a scene is matched among those).
    pub figure: bool,
}

impl Entry {
    /// The scene with `overrides`, as `vk-render render --set` makes it.
    pub fn scene(&self, overrides: &[Override]) -> vk_render::Result<Scene> {
        Scene::parse(&self.text, &self.path, overrides)
    }

    /// The scene file's text (the explore page's download starts from it).
    pub fn text(&self) -> &str {
        &self.text
    }
}

/// Every scene offered, by id.
pub struct Catalogue {
    entries: BTreeMap<String, Entry>,
}

impl Catalogue {
    /// The practical's figures, then the `.toml` files of each folder (not their subfolders). Two scenes with
    /// one id, or a file that is not a valid scene, stop the server from starting, naming the files.
    pub fn new(folders: &[PathBuf]) -> anyhow::Result<Self> {
        let mut entries = BTreeMap::new();
        for figure in FIGURES {
            for image in figure.images {
                let id = image.file.trim_end_matches(".toml").to_string();
                let scene = image.scene(&[])?;
                let entry = Entry {
                    id: id.clone(),
                    title: format!("{}: {}", figure.title, image.label),
                    text: image.text().to_string(),
                    path: scene.source.clone(),
                    scene,
                    figure: true,
                };
                entries.insert(id, entry);
            }
        }
        for folder in folders {
            let listing = std::fs::read_dir(folder)
                .with_context(|| format!("--scenes {}: cannot read the folder", folder.display()))?;
            let mut files: Vec<PathBuf> = listing
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            files.sort();
            for path in files {
                let id = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                if !is_id(&id) {
                    anyhow::bail!(
                        "{}: a scene's id is its file's stem, of letters, digits, '-', '_' and '.'",
                        path.display()
                    );
                }
                if let Some(other) = entries.get(&id) {
                    anyhow::bail!("{}: its id `{id}` is already {}'s", path.display(), other.path.display());
                }
                let text =
                    std::fs::read_to_string(&path).with_context(|| format!("{}: cannot read it", path.display()))?;
                let scene = Scene::parse(&text, &path, &[])?;
                let title = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                entries.insert(id.clone(), Entry { id, title, text, path, scene, figure: false });
            }
        }
        Ok(Self { entries })
    }

    /// The scene `id`, if the catalogue has it.
    pub fn get(&self, id: &str) -> Option<&Entry> {
        self.entries.get(id)
    }

    /// Every scene, by id.
    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }

    /// The catalogue as `GET /api/scenes` answers it.
    pub fn describe(&self) -> Vec<SceneDescription> {
        self.entries.values().map(describe_scene).collect()
    }
}

/// Whether `text` could be a scene's id (ids are file stems; anything else is no scene's).
pub fn is_id(text: &str) -> bool {
    !text.is_empty()
        && text.len() <= 128
        && !text.starts_with('.')
        && text.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
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
    pub browser: super::browser::BrowserScene,
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
        browser: super::browser::describe(entry),
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
