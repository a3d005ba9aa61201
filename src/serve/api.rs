//! The HTTP API under `/api/`, which the pages use and scripts call: the catalogue, renders, lobes and
//! albedos, scene files, and reports. Each handler checks what it was sent, builds the scene from the
//! catalogue by id, and hands the work to the render workers.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{Path as UrlPath, Query, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use glam::Vec3;
use serde::Deserialize;
use serde_json::{json, Map, Value as Json};

use vk_render::analysis::albedo::{albedo_angles, directional_albedos, ALBEDO_TOLERANCE};
use vk_render::analysis::lobe::{lobe_angles, lobes, LobeCut};
use vk_render::analysis::plots::{albedo_chart, albedo_table, lobe_chart, lobe_table, LobeStyle};
use vk_render::analysis::{rgb, Channel, NamedBrdf};
use vk_render::brdf::Brdf;
use vk_render::pictures::chart::chart_svg;
use vk_render::pictures::output::png_bytes;
use vk_render::scene::overridden;
use vk_render::{Renderer, Scene};

use super::app::App;
use super::catalogue::{is_id, Entry};
use super::error::ApiError;
use super::limits::overrides;
use super::workers::Lane;
use vk_render::files::shortened;

/// The largest JSON body a request other than a check may send.
pub const MAX_JSON_BYTES: usize = 64 << 10;

/// A request's body as a JSON object with only `allowed` keys.
pub fn json_object(body: &[u8], allowed: &[&str]) -> Result<Map<String, Json>, ApiError> {
    let value: Json = serde_json::from_slice(body)
        .map_err(|e| ApiError::bad_request(format!("the request's body is not JSON: {e}")))?;
    let Json::Object(object) = value else {
        return Err(ApiError::bad_request("the request's body is not a JSON object".into()));
    };
    if let Some(unknown) = object.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(ApiError::bad_request(format!(
            "`{}`: no such field (the request takes {})",
            shortened(unknown),
            allowed.join(", ")
        )));
    }
    Ok(object)
}

/// The catalogue's scene a request names by `id`: 404 for anything that is not one of its ids.
pub fn entry<'a>(app: &'a App, id: Option<&Json>) -> Result<&'a Entry, ApiError> {
    let id = match id {
        Some(Json::String(id)) => id,
        Some(other) => {
            return Err(ApiError::bad_request(format!(
                "scene = {}: expected a scene's id",
                shortened(&other.to_string())
            )))
        }
        None => return Err(ApiError::bad_request("scene: missing (a scene's id from GET /api/scenes)".into())),
    };
    let unknown =
        || ApiError::not_found(format!("scene `{}`: no such scene (GET /api/scenes lists them)", shortened(id)));
    if !is_id(id) {
        return Err(unknown());
    }
    app.catalogue.get(id).ok_or_else(unknown)
}

/// The scene of a request (`scene` and its overrides), within the server's bounds; errors name the scene by
/// its id, not by where the server keeps it.
pub fn requested_scene<'a>(app: &'a App, request: &Map<String, Json>) -> Result<(&'a Entry, Scene), ApiError> {
    let entry = entry(app, request.get("scene"))?;
    let scene = entry.scene(&overrides(request)?).map_err(|e| scene_error(entry, &e))?;
    app.limits.check_scene(&scene)?;
    Ok((entry, scene))
}

/// A library error about a catalogue scene, naming it by id.
pub fn scene_error(entry: &Entry, error: &vk_render::Error) -> ApiError {
    let mut error = ApiError::from_library(error);
    error.message = error.message.replace(&entry.scene.source.display().to_string(), &entry.id);
    error
}

const RENDER_FIELDS: [&str; 7] = ["scene", "set", "width", "height", "samples", "view", "environment_mode"];

/// `GET /api/scenes`: the catalogue.
pub async fn scenes(State(app): State<Arc<App>>) -> Response {
    ([(header::CONTENT_TYPE, "application/json")], app.described.clone()).into_response()
}

/// `POST /api/render`: the PNG `vk-render render` writes for the same scene and overrides, byte for byte.
pub async fn render(State(app): State<Arc<App>>, body: Bytes) -> Result<Response, ApiError> {
    let request = json_object(&body, &RENDER_FIELDS)?;
    let (entry, scene) = requested_scene(&app, &request)?;
    let id = entry.id.clone();
    let png = app
        .workers
        .run(Lane::Quick, move |renderer| rendered_png(renderer, &scene))
        .await
        .map_err(|e| named(e, &id))?;
    Ok(([(header::CONTENT_TYPE, "image/png")], png).into_response())
}

/// The PNG `vk-render render` writes for `scene`: what the render route answers and the explore page's
/// frames are.
pub fn rendered_png(renderer: &mut Renderer, scene: &Scene) -> Result<Vec<u8>, ApiError> {
    Ok(png_bytes(&renderer.render_picture(scene)?.pixels)?)
}

fn named(mut error: ApiError, id: &str) -> ApiError {
    if error.status == StatusCode::BAD_REQUEST && !error.message.starts_with(id) {
        error.message = format!("{id}: {}", error.message);
    }
    error
}

/// `POST /api/scene-file`: the scene file that reproduces a render (the scene's own text with the overrides
/// written into it), to download.
pub async fn scene_file(State(app): State<Arc<App>>, body: Bytes) -> Result<Response, ApiError> {
    let request = json_object(&body, &RENDER_FIELDS)?;
    let (entry, _) = requested_scene(&app, &request)?;
    let all = overrides(&request)?;
    let text = if all.is_empty() {
        entry.text().to_string()
    } else {
        let (_, text) = overridden(entry.text(), &entry.scene.source, &all).map_err(|e| scene_error(entry, &e))?;
        text
    };
    let disposition = HeaderValue::from_str(&format!("attachment; filename=\"{}.toml\"", entry.id))
        .map_err(|e| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?;
    Ok((
        [
            (header::CONTENT_TYPE, HeaderValue::from_static("application/toml")),
            (header::CONTENT_DISPOSITION, disposition),
        ],
        text,
    )
        .into_response())
}

/// What a lobe or albedo request answers with (`?format=`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    #[default]
    Csv,
    Svg,
    Json,
}

#[derive(Deserialize)]
pub struct FormatQuery {
    #[serde(default)]
    format: Format,
}

/// The material of a lobe or albedo request: `material` in the scene format's words (one of the course's
/// models: `{"brdf": "lambert", "kd": [0.5, 0.5, 0.5]}`), or a scene's material by name (`"scene": ID,
/// "material": NAME`, with the scene's `set`).
fn material(app: &App, request: &Map<String, Json>) -> Result<NamedBrdf, ApiError> {
    match request.get("material") {
        Some(Json::Object(words)) => {
            if request.contains_key("scene") || request.contains_key("set") {
                return Err(ApiError::bad_request(
                    "material: give the material in words, or a scene and its material's name, not both".into(),
                ));
            }
            material_in_words(words)
        }
        Some(Json::String(name)) => {
            let entry = entry(app, request.get("scene"))?;
            let scene = entry.scene(&overrides(request)?).map_err(|e| scene_error(entry, &e))?;
            let brdf = scene.materials.get(name).cloned().ok_or_else(|| {
                let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
                ApiError::not_found(format!(
                    "material `{}`: the scene {} has no such material (it has {})",
                    shortened(name),
                    entry.id,
                    known.join(", ")
                ))
            })?;
            Ok(NamedBrdf { name: name.clone(), brdf })
        }
        Some(other) => Err(ApiError::bad_request(format!(
            "material = {}: expected the material in the scene format's words or a scene's material's name",
            shortened(&other.to_string())
        ))),
        None => Err(ApiError::bad_request("material: missing".into())),
    }
}

/// A material written as a scene file's `[material.NAME]` table, each value checked as a `set` value is.
fn material_in_words(words: &Map<String, Json>) -> Result<NamedBrdf, ApiError> {
    let mut table = toml::Table::new();
    for (key, value) in words {
        if !key.chars().all(|c| c.is_ascii_lowercase() || c == '_') || key.is_empty() || key.len() > 32 {
            return Err(ApiError::bad_request(format!("material.{}: not a key of a material", shortened(key))));
        }
        let set = Map::from_iter([(format!("material.given.{key}"), value.clone())]);
        let request = Map::from_iter([("set".to_string(), Json::Object(set))]);
        let checked = overrides(&request)?;
        table.insert(key.clone(), checked[0].value.clone());
    }
    let mut materials = toml::Table::new();
    materials.insert("given".into(), toml::Value::Table(table));
    let document = toml::Table::from_iter([("material".to_string(), toml::Value::Table(materials))]);
    let text = toml::to_string(&document).map_err(|e| ApiError::bad_request(format!("material: {e}")))?;
    let scene = Scene::parse(&text, std::path::Path::new("material"), &[]).map_err(|e| ApiError::from_library(&e))?;
    let brdf: Brdf =
        scene.materials.get("given").cloned().ok_or_else(|| ApiError::bad_request("material: empty".into()))?;
    Ok(NamedBrdf { name: "material".into(), brdf })
}

/// Numbers of a request's field, each in `range` (degrees), at most `most` of them; `default` when absent.
fn angles(
    request: &Map<String, Json>,
    key: &str,
    range: std::ops::Range<f64>,
    most: usize,
    default: Vec<f64>,
) -> Result<Vec<f64>, ApiError> {
    let bad = |why: String| ApiError::bad_request(format!("{key}: {why}"));
    let values = match request.get(key) {
        None | Some(Json::Null) => return Ok(default),
        Some(Json::Number(n)) => vec![n.as_f64().unwrap_or(f64::NAN)],
        Some(Json::Array(items)) => items.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect(),
        Some(other) => {
            return Err(bad(format!(
                "{}: expected a number of degrees or an array of them",
                shortened(&other.to_string())
            )))
        }
    };
    if values.is_empty() || values.len() > most {
        return Err(bad(format!("{} angles; give 1 to {most}", values.len())));
    }
    if let Some(v) = values.iter().find(|v| !range.contains(*v)) {
        return Err(bad(format!("{v}: an angle is from {} to below {} degrees", range.start, range.end)));
    }
    Ok(values)
}

fn flag(request: &Map<String, Json>, key: &str, default: bool) -> Result<bool, ApiError> {
    match request.get(key) {
        None | Some(Json::Null) => Ok(default),
        Some(Json::Bool(b)) => Ok(*b),
        Some(other) => {
            Err(ApiError::bad_request(format!("{key} = {}: expected true or false", shortened(&other.to_string()))))
        }
    }
}

fn channel(request: &Map<String, Json>) -> Result<Channel, ApiError> {
    match request.get("channel").and_then(Json::as_str) {
        None => Ok(Channel::Luminance),
        Some("r") => Ok(Channel::Red),
        Some("g") => Ok(Channel::Green),
        Some("b") => Ok(Channel::Blue),
        Some("luminance") => Ok(Channel::Luminance),
        Some(other) => Err(ApiError::bad_request(format!("channel = {}: r, g, b or luminance", shortened(other)))),
    }
}

fn answer(
    format: Format,
    csv: String,
    svg: impl FnOnce() -> Result<String, ApiError>,
    json: Json,
) -> Result<Response, ApiError> {
    Ok(match format {
        Format::Csv => ([(header::CONTENT_TYPE, "text/csv; charset=utf-8")], csv).into_response(),
        Format::Svg => ([(header::CONTENT_TYPE, "image/svg+xml")], svg()?).into_response(),
        Format::Json => ([(header::CONTENT_TYPE, "application/json")], json.to_string()).into_response(),
    })
}

fn drawn(result: Result<String, String>) -> Result<String, ApiError> {
    result.map_err(|e| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, e))
}

const LOBE_FIELDS: [&str; 9] = ["material", "scene", "set", "theta_i", "phi", "cosine", "log", "channel", "format"];

/// `POST /api/lobe`: `vk-render plot lobe` of one material (CSV of the first incidence angle, as the command
/// writes it; SVG; or JSON of every angle).
pub async fn lobe(
    State(app): State<Arc<App>>,
    Query(query): Query<FormatQuery>,
    body: Bytes,
) -> Result<Response, ApiError> {
    let request = json_object(&body, &LOBE_FIELDS)?;
    let material = material(&app, &request)?;
    let theta_i = angles(&request, "theta_i", 0.0..90.0, 8, vec![30.0])?;
    let phi = match request.get("phi") {
        None => 0.0,
        Some(v) => v
            .as_f64()
            .filter(|p| p.is_finite())
            .ok_or_else(|| ApiError::bad_request(format!("phi = {v}: a number of degrees")))?,
    };
    let cosine = flag(&request, "cosine", true)?;
    let style = LobeStyle { channel: channel(&request)?, log: flag(&request, "log", false)? };
    let cuts: Vec<LobeCut> = theta_i.iter().map(|&theta_i| LobeCut { theta_i, phi, cosine }).collect();
    let format = query.format;
    app.workers
        .run(Lane::Quick, move |renderer| {
            let brdfs = [material.brdf.clone()];
            let values = cuts.iter().map(|cut| lobes(renderer, &brdfs, cut)).collect::<vk_render::Result<Vec<_>>>()?;
            let angles = lobe_angles();
            let materials = [material];
            let csv = lobe_table(&materials, &angles, &values[0]);
            let json = json!({
                "theta_o": angles,
                "lobes": cuts.iter().zip(&values).map(|(cut, v)| json!({
                    "theta_i": cut.theta_i,
                    "values": v[0].iter().map(|f: &Vec3| rgb(*f)).collect::<Vec<_>>(),
                })).collect::<Vec<_>>(),
            });
            answer(format, csv, || drawn(chart_svg(&lobe_chart(&materials, &cuts, &angles, &values, style))), json)
        })
        .await
}

const ALBEDO_FIELDS: [&str; 6] = ["material", "scene", "set", "theta_o", "channel", "format"];

/// `POST /api/albedo`: `vk-render plot albedo` of one material (CSV, SVG or JSON with the error bound).
pub async fn albedo(
    State(app): State<Arc<App>>,
    Query(query): Query<FormatQuery>,
    body: Bytes,
) -> Result<Response, ApiError> {
    let request = json_object(&body, &ALBEDO_FIELDS)?;
    let material = material(&app, &request)?;
    let theta_o = angles(&request, "theta_o", 0.0..90.0, 200, albedo_angles())?;
    let channel = channel(&request)?;
    let format = query.format;
    app.workers
        .run(Lane::Long, move |renderer| {
            let radians: Vec<f64> = theta_o.iter().map(|a| a.to_radians()).collect();
            let albedos = directional_albedos(renderer, &material.brdf, &radians, ALBEDO_TOLERANCE)?;
            let bound = albedos.iter().fold(0.0f64, |b, a| b.max(a.error_bound));
            let materials = [material];
            let curves = [albedos];
            let csv = albedo_table(&materials, &theta_o, &curves);
            let json = json!({
                "theta_o": theta_o,
                "albedo": curves[0].iter().map(|a| a.rho).collect::<Vec<_>>(),
                "error_bound": bound,
            });
            answer(format, csv, || drawn(chart_svg(&albedo_chart(&materials, &theta_o, &curves, bound, channel))), json)
        })
        .await
}

const ENVIRONMENT_ALBEDO_FIELDS: [&str; 3] = ["material", "scene", "set"];

/// `POST /api/environment-albedo`: the albedo table the environment's fast mode reads for one material
/// (`Renderer::albedo_table`: its diffuse and specular lobes' directional albedos at the table's 32 cosines),
/// as the browser's uniform block holds it: `{"table": [...]}`, each entry's diffuse rgb and 0, then its
/// specular rgb and 0.
pub async fn environment_albedo(State(app): State<Arc<App>>, body: Bytes) -> Result<Response, ApiError> {
    let request = json_object(&body, &ENVIRONMENT_ALBEDO_FIELDS)?;
    let material = material(&app, &request)?;
    app.workers
        .run(Lane::Long, move |renderer| {
            let table = albedo_file(renderer, &material.brdf)?;
            Ok(([(header::CONTENT_TYPE, "application/json")], table).into_response())
        })
        .await
}

/// `brdf`'s albedo table as `POST /api/environment-albedo` answers it.
pub fn albedo_file(renderer: &mut Renderer, brdf: &Brdf) -> vk_render::Result<String> {
    let table = renderer.albedo_table(brdf)?;
    let floats: Vec<f32> = table.iter().flat_map(|entry| entry.diffuse.into_iter().chain(entry.specular)).collect();
    Ok(json!({ "table": floats }).to_string())
}

/// `GET /api/reports/ID`: a check's report as JSON, while it is kept.
pub async fn report(State(app): State<Arc<App>>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    let report = app.reports.get(&id).ok_or_else(|| forgotten(&app, &id))?;
    Ok(([(header::CONTENT_TYPE, "application/json"), (header::CACHE_CONTROL, "no-store")], report.json.clone())
        .into_response())
}

/// `GET /api/reports/ID/NAME.png`: one of a report's pictures.
pub async fn report_picture(
    State(app): State<Arc<App>>,
    UrlPath((id, file)): UrlPath<(String, String)>,
) -> Result<Response, ApiError> {
    let report = app.reports.get(&id).ok_or_else(|| forgotten(&app, &id))?;
    let name = file.strip_suffix(".png").unwrap_or("");
    let picture = report
        .pictures
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| ApiError::not_found(format!("`{}`: the report has no such picture", shortened(&file))))?;
    Ok(([(header::CONTENT_TYPE, "image/png"), (header::CACHE_CONTROL, "no-store")], picture.1.clone()).into_response())
}

fn forgotten(app: &App, id: &str) -> ApiError {
    ApiError::not_found(format!(
        "report `{}`: no such report (a report is kept {} minutes, then forgotten)",
        shortened(id),
        app.reports.lifetime.as_secs() / 60
    ))
}

/// `GET /api/status`: what the server is doing, for its staff.
pub async fn status(State(app): State<Arc<App>>) -> Response {
    let body = json!({
        "workers": app.worker_count,
        "pending": app.workers.pending(),
        "reports": app.reports.count(),
        "scenes": app.catalogue.entries().count(),
    });
    ([(header::CONTENT_TYPE, "application/json"), (header::CACHE_CONTROL, "no-store")], body.to_string())
        .into_response()
}
