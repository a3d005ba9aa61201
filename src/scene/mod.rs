//! Scene files (SCENE_FORMAT version 1): parsing, `--set` overrides and validation.
//!
//! No GPU types here: a `Scene` is plain data that the Vulkan renderer and the CPU code both read.

pub mod figures;
mod file;
pub mod grid;
mod overrides;
mod validate;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use crate::brdf::Brdf;
use crate::error::{Error, Result};

pub use overrides::{shortened, Override, Shorthands};

/// The default `[image] shadow_map_size`: a 1024 x 1024 cube face is 0.09 degrees a texel, so a shadow
/// edge on the course's plane (3 to 10 units from the light) is placed within 5 to 15 mm.
pub const DEFAULT_SHADOW_MAP_SIZE: u32 = 1024;

/// The largest image side a scene may ask for, in pixels (no Vulkan device renders more; each device's own,
/// lower limit is checked when it renders).
pub const MAX_IMAGE_SIDE: u32 = 65536;

/// The most lights a scene may hold, each with its own shadow cube.
pub const MAX_LIGHTS: usize = 16;

/// The installed Stanford bunny that `path = "bunny"` names (Debian package glmark2-data).
pub const BUNNY_PATH: &str = "/usr/share/glmark2/models/bunny.obj";

/// A validated scene, ready to render.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The file it was read from: error messages name it and mesh paths are relative to it.
    pub source: PathBuf,
    /// `[image]`: the output's size, sampling and output transform.
    pub image: ImageSettings,
    /// `[camera]`: where the image is seen from.
    pub camera: Camera,
    /// Every `[[light]]`, in file order (at most [`MAX_LIGHTS`]).
    pub lights: Vec<PointLight>,
    /// Every `[[object]]`, in file order, each with its material resolved.
    pub objects: Vec<Object>,
    /// Every `[material.NAME]` as the file defines it, by name, used or not (the analysis commands study
    /// them; each object holds its own copy, which the preview edits).
    pub materials: BTreeMap<String, Brdf>,
    /// `[environment]`: light from every direction, if the scene has it.
    pub environment: Option<Environment>,
}

/// `[environment]`: radiance arriving from every direction, not occluded by the scene's objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// `map` (a file beside the scene) or `builtin`: exactly one of the two.
    pub source: EnvironmentSource,
    /// The radiance's scale.
    pub intensity: f32,
    /// Degrees about +y: the map's centre, +z unrotated, turns towards +x for a positive rotation.
    pub rotation: f32,
    /// Whether the background shows the environment (or `image.background`).
    pub visible: bool,
    /// `mode`: how the light is integrated (default exact).
    pub mode: EnvironmentMode,
}

/// Where an environment's radiance comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// An equirectangular map (Radiance .hdr or OpenEXR), linear radiance, twice as wide as high.
    Map(PathBuf),
    /// A map vk-render makes itself (`builtin = "white"`, `"sky"` or `"studio"`).
    Builtin(BuiltinEnvironment),
}

/// The environments vk-render makes itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BuiltinEnvironment {
    /// Radiance 1 from every direction: the white furnace.
    White,
    /// An analytic sky over a ground, with a sun.
    Sky,
    /// Soft light panels over a dark floor.
    Studio,
}

impl BuiltinEnvironment {
    /// Every built-in environment, in the order messages list them.
    pub const ALL: [BuiltinEnvironment; 3] =
        [BuiltinEnvironment::White, BuiltinEnvironment::Sky, BuiltinEnvironment::Studio];

    /// The name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            BuiltinEnvironment::White => "white",
            BuiltinEnvironment::Sky => "sky",
            BuiltinEnvironment::Studio => "studio",
        }
    }
}

/// How the environment's light is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EnvironmentMode {
    /// Monte Carlo integration of brdf_eval against the environment, pass after pass until its standard
    /// error is below a stated bound: for stills.
    Exact,
    /// Prefiltered maps and per-material albedo tables (a split sum): for the preview.
    Fast,
}

impl EnvironmentMode {
    /// The name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            EnvironmentMode::Exact => "exact",
            EnvironmentMode::Fast => "fast",
        }
    }

    /// The mode a name gives.
    pub fn from_name(name: &str) -> Option<Self> {
        [EnvironmentMode::Exact, EnvironmentMode::Fast].into_iter().find(|m| m.name() == name)
    }
}

/// `[image]`: the output's size, sampling and output transform.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageSettings {
    /// Image width in pixels, 1 to [`MAX_IMAGE_SIDE`] (default 600).
    pub width: u32,
    /// Image height in pixels, 1 to [`MAX_IMAGE_SIDE`] (default 400).
    pub height: u32,
    /// MSAA samples per pixel; the device decides which counts it supports.
    pub samples: u32,
    /// Linear radiance where no object is seen.
    pub background: Vec3,
    /// The tone curve after exposure (default clamp).
    pub tonemap: Tonemap,
    /// The factor linear radiance is multiplied by before the tone curve, at least 0 (default 1).
    pub exposure: f32,
    /// How the tone-mapped value becomes an 8-bit level (default linear).
    pub encoding: Encoding,
    /// The side of each face of a light's shadow cube, in texels.
    pub shadow_map_size: u32,
    /// Hard shadows (the course) or percentage-closer filtered ones.
    pub shadow_filter: ShadowFilter,
    /// What the image shows: the radiance, or one term of the shading.
    pub view: View,
}

/// What an image shows at each pixel: the radiance (the render), or one term of the shading, so that a term
/// that differs from a student's can be seen. Each light's term is summed over the lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The outgoing radiance: the render.
    Radiance,
    /// The shading normal (facing the camera), each component in [-1, 1].
    Normal,
    /// max(0, n . wi), summed over the lights.
    NDotL,
    /// f_r(wi, wo) alone, summed over the lights.
    Brdf,
    /// Cook-Torrance's microfacet distribution D(h) (GGX), summed over the lights.
    D,
    /// Cook-Torrance's shadowing-masking G (Smith-Schlick), summed over the lights.
    G,
    /// Cook-Torrance's Fresnel F (Schlick), summed over the lights.
    F,
    /// The radiance the diffuse lobe reflects.
    Diffuse,
    /// The radiance the specular lobe reflects.
    Specular,
}

impl View {
    /// Every view, in the order of the shaders' ids (shading.glsl's `VIEW_*`).
    pub const ALL: [View; 9] = [
        View::Radiance,
        View::Normal,
        View::NDotL,
        View::Brdf,
        View::D,
        View::G,
        View::F,
        View::Diffuse,
        View::Specular,
    ];

    /// The name of the view in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            View::Radiance => "radiance",
            View::Normal => "normal",
            View::NDotL => "n-dot-l",
            View::Brdf => "brdf",
            View::D => "d",
            View::G => "g",
            View::F => "f",
            View::Diffuse => "diffuse",
            View::Specular => "specular",
        }
    }

    /// The view's id in the shaders.
    pub fn id(self) -> u32 {
        View::ALL.iter().position(|&v| v == self).unwrap_or(0) as u32
    }

    /// A radiance (the render or a lobe's share of it): it goes through the scene's output transform.
    pub fn is_radiance(self) -> bool {
        matches!(self, View::Radiance | View::Diffuse | View::Specular)
    }

    /// One of Cook-Torrance's D, G, F: other models have no such term.
    pub fn is_microfacet_term(self) -> bool {
        matches!(self, View::D | View::G | View::F)
    }
}

/// How the shadow maps are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowFilter {
    /// One lookup: a hard edge, as the course's ray tracer.
    Hard,
    /// 3 x 3 lookups a texel apart, averaged: a soft edge one or two texels wide.
    Pcf,
}

/// The tone curve applied after exposure and before the clamp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tonemap {
    /// Nothing before the clamp (the course).
    Clamp,
    /// c / (1 + c).
    Reinhard,
    /// Narkowicz's 2015 fit of the ACES filmic curve.
    Aces,
}

/// How a [0, 1] value becomes an 8-bit one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// x255, truncated, no gamma (the course).
    Linear,
    /// The sRGB transfer function, x255, rounded.
    Srgb,
}

/// `[camera]`: a right-handed look-at camera (world +x on the image's left when looking along +z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye, in world space.
    pub position: Vec3,
    /// The point seen at the image's centre, in world space.
    pub look_at: Vec3,
    /// Which way is up: the image's vertical is its part across the view direction (any length, not parallel to it).
    pub up: Vec3,
    /// Vertical field of view, in degrees.
    pub fov_y: f32,
}

impl Camera {
    /// World to camera: glam's right-handed look-at, whose image-right axis is normalize(cross(forward, up)),
    /// the same as the course's u = normalize(cross(up, w)) with w = normalize(position - look_at).
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.position, self.look_at, self.up)
    }
}

/// One `[[light]]` of type "point".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// Linear RGB, each component at least 0 (default white).
    pub color: Vec3,
    /// Incident radiance at distance d is color * power / d^2.
    pub power: f32,
    /// Whether it casts shadows (each such light has a shadow cube; default true).
    pub shadows: bool,
}

/// One `[[object]]` with its material resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Its geometry, in world space.
    pub shape: Shape,
    /// The `[material.NAME]` it uses, kept for messages.
    pub material: String,
    /// The material's BRDF: the object's own copy of `Scene::materials[material]`.
    pub brdf: Brdf,
    /// Whether it is drawn into the shadow cubes: every object of a scene file is; what a command adds to
    /// look at (the preview's lobe) is not.
    pub casts_shadow: bool,
}

/// An object's geometry.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere, shaded from outside.
    Sphere {
        /// World-space centre.
        center: Vec3,
        /// Radius in world units, greater than 0.
        radius: f32,
    },
    /// An infinite plane through `point`; `normal` is unit length.
    Plane {
        /// A point on the plane, in world space.
        point: Vec3,
        /// The file's normal, normalized; the plane is shaded on whichever side the camera sees.
        normal: Vec3,
    },
    /// An OBJ file, placed by scale, then rotations about x, y, z (degrees), then translation.
    Mesh {
        /// The OBJ file: relative to the scene's folder, or [`BUNNY_PATH`] for `"bunny"`.
        path: PathBuf,
        /// Uniform scale, greater than 0 (default 1).
        scale: f32,
        /// Rotations about x, y and z in degrees (default 0).
        rotate: Vec3,
        /// Translation in world units (default 0).
        translate: Vec3,
    },
    /// Triangles a command makes rather than a file (the 3D lobe plot's lobe, arrows and disc).
    Triangles(std::sync::Arc<Triangles>),
}

/// Triangles in world space, each vertex with its normal, three indices a triangle, wound counter-clockwise
/// seen from the side the normals face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triangles {
    /// World-space vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Three indices into `positions` a triangle.
    pub indices: Vec<u32>,
}

impl Shape {
    /// What the object is, in a word, for messages and titles.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Plane { .. } => "plane",
            Shape::Mesh { .. } | Shape::Triangles(_) => "mesh",
        }
    }

    /// Object to world for a mesh: translate * Rz * Ry * Rx * scale, so x turns first.
    pub fn mesh_transform(scale: f32, rotate: Vec3, translate: Vec3) -> Mat4 {
        let r = rotate * (std::f32::consts::PI / 180.0);
        Mat4::from_translation(translate)
            * Mat4::from_rotation_z(r.z)
            * Mat4::from_rotation_y(r.y)
            * Mat4::from_rotation_x(r.x)
            * Mat4::from_scale(Vec3::splat(scale))
    }
}

impl Scene {
    /// How the image integrates the environment: its mode, or `None` for a scene without one and for a term
    /// view other than the lobes' (those show the point lights' terms alone).
    pub fn environment_light(&self) -> Option<EnvironmentMode> {
        self.environment.as_ref().map(|e| e.mode).filter(|_| self.image.view.is_radiance())
    }

    /// Reads, overrides and validates a scene file.
    ///
    /// # Errors
    /// `Error::Scene` naming the file, the key and the value for anything the format does not allow:
    /// an unreadable file, a TOML syntax error (with its line), an unknown key, a wrong type, a value out of
    /// range, an undefined material or an unknown brdf; an override whose path the format does not have.
    pub fn load(path: &Path, overrides: &[Override]) -> Result<Scene> {
        let text = crate::files::read_regular_text(path, "scene file", crate::files::MAX_SCENE_BYTES)
            .map_err(|message| Error::Scene { file: path.to_path_buf(), message })?;
        Self::parse(&text, path, overrides)
    }

    /// What is legal but probably not meant, one line each naming the file: no object (the image is the
    /// background alone), no light (every object is black), what an analytic model's file holds that is not
    /// used (each file once).
    pub fn warnings(&self) -> Vec<String> {
        let file = self.source.display();
        let mut warnings = Vec::new();
        let mut files: Vec<&std::path::Path> = Vec::new();
        for brdf in self.materials.values() {
            if let Brdf::Analytic(material) = brdf {
                let model = material.model();
                if !files.contains(&model.path.as_path()) {
                    files.push(&model.path);
                    warnings.extend(model.warnings.iter().cloned());
                }
            }
        }
        if self.objects.is_empty() {
            warnings.push(format!("{file}: the scene has no [[object]]: the image is its background alone"));
        }
        if self.lights.is_empty() && !self.objects.is_empty() && self.environment.is_none() {
            warnings.push(format!("{file}: the scene has no [[light]]: every object is black"));
        }
        let view = self.image.view;
        if view.is_microfacet_term() {
            let others: Vec<String> = self
                .objects
                .iter()
                .enumerate()
                .filter(|(_, o)| !matches!(o.brdf, Brdf::CookTorrance { .. }))
                .map(|(i, o)| match &o.brdf {
                    Brdf::Analytic(material) => {
                        format!("object.{i} ({}: a .brdf file has no separable terms)", material.model().name())
                    }
                    brdf => format!("object.{i} ({})", brdf.name()),
                })
                .collect();
            if !others.is_empty() {
                warnings.push(format!(
                    "{file}: image.view = \"{}\": {} not Cook-Torrance: black in this view",
                    view.name(),
                    others.join(", ")
                ));
            }
        }
        let analytic: Vec<(usize, String)> = self
            .objects
            .iter()
            .enumerate()
            .filter_map(|(i, o)| match &o.brdf {
                Brdf::Analytic(material) => Some((i, material.model().name())),
                _ => None,
            })
            .collect();
        if matches!(view, View::Diffuse | View::Specular) && !analytic.is_empty() {
            let named: Vec<String> = analytic.iter().map(|(i, name)| format!("object.{i} ({name})")).collect();
            warnings.push(format!(
                "{file}: image.view = \"{}\": {} not split into lobes (a .brdf file is one function): whole in the \
                 diffuse view, black in the specular one",
                view.name(),
                named.join(", ")
            ));
        }
        // A file with its own sampler (an isFunc section) is drawn from it in the exact mode.
        let unsampled = self.objects.iter().enumerate().find_map(|(i, o)| match &o.brdf {
            Brdf::Analytic(material) if !material.model().has_sampler() => Some((i, material.model().name())),
            _ => None,
        });
        let warned = match self.environment_light() {
            Some(EnvironmentMode::Exact) => unsampled.map(|object| {
                (
                    object,
                    "the exact mode draws its directions by the cosine and the environment alone (the file has no \
                     isFunc section, its importance sampler), which converges more slowly than a model's lobe",
                )
            }),
            Some(EnvironmentMode::Fast) => analytic.first().cloned().map(|object| {
                (
                    object,
                    "the fast mode lights it as a diffuse surface of its directional albedo: its highlights are lost",
                )
            }),
            None => None,
        };
        if let Some(((i, name), how)) = warned {
            warnings.push(format!("{file}: object.{i} ({name}) under the environment: {how}"));
        }
        if !view.is_radiance() && view != View::Normal && self.lights.len() > 1 {
            warnings.push(format!(
                "{file}: image.view = \"{}\": each pixel sums the term over the scene's {} lights",
                view.name(),
                self.lights.len()
            ));
        }
        warnings
    }

    /// Parses scene text as if read from `path` (used for messages and relative mesh paths).
    ///
    /// # Errors
    /// As [`Scene::load`].
    pub fn parse(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene> {
        let (raw, _) = overridden_file(text, path, overrides)?;
        validate::validate(raw, path).map_err(|message| Error::Scene { file: path.to_path_buf(), message })
    }
}

/// The scene file's sections with `overrides` applied, and the document they were applied to (`None`
/// without overrides: the text itself is the document).
fn overridden_file(text: &str, path: &Path, overrides: &[Override]) -> Result<(file::SceneFile, Option<toml::Table>)> {
    let scene_error = |message: String| Error::Scene { file: path.to_path_buf(), message };
    // Deserializing the text itself keeps toml's spans, so syntax errors, unknown keys and wrong types are
    // reported with their line and the offending source line.
    let raw: file::SceneFile = toml::from_str(text).map_err(|e| scene_error(toml_error(&e, text)))?;
    if overrides.is_empty() {
        return Ok((raw, None));
    }
    let mut table: toml::Table = toml::from_str(text).map_err(|e| scene_error(toml_error(&e, text)))?;
    let raw = overrides::apply(&mut table, overrides).map_err(scene_error)?;
    Ok((raw, Some(table)))
}

/// The scene of `text` with `overrides`, as [`Scene::parse`] makes it, and its text with the overrides
/// written into it, as a TOML document: what `--set` makes of the file, for tools that keep a scene as text
/// (the Python package's `Scene.with_set` and `Scene.to_toml`). The file's comments and layout are not kept.
///
/// # Errors
/// As [`Scene::parse`].
pub fn overridden(text: &str, path: &Path, overrides: &[Override]) -> Result<(Scene, String)> {
    let scene_error = |message: String| Error::Scene { file: path.to_path_buf(), message };
    let (raw, table) = overridden_file(text, path, overrides)?;
    let scene = validate::validate(raw, path).map_err(scene_error)?;
    let table = match table {
        Some(table) => table,
        None => toml::from_str(text).map_err(|e| scene_error(toml_error(&e, text)))?,
    };
    Ok((scene, toml::to_string(&table).map_err(|e| scene_error(e.to_string()))?))
}

/// A TOML error of the scene `text` in one line: `line L, column C: KEY = VALUE: what is wrong`, the key
/// as a dotted path (`object.0.center`), the value as written (cut at 40 characters), and the toml crate's
/// words for types put in the scene format's (a number, a whole number).
fn toml_error(error: &toml::de::Error, text: &str) -> String {
    let what = error
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
        .replace("expected f32", "expected a number")
        .replace("expected f64", "expected a number")
        .replace("expected i64", "expected a whole number")
        .replace("expected u32", "expected a whole number")
        .replace("floating point", "the number")
        .replace("invalid type: integer", "invalid type: the whole number");
    let Some(span) = error.span() else { return what };
    let start = span.start.min(text.len());
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let line = text[..start].matches('\n').count() + 1;
    let column = text[line_start..start].chars().count() + 1;
    let line_text = text[line_start..].lines().next().unwrap_or("");
    let position = format!("line {line}, column {column}");
    match line_text.split_once('=') {
        Some((key, value)) if !key.trim().starts_with('[') => {
            let key = key.trim().trim_matches('"');
            let path = match table_path(&text[..line_start]) {
                Some(table) => format!("{table}.{key}"),
                None => key.to_string(),
            };
            format!("{position}: {path} = {}: {what}", overrides::shortened(value.trim()))
        }
        _ => format!("{position}: {}: {what}", overrides::shortened(line_text.trim())),
    }
}

/// The dotted path of the table that the end of `before` is in: `camera`, `material.gold`, or `object.2`
/// for the third `[[object]]`.
fn table_path(before: &str) -> Option<String> {
    let mut counts: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    let mut current = None;
    for line in before.lines().map(str::trim) {
        if let Some(name) = line.strip_prefix("[[").and_then(|l| l.split_once("]]")).map(|(n, _)| n.trim()) {
            let count = counts.entry(name).or_insert(0);
            current = Some(format!("{name}.{count}"));
            *count += 1;
        } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.split_once(']')).map(|(n, _)| n.trim()) {
            current = Some(name.to_string());
        }
    }
    current
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, overrides: &[&str]) -> Result<Scene> {
        let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
        Scene::parse(text, Path::new("/scenes/test.toml"), &overrides)
    }

    fn error(text: &str, overrides: &[&str]) -> String {
        parse(text, overrides).unwrap_err().to_string()
    }

    const MINIMAL: &str = "[material.m]\nbrdf = \"lambert\"\nkd = 0.25\n\
                           [[object]]\nshape = \"sphere\"\ncenter = [0, 0, 3]\nradius = 1\nmaterial = \"m\"\n";

    #[test]
    fn a_view_is_named_and_a_microfacet_term_needs_cook_torrance() {
        let unknown = error(MINIMAL, &["image.view=\"depth\""]);
        assert!(unknown.contains("image.view = \"depth\": unknown view (expected one of \"radiance\""), "{unknown}");
        let no_term = error(MINIMAL, &["image.view=\"d\""]);
        assert!(no_term.contains("no object is Cook-Torrance, the only model with a microfacet D term"), "{no_term}");
        let gold = "[material.gold]\nbrdf = \"cook-torrance\"\nkd = 1\nf0 = 1\nroughness = 0.3\n\
                    [[object]]\nshape = \"sphere\"\ncenter = [0, 0, 3]\nradius = 1\nmaterial = \"gold\"\n";
        let scene = parse(&format!("{MINIMAL}{gold}[[light]]\nposition = [0, 0, 0]\n"), &["image.view=\"g\""]).unwrap();
        assert_eq!(scene.image.view, View::G);
        let warnings = scene.warnings();
        assert!(
            warnings.iter().any(|w| w.contains("object.0 (lambert) not Cook-Torrance: black in this view")),
            "{warnings:?}"
        );
    }

    #[test]
    fn an_environment_takes_its_defaults_and_a_map_path_relative_to_the_scene() {
        let scene = parse(&format!("{MINIMAL}[environment]\nmap = \"maps/sky.hdr\"\n"), &[]).unwrap();
        assert_eq!(
            scene.environment,
            Some(Environment {
                source: EnvironmentSource::Map(PathBuf::from("/scenes/maps/sky.hdr")),
                intensity: 1.0,
                rotation: 0.0,
                visible: true,
                mode: EnvironmentMode::Exact,
            })
        );
        // No light but an environment: the objects are lit, nothing to warn about.
        assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
        let sky = parse(MINIMAL, &["environment.builtin=\"sky\"", "environment.mode=\"fast\""]).unwrap();
        let environment = sky.environment.unwrap();
        assert_eq!(environment.source, EnvironmentSource::Builtin(BuiltinEnvironment::Sky));
        assert_eq!(environment.mode, EnvironmentMode::Fast);
    }

    #[test]
    fn defaults_follow_the_format() {
        let scene = parse("", &[]).unwrap();
        assert_eq!(
            scene.image,
            ImageSettings {
                width: 600,
                height: 400,
                samples: 4,
                background: Vec3::splat(0.5),
                tonemap: Tonemap::Clamp,
                exposure: 1.0,
                encoding: Encoding::Linear,
                shadow_map_size: 1024,
                shadow_filter: ShadowFilter::Hard,
                view: View::Radiance,
            }
        );
        assert_eq!(scene.camera, Camera { position: Vec3::ZERO, look_at: Vec3::Z, up: Vec3::Y, fov_y: 60.0 });
        let light = parse("[[light]]\nposition = [1, 2, 3]\n", &[]).unwrap().lights[0];
        assert_eq!(
            light,
            PointLight { position: Vec3::new(1.0, 2.0, 3.0), color: Vec3::ONE, power: 1.0, shadows: true }
        );
    }

    #[test]
    fn a_single_number_is_a_grey_and_integers_are_numbers() {
        let scene = parse(MINIMAL, &[]).unwrap();
        assert_eq!(scene.objects[0].brdf, Brdf::Lambert { kd: Vec3::splat(0.25) });
        assert_eq!(scene.objects[0].shape, Shape::Sphere { center: Vec3::new(0.0, 0.0, 3.0), radius: 1.0 });
    }

    #[test]
    fn every_brdf_parses_with_its_parameters() {
        let text = "[material.a]\nbrdf = \"oren-nayar\"\nkd = 0.5\nsigma = 0.6\n\
                    [material.b]\nbrdf = \"phong\"\nkd = 0.35\nks = 0.15\nshininess = 16\n\
                    [material.c]\nbrdf = \"blinn-phong\"\nkd = 0.35\nks = 0.15\nshininess = 64\n\
                    [material.d]\nbrdf = \"cook-torrance\"\nkd = [1, 0.85, 0.57]\nf0 = [1, 0.85, 0.57]\nroughness = 0.3\n\
                    [[object]]\nshape = \"plane\"\npoint = [0, -2, 0]\nnormal = [0, 2, 0]\nmaterial = \"a\"\n\
                    [[object]]\nshape = \"plane\"\npoint = [0, -2, 0]\nnormal = [0, 1, 0]\nmaterial = \"b\"\n\
                    [[object]]\nshape = \"plane\"\npoint = [0, -2, 0]\nnormal = [0, 1, 0]\nmaterial = \"c\"\n\
                    [[object]]\nshape = \"mesh\"\npath = \"bunny\"\nmaterial = \"d\"\n";
        let scene = parse(text, &[]).unwrap();
        let brdfs: Vec<Brdf> = scene.objects.iter().map(|o| o.brdf.clone()).collect();
        let (half, gold) = (Vec3::splat(0.5), Vec3::new(1.0, 0.85, 0.57));
        assert_eq!(brdfs[0], Brdf::OrenNayar { kd: half, sigma: 0.6 });
        assert_eq!(brdfs[1], Brdf::Phong { kd: Vec3::splat(0.35), ks: Vec3::splat(0.15), shininess: 16.0 });
        assert_eq!(brdfs[2], Brdf::BlinnPhong { kd: Vec3::splat(0.35), ks: Vec3::splat(0.15), shininess: 64.0 });
        // metalness defaults to 0 and the diffuse lobe to Oren-Nayar, as in the course.
        assert_eq!(
            brdfs[3],
            Brdf::CookTorrance {
                kd: gold,
                f0: gold,
                roughness: 0.3,
                metalness: 0.0,
                diffuse: crate::brdf::DiffuseModel::OrenNayar
            }
        );
        assert_eq!(scene.objects[0].shape, Shape::Plane { point: Vec3::new(0.0, -2.0, 0.0), normal: Vec3::Y });
        assert_eq!(
            scene.objects[3].shape,
            Shape::Mesh { path: BUNNY_PATH.into(), scale: 1.0, rotate: Vec3::ZERO, translate: Vec3::ZERO }
        );
    }

    #[test]
    fn mesh_paths_are_relative_to_the_scene_file() {
        let text = MINIMAL.replace(
            "shape = \"sphere\"\ncenter = [0, 0, 3]\nradius = 1",
            "shape = \"mesh\"\npath = \"models/cube.obj\"",
        );
        let scene = parse(&text, &[]).unwrap();
        assert!(
            matches!(&scene.objects[0].shape, Shape::Mesh { path, .. } if path == Path::new("/scenes/models/cube.obj"))
        );
    }

    #[test]
    fn overrides_reach_every_kind_of_key() {
        let text = format!("{MINIMAL}[[light]]\nposition = [0, 0, -2]\npower = 60\n");
        let scene = parse(
            &text,
            &[
                "image.width=1200",
                "camera.fov_y=45",
                "light.0.power=30",
                "material.m.brdf=oren-nayar",
                "material.m.sigma=0.4",
                "object.0.radius=2",
            ],
        )
        .unwrap();
        assert_eq!(scene.image.width, 1200);
        assert_eq!(scene.camera.fov_y, 45.0);
        assert_eq!(scene.lights[0].power, 30.0);
        assert_eq!(scene.objects[0].brdf, Brdf::OrenNayar { kd: Vec3::splat(0.25), sigma: 0.4 });
        assert!(matches!(scene.objects[0].shape, Shape::Sphere { radius, .. } if radius == 2.0));
    }

    #[test]
    fn a_table_override_merges_key_by_key() {
        let scene = parse(MINIMAL, &["image={width=8}", "image.height=64"]).unwrap();
        assert_eq!((scene.image.width, scene.image.height), (8, 64));
        let scene = parse(MINIMAL, &["image.height=64", "image={width=8}"]).unwrap();
        assert_eq!((scene.image.width, scene.image.height), (8, 64), "the table dropped the height set before");
    }

    #[test]
    fn bad_overrides_name_themselves() {
        assert!(error(MINIMAL, &["image.widht=3"]).contains("--set image.widht=3: unknown field `widht`"));
        assert!(error(MINIMAL, &["object.0.radius=-1"]).contains("object.0.radius = -1"));
        assert!(error(MINIMAL, &["object.x.radius=1"]).contains("not an index"));
        assert!(error(&format!("[image]\nwidth = 300\n{MINIMAL}"), &["image.width.x=1"])
            .contains("is a value, not a table"));
        assert!(error(MINIMAL, &["light.0.power=1"]).contains("no `light`"));
        assert!("nokey".parse::<Override>().is_err());
        // One value for one key: no second assignment smuggled in after a newline.
        let two = "image.width=8\nimage.height = 9".parse::<Override>().unwrap_err();
        assert!(two.contains("--set image.width") && two.contains("more than one value"), "{two}");
        assert!("object.0.path=a\nb c".parse::<Override>().unwrap_err().contains("not one TOML value"));
        assert_eq!("object.0.path=my mesh.obj".parse::<Override>().unwrap().value, toml::Value::from("my mesh.obj"));
        assert!("a..b=1".parse::<Override>().is_err());
    }

    #[test]
    fn ranges_are_enforced() {
        let with = |from: &str, to: &str| error(&MINIMAL.replace(from, to), &[]);
        assert!(with("kd = 0.25", "kd = -0.1").contains("material.m.kd = [-0.1, -0.1, -0.1]"));
        assert!(with("kd = 0.25", "kd = [0.1, 0.2]").contains("invalid length 2"));
        assert!(with("radius = 1", "radius = 0").contains("object.0.radius = 0"));
        assert!(with("brdf = \"lambert\"", "brdf = \"cook-torrance\"\nf0 = 0.5\nroughness = 0")
            .contains("roughness = 0: must be in (0, 1]"));
        assert!(with("brdf = \"lambert\"", "brdf = \"cook-torrance\"\nf0 = 0.5\nroughness = 0.5\nmetalness = 2")
            .contains("metalness = 2"));
        assert!(with("brdf = \"lambert\"", "brdf = \"phong\"\nks = 0.5\nshininess = -1").contains("shininess = -1"));
        assert!(with("brdf = \"lambert\"", "brdf = \"oren-nayar\"").contains("material.m.sigma: missing"));
        assert!(with("brdf = \"lambert\"", "brdf = \"oren-nayar\"\nsigma = -0.5").contains("sigma = -0.5"));
        assert!(with("shape = \"sphere\"", "shape = \"cube\"").contains("object.0.shape = \"cube\""));
        assert!(with("radius = 1\n", "").contains("object.0.radius: missing"));
        assert!(
            with("radius = 1\n", "radius = 1\npoint = [0, 0, 0]\n").contains("object.0.point: not a key of a sphere")
        );
        assert!(error("[image]\ntonemap = \"filmic\"", &[]).contains("image.tonemap = \"filmic\""));
        assert!(error("[image]\nencoding = \"gamma\"", &[]).contains("image.encoding = \"gamma\""));
        assert!(error("[image]\nsamples = 3", &[]).contains("image.samples = 3"));
        assert!(error("[image]\nwidth = -5", &[]).contains("image.width = -5"));
        assert!(error("[camera]\nup = [0, 0, 1]", &[]).contains("camera.up = [0.0, 0.0, 1.0]: parallel"));
        assert!(error("[camera]\nfov_y = 180", &[]).contains("camera.fov_y = 180"));
        assert!(error("[[light]]\nposition = [0, 0, 0]\npower = -1", &[]).contains("light.0.power = -1"));
        assert!(error("[[light]]\ntype = \"spot\"\nposition = [0, 0, 0]", &[]).contains("light.0.type = \"spot\""));
        assert!(error("[[light]]\npower = 1", &[]).contains("missing field `position`"));
        assert!(error("[image]\nshadow_map_size = 8", &[]).contains("image.shadow_map_size = 8"));
        assert!(error("[image]\nshadow_filter = \"soft\"", &[]).contains("image.shadow_filter = \"soft\""));
        let seventeen_lights = "[[light]]\nposition = [0, 1, 0]\n".repeat(MAX_LIGHTS + 1);
        assert!(error(&seventeen_lights, &[]).contains("light.16: the scene has 17 lights"));
        assert_eq!(
            parse(&"[[light]]\nposition = [0, 1, 0]\n".repeat(MAX_LIGHTS), &[]).unwrap().lights.len(),
            MAX_LIGHTS
        );
    }

    #[test]
    fn toml_errors_are_one_line_with_the_dotted_key() {
        let text = "[image]\nwidth = 1.5\n[[object]]\nshape = \"sphere\"\n[[object]]\ncenter = 3\n";
        let message = error(text, &[]);
        assert!(
            message.contains("line 2, column 9: image.width = 1.5") && message.contains("a whole number"),
            "{message}"
        );
        let object = "shape = \"sphere\"\nradius = 1.0\nmaterial = \"m\"\n";
        let text = format!("[[object]]\n{object}center = [0, 0, 3]\n[[object]]\n{object}center = 3\n");
        let text = text.as_str();
        let message = error(text, &[]);
        assert!(message.contains("object.1.center = 3") && message.contains("three numbers"), "{message}");
        let message = error("[camera]\nfov_y = = 3\n", &[]);
        assert!(message.contains("line 2") && !message.contains('\n'), "{message}");
    }

    #[test]
    fn thousands_of_mutated_scenes_give_one_line_or_a_scene() {
        // A fixed-seed generator mutates Figure 1's file (characters replaced, removed, repeated, lines
        // swapped): parsing never panics, and every error is one line naming the file.
        let base = include_str!("../../assets/scenes/fig1-lambert.toml");
        let alphabet: Vec<char> = "[]{}=\",.-+0123456789eE#\n abcdefghijklmnopqrstuvwxyz_\\'".chars().collect();
        let mut state = 0x2545_f491_u64;
        let mut next = move |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let path = Path::new("mutated.toml");
        let (mut parsed, mut refused) = (0, 0);
        for _ in 0..3000 {
            let mut chars: Vec<char> = base.chars().collect();
            for _ in 0..1 + next(4) {
                let at = next(chars.len());
                match next(4) {
                    0 => chars[at] = alphabet[next(alphabet.len())],
                    1 => {
                        chars.remove(at);
                    }
                    2 => chars.insert(at, alphabet[next(alphabet.len())]),
                    _ => {
                        let c = chars[at];
                        chars.splice(at..at, std::iter::repeat_n(c, 1 + next(30)));
                    }
                }
            }
            let text: String = chars.into_iter().collect();
            match Scene::parse(&text, path, &[]) {
                Ok(_) => parsed += 1,
                Err(e) => {
                    let message = e.to_string();
                    assert!(!message.contains('\n') && message.starts_with("mutated.toml: "), "{message:?}\n{text}");
                    refused += 1;
                }
            }
        }
        assert!(parsed > 100 && refused > 1000, "{parsed} parsed, {refused} refused");
    }
}
