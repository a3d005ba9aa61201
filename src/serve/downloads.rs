//! The files the explore page fetches to render a scene in the visitor's browser (src/serve/browser.rs makes
//! them): the translated shaders and the editor's templates, and each catalogue scene's meshes, measured
//! tables, `.brdf` models' shaders and environment, each made once (src/serve/cache.rs) and kept.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;

use vk_render::brdf::Brdf;

use super::app::App;
use super::browser::{analytic_file, environment_file, measured_file, mesh_file, shaders_file, templates_file};
use super::catalogue::Entry;
use super::error::ApiError;

/// `GET /static/shaders.json`: every translated shader by its entry file's name, one JSON object.
pub async fn shaders() -> Response {
    json_file(shaders_file())
}

/// `GET /static/brdf-templates.json`: the analytic templates of the editor, by entry, one JSON object (fetched
/// when a student's model is first compiled: most visits never need it).
pub async fn templates() -> Response {
    json_file(templates_file())
}

fn json_file(text: &'static str) -> Response {
    ([(header::CONTENT_TYPE, "application/json"), (header::CACHE_CONTROL, "no-cache")], text).into_response()
}

fn binary(bytes: Bytes) -> Response {
    ([(header::CONTENT_TYPE, "application/octet-stream"), (header::CACHE_CONTROL, "max-age=3600")], bytes)
        .into_response()
}

fn no_scene(id: &str) -> ApiError {
    ApiError::new(StatusCode::NOT_FOUND, format!("scene {}: no such scene", vk_render::files::shortened(id)))
}

/// The 404 of a request for a `kind` material (measured, analytic) that `entry`'s scene has not by that name.
fn no_material(entry: &Entry, name: &str, kind: &str) -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        format!("scene {}: material {}: no {kind} material of that name", entry.id, vk_render::files::shortened(name)),
    )
}

#[derive(Deserialize)]
pub struct MeshQuery {
    scene: String,
    object: usize,
    /// The lighter mesh of the motion frames, where the object has one (its `motion_mesh`).
    #[serde(default)]
    motion: bool,
}

/// `GET /api/mesh?scene=ID&object=N`: the vertices and triangles the renderer draws for that object (a
/// sphere's bounding mesh, the plane's fan to infinity, an OBJ's mesh), little-endian: the vertex count and
/// the index count (u32 each), then each vertex's position (4 floats, homogeneous), normal (3) and tangent
/// (3), then the indices (u32). With `motion=true`, the lighter mesh of its motion frames (404 where it has
/// none).
pub async fn mesh(State(app): State<Arc<App>>, Query(query): Query<MeshQuery>) -> Result<Response, ApiError> {
    let entry = app.catalogue.get(&query.scene).ok_or_else(|| no_scene(&query.scene))?;
    let object = query.object;
    if object >= entry.scene.objects.len() {
        return Err(ApiError::new(
            StatusCode::NOT_FOUND,
            format!("scene {}: object {object}: no such object", entry.id),
        ));
    }
    let scene = entry.scene.clone();
    let (id, motion) = (entry.id.clone(), query.motion);
    let key = format!("mesh {} {object} {motion}", entry.id);
    let bytes = app.browser_files.get(key, move || mesh_file(&id, &scene, object, motion)).await?;
    Ok(binary(bytes))
}

#[derive(Deserialize)]
pub struct TableQuery {
    scene: String,
    material: String,
}

/// `GET /api/measured?scene=ID&material=NAME`: a measured material's table as the renderer holds it (f_r of
/// every entry, red, green and blue interleaved, in the MERL file's order; float32, little-endian), which the
/// page uploads as a float texture (shaders/brdf/measured.glsl, `measured_texel`).
pub async fn measured(State(app): State<Arc<App>>, Query(query): Query<TableQuery>) -> Result<Response, ApiError> {
    let entry = app.catalogue.get(&query.scene).ok_or_else(|| no_scene(&query.scene))?;
    let Some(Brdf::Measured(table)) = entry.scene.materials.get(&query.material).cloned() else {
        return Err(no_material(entry, &query.material, "measured"));
    };
    let key = format!("measured {} {}", entry.id, query.material);
    let bytes = app.browser_files.get(key, move || Ok(measured_file(&table))).await?;
    Ok(binary(bytes))
}

/// `GET /api/analytic?scene=ID&material=NAME`: an analytic material's browser shaders (the forward passes'
/// entries and variants with its model: vk_render::render::webgl::analytic_shaders), one JSON object by entry name,
/// translated once per model and kept; the page compiles them as it does /static/shaders.json's.
pub async fn analytic(State(app): State<Arc<App>>, Query(query): Query<TableQuery>) -> Result<Response, ApiError> {
    let entry = app.catalogue.get(&query.scene).ok_or_else(|| no_scene(&query.scene))?;
    let Some(Brdf::Analytic(material)) = entry.scene.materials.get(&query.material) else {
        return Err(no_material(entry, &query.material, "analytic"));
    };
    let model = material.model().clone();
    let key = format!("analytic {:016x}", model.key());
    let bytes = app.browser_files.get(key, move || analytic_file(&model)).await?;
    Ok(([(header::CONTENT_TYPE, "application/json"), (header::CACHE_CONTROL, "max-age=3600")], bytes).into_response())
}

#[derive(Deserialize)]
pub struct SceneQuery {
    scene: String,
}

/// `GET /api/environment?scene=ID`: the scene's environment as the renderer uploads it, little-endian: the
/// map's width and height, the prefiltered layers' width, height and count (u32 each), then the map's texels
/// and the layers' (RGB float32 each, rows from the top; src/environment/prefilter.rs), which the page uploads
/// as float textures (common/environment_map.glsl, common/environment.glsl). Made once per scene.
pub async fn environment(State(app): State<Arc<App>>, Query(query): Query<SceneQuery>) -> Result<Response, ApiError> {
    let entry = app.catalogue.get(&query.scene).ok_or_else(|| no_scene(&query.scene))?;
    let Some(environment) = entry.scene.environment.clone() else {
        return Err(ApiError::new(StatusCode::NOT_FOUND, format!("scene {}: it has no environment", entry.id)));
    };
    let scene = entry.scene.clone();
    let key = format!("environment {}", entry.id);
    let bytes = app.browser_files.get(key, move || environment_file(&scene, &environment)).await?;
    Ok(binary(bytes))
}
