//! What the explore page needs to render a scene in the visitor's browser (WebGL2) instead of on the
//! server: the renderer's own shaders translated at build time (build.rs: glslc with WEBGL defined, then
//! SPIRV-Cross to GLSL ES 3.00, checked by glslangValidator), each catalogue scene's data as the renderer
//! uploads it (its objects' matrices and flags, its materials, its lights, and the frame and shadow views of
//! the scene as its file says, against which the page's own are checked), and its meshes' vertices. The page
//! computes what its controls change (the camera's matrices, the lights, the materials' parameters) and
//! draws; the server only hands out these files.

use std::collections::BTreeMap;
use std::sync::LazyLock;

use axum::http::StatusCode;
use serde::Serialize;
use serde_json::{json, Value as Json};

use vk_render::brdf::Brdf;
use vk_render::environment::prefilter::{prefiltered_layers, LAYERS, LAYER_WIDTH};
use vk_render::environment::EnvironmentMap;
use vk_render::mesh::motion::{has_motion_mesh, motion_mesh};
use vk_render::mesh::Mesh;
use vk_render::render::gpu_types::{GpuFrame, GpuMaterial, GpuObject};
use vk_render::render::{cube_face_views, NEAR_PLANE};
use vk_render::scene::{Encoding, EnvironmentMode, Tonemap};
use vk_render::Scene;

use super::catalogue::Entry;
use super::error::ApiError;

/// The browser's shaders: (entry file under shaders/, its GLSL ES 3.00), made by build.rs.
const SHADERS: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/webgl.rs"));

/// Every translated shader by its entry file's name, one JSON object, as `GET /static/shaders.json` hands it out.
pub fn shaders_file() -> &'static str {
    static TEXT: LazyLock<String> = LazyLock::new(|| table_json(SHADERS));
    TEXT.as_str()
}

/// The analytic templates by entry, as `GET /static/brdf-templates.json` hands them out.
pub fn templates_file() -> &'static str {
    static TEXT: LazyLock<String> = LazyLock::new(|| table_json(vk_render::render::webgl::ANALYTIC_TEMPLATES));
    TEXT.as_str()
}

fn table_json(table: &[(&str, &str)]) -> String {
    let table: BTreeMap<&str, &str> = table.iter().copied().collect();
    serde_json::to_string(&table).unwrap_or_default()
}

/// A scene as the browser draws it (`GET /api/scenes`, each scene's `browser`).
#[derive(Serialize)]
pub struct BrowserScene {
    /// Why the browser cannot draw this scene (the server then renders its frames, and the page says why).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsupported: Option<String>,
    /// The factor the radiance is multiplied by before the tone curve.
    pub exposure: f32,
    /// The tone curve: shaders/common/output.glsl's TONEMAP_* (0 the course's clamp, 1 Reinhard, 2 ACES).
    pub tonemap: u32,
    /// The encoding: ENCODING_* (0 the course's linear, 1 sRGB).
    pub encoding: u32,
    /// What the image shows: views.glsl's VIEW (0 the radiance); a term is drawn by the TERM_VIEWS variants.
    pub view: u32,
    /// Whether the view is written through a term's scale (output.rs's TermScale), not the output transform.
    pub term: bool,
    /// The image's background, linear rgb and alpha 1 (the frame's `background`).
    pub background: [f32; 4],
    /// Texels on a side of each face of a light's shadow cube.
    pub shadow_map_size: u32,
    /// shading.glsl's `SHADOW_FILTER`: 0 hard, 1 PCF.
    pub shadow_filter: u32,
    /// The projection's near plane (the renderer's).
    pub near: f32,
    /// Whether each light casts shadows, in the scene's order.
    pub shadows: Vec<bool>,
    pub objects: Vec<BrowserObject>,
    /// Each material's `Material` (shaders/common/material.glsl) as the scene file sets it, by name.
    pub materials: BTreeMap<String, Json>,
    /// The frame's data for the scene as its file says it, at the file's size: the page computes its own
    /// (the camera moves) and the browser test holds them equal.
    pub frame: Json,
    /// Each light's six shadow views (view-projections, column-major), likewise.
    pub shadow_views: Vec<Vec<[f32; 16]>>,
    /// The environment's light, if the scene has one: drawn in its fast mode (its map and prefiltered layers
    /// from [`environment`], each material's albedo table from `POST /api/environment-albedo`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environment: Option<BrowserEnvironment>,
}

/// A scene's environment as the browser draws it.
#[derive(Serialize)]
pub struct BrowserEnvironment {
    /// The frame's `environment`: cos and sin of its rotation, its intensity, and 0.
    pub frame: [f32; 4],
    /// Whether the background shows it.
    pub visible: bool,
    /// Whether its light is integrated in the fast mode in `vk-render render` (else exactly: the browser's
    /// frames are then motion frames, and the still frame is the server's).
    pub fast: bool,
}

/// One object: its `ObjectData` but for the material (named), and how it is drawn.
#[derive(Serialize)]
pub struct BrowserObject {
    /// Drawn as an exact sphere (forward_sphere.frag) over its bounding mesh.
    pub sphere: bool,
    pub casts_shadow: bool,
    pub material: String,
    /// Object to world, column-major.
    pub model: [f32; 16],
    /// Its inverse transpose.
    pub normal_matrix: [f32; 16],
    /// `ObjectData.flags`.
    pub flags: [u32; 4],
    /// Whether its mesh is closed and wound outwards and its placement keeps the winding: its back faces
    /// may be culled from outside its bounding box (the renderer's `hides_back_faces`).
    pub closed: bool,
    /// Its mesh's bounding box in its own space: the least and the greatest corner.
    pub bounds: [[f32; 3]; 2],
    /// Whether a lighter mesh of it draws the motion frames (`GET /api/mesh?...&motion=true`:
    /// vk_render::mesh::motion).
    pub motion_mesh: bool,
}

/// The most analytic values a scene's materials may have together in the browser: its uniform block's
/// (ANALYTIC_VALUE_VECTORS of shaders/common/analytic.glsl, four values each).
const BROWSER_ANALYTIC_VALUES: usize = 4 * 1024;

/// What the browser cannot draw, or None: more analytic values than its block holds.
fn unsupported(scene: &Scene) -> Option<String> {
    let values: usize = scene
        .materials
        .values()
        .map(|brdf| if let Brdf::Analytic(material) = brdf { material.floats().len() } else { 0 })
        .sum();
    if values > BROWSER_ANALYTIC_VALUES {
        return Some(format!(
            "its analytic materials' {values} values (WebGL2's block holds {BROWSER_ANALYTIC_VALUES})"
        ));
    }
    None
}

fn columns(m: [[f32; 4]; 4]) -> [f32; 16] {
    let mut out = [0.0; 16];
    for (k, column) in m.iter().enumerate() {
        out[4 * k..4 * k + 4].copy_from_slice(column);
    }
    out
}

/// A material's `Material` values; a measured one's table is fetched apart ([`measured`]), and the page
/// numbers the tables it holds; an analytic one's values (`analytic_values`, as the renderer's buffer holds
/// them: `Analytic::floats`) with where each parameter's begin (`analytic_offsets`, by name), its shaders
/// fetched apart ([`analytic`]).
fn material(brdf: &Brdf) -> Json {
    let m = GpuMaterial::of_parameters(brdf);
    let mut material = json!({
        "kd": m.kd, "ks": m.ks, "f0": m.f0, "brdf": m.brdf, "shininess": m.shininess, "sigma": m.sigma,
        "roughness": m.roughness, "metalness": m.metalness, "diffuse": m.diffuse,
        "measured_table": matches!(brdf, Brdf::Measured(_)),
    });
    if let Brdf::Analytic(analytic) = brdf {
        let mut offsets = serde_json::Map::new();
        let mut offset = 0;
        for (parameter, _) in analytic.values() {
            offsets.insert(parameter.name.clone(), json!(offset));
            offset += parameter.kind.floats();
        }
        material["analytic_values"] = json!(analytic.floats());
        material["analytic_offsets"] = Json::Object(offsets);
    }
    material
}

/// The browser's data of `entry`'s scene (its meshes are fetched apart: [`mesh`]).
pub fn describe(entry: &Entry) -> BrowserScene {
    let scene = &entry.scene;
    let placed = vk_render::mesh::place_objects(scene).unwrap_or_default();
    let objects = scene
        .objects
        .iter()
        .zip(&placed)
        .map(|(object, placed)| {
            let data = GpuObject::placed(object, placed.model);
            let (min, max) = placed.mesh.bounds();
            BrowserObject {
                closed: placed.mesh.is_closed_outward() && placed.model.determinant() > 0.0,
                motion_mesh: has_motion_mesh(&placed.mesh),
                bounds: [min.to_array(), max.to_array()],
                sphere: placed.exact_sphere,
                casts_shadow: placed.casts_shadow,
                material: object.material.clone(),
                model: columns(data.model),
                normal_matrix: columns(data.normal_matrix),
                flags: data.flags,
            }
        })
        .collect();
    let frame = GpuFrame::new(&scene.camera, &scene.image, NEAR_PLANE);
    BrowserScene {
        unsupported: unsupported(scene),
        exposure: scene.image.exposure,
        tonemap: match scene.image.tonemap {
            Tonemap::Clamp => 0,
            Tonemap::Reinhard => 1,
            Tonemap::Aces => 2,
        },
        encoding: match scene.image.encoding {
            Encoding::Linear => 0,
            Encoding::Srgb => 1,
        },
        view: scene.image.view.id(),
        term: !scene.image.view.is_radiance(),
        background: frame.background,
        shadow_map_size: scene.image.shadow_map_size,
        shadow_filter: u32::from(scene.image.shadow_filter != vk_render::scene::ShadowFilter::Hard),
        near: NEAR_PLANE,
        shadows: scene.lights.iter().map(|l| l.shadows).collect(),
        objects,
        materials: scene.materials.iter().map(|(name, brdf)| (name.clone(), material(brdf))).collect(),
        frame: json!({
            "view_projection": columns(frame.view_projection),
            "pixel_rays": columns(frame.pixel_rays),
            "camera_position": frame.camera_position,
            "shadow_texel_angle": frame.shadow_texel_angle,
        }),
        shadow_views: scene
            .lights
            .iter()
            .map(|light| cube_face_views(light.position, NEAR_PLANE).iter().map(|m| m.to_cols_array()).collect())
            .collect(),
        environment: scene.environment.as_ref().map(|environment| {
            let (sin, cos) = environment.rotation.to_radians().sin_cos();
            BrowserEnvironment {
                frame: [cos, sin, environment.intensity, 0.0],
                visible: environment.visible,
                fast: environment.mode == EnvironmentMode::Fast,
            }
        }),
    }
}

/// Object `object`'s mesh of scene `id` as `GET /api/mesh` hands it out (an OBJ read from disk), or its
/// lighter mesh of the motion frames.
pub fn mesh_file(id: &str, scene: &Scene, object: usize, motion: bool) -> Result<Vec<u8>, ApiError> {
    let placed = vk_render::mesh::place_objects(scene).map_err(|e| ApiError::from_library(&e))?;
    let mesh = &placed[object].mesh;
    if !motion {
        return Ok(mesh_bytes(mesh));
    }
    let light = motion_mesh(mesh).ok_or_else(|| {
        ApiError::new(StatusCode::NOT_FOUND, format!("scene {id}: object {object}: no lighter mesh for motion"))
    })?;
    Ok(mesh_bytes(&light))
}

/// A mesh as `GET /api/mesh` hands it out.
pub fn mesh_bytes(mesh: &Mesh) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(8 + mesh.vertices.len() * 40 + mesh.indices.len() * 4);
    bytes.extend((mesh.vertices.len() as u32).to_le_bytes());
    bytes.extend((mesh.indices.len() as u32).to_le_bytes());
    for vertex in &mesh.vertices {
        for value in vertex.position.iter().chain(&vertex.normal).chain(&vertex.tangent) {
            bytes.extend(value.to_le_bytes());
        }
    }
    for index in &mesh.indices {
        bytes.extend(index.to_le_bytes());
    }
    bytes
}

/// A measured material's table as `GET /api/measured` hands it out.
pub fn measured_file(table: &vk_render::brdf::Measured) -> Vec<u8> {
    table.table().rgb.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A `.brdf` model's browser shaders as `GET /api/analytic` hands them out (a JSON object by entry name).
pub fn analytic_file(model: &vk_render::brdf::AnalyticModel) -> Result<Vec<u8>, ApiError> {
    let failed = |e: String| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, format!("{}: {e}", model.name()));
    let shaders =
        vk_render::render::webgl::analytic_shaders(model, &Default::default()).map_err(|e| failed(e.to_string()))?;
    serde_json::to_vec(&shaders).map_err(|e| failed(e.to_string()))
}

/// A scene's environment as `GET /api/environment` hands it out (a map file read from disk).
pub fn environment_file(scene: &Scene, environment: &vk_render::scene::Environment) -> Result<Vec<u8>, ApiError> {
    let map = EnvironmentMap::of(scene, environment).map_err(|e| ApiError::from_library(&e))?;
    let layers = prefiltered_layers(&map);
    let mut bytes = Vec::with_capacity(20 + 12 * (map.texels.len() + layers.len()));
    for size in [map.width, map.height, LAYER_WIDTH, LAYER_WIDTH / 2, LAYERS] {
        bytes.extend(size.to_le_bytes());
    }
    for texel in map.texels.iter().chain(&layers) {
        for value in texel.to_array() {
            bytes.extend(value.to_le_bytes());
        }
    }
    Ok(bytes)
}
