//! `POST /api/check`: a student's image against a scene of the catalogue (or the figure it is closest to),
//! answered with `vk_render.check`'s JSON and the address of its report. The upload is checked before it is
//! decoded (its size, its format by content, the dimensions its header states) and decoded within
//! `image::Limits`; nothing of it touches the disk.

use std::sync::Arc;
use std::time::Duration;

use axum::extract::{Multipart, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use image::RgbImage;
use serde_json::{json, Value as Json};

use vk_render::check::report::{check_image, decode_image, Checked};
use vk_render::check::summary::Summary;
use vk_render::pictures::compare::compare;
use vk_render::pictures::output::png_bytes;
use vk_render::pictures::report::Difference;
use vk_render::{Override, Renderer, Scene};

use super::api::{entry, json_object, scene_error};
use super::app::App;
use super::catalogue::{Catalogue, Entry};
use super::error::ApiError;
use super::limits::{decoding_limits, overrides, Limits, Upload};
use super::reports::{new_id, Report};
use super::workers::Lane;
use vk_render::files::shortened;

/// A report's pictures: name and PNG bytes.
type Pictures = Vec<(&'static str, Vec<u8>)>;

/// The most parts a check's form may have (it takes two).
const MAX_PARTS: usize = 4;

/// The most bytes of the `scene` part, and of the `set` part.
const MAX_SCENE_PART: usize = 256;
const MAX_SET_PART: usize = 16 << 10;

/// What a check was sent.
struct Sent {
    image: Vec<u8>,
    scene: Option<String>,
    /// Overrides of the scene (a JSON object, as a render's `set`).
    set: Vec<Override>,
}

async fn read_form(mut form: Multipart, limits: &Limits) -> Result<Sent, ApiError> {
    let mut image = None;
    let mut scene = None;
    let mut set = Vec::new();
    let mut parts = 0;
    while let Some(mut field) = form.next_field().await.map_err(|e| multipart_error(e, limits.body_timeout))? {
        parts += 1;
        if parts > MAX_PARTS {
            return Err(ApiError::bad_request(format!(
                "the form has more than {MAX_PARTS} parts; a check takes `image`, `scene` and `set`"
            )));
        }
        let name = field.name().unwrap_or("").to_string();
        let most = match name.as_str() {
            "image" => limits.max_upload,
            "scene" => MAX_SCENE_PART,
            "set" => MAX_SET_PART,
            other => {
                return Err(ApiError::bad_request(format!(
                    "`{}`: no such part (a check takes `image`, `scene` and `set`)",
                    shortened(other)
                )))
            }
        };
        let mut bytes = Vec::new();
        while let Some(chunk) = field.chunk().await.map_err(|e| multipart_error(e, limits.body_timeout))? {
            if bytes.len() + chunk.len() > most {
                // The image past the upload's limit is refused as the body's limit refuses it (whichever
                // trips first depends on where the reads end).
                return Err(if name == "image" {
                    upload_too_large()
                } else {
                    ApiError::too_large(format!("{name}: more than {most} bytes"))
                });
            }
            bytes.extend_from_slice(&chunk);
        }
        if name == "image" {
            image = Some(bytes);
            continue;
        }
        let text = String::from_utf8(bytes).map_err(|_| ApiError::bad_request(format!("{name}: not UTF-8 text")))?;
        let text = text.trim().to_string();
        if name == "scene" {
            scene = (!text.is_empty()).then_some(text);
        } else if !text.is_empty() {
            let object = json_object(format!("{{\"set\": {text}}}").as_bytes(), &["set"])
                .map_err(|e| ApiError::bad_request(format!("set: {}", e.message)))?;
            set = overrides(&object)?;
        }
    }
    let image =
        image.ok_or_else(|| ApiError::bad_request("image: missing (the form's `image` part is the file)".into()))?;
    Ok(Sent { image, scene, set })
}

fn upload_too_large() -> ApiError {
    ApiError::too_large("the upload is larger than this server takes".into())
}

fn multipart_error(error: axum::extract::multipart::MultipartError, body_timeout: Duration) -> ApiError {
    // A body that paused for the body timeout or broke off is the client's doing, not the server's.
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(&error);
    while let Some(cause) = source {
        if cause.is::<tower_http::timeout::TimeoutError>() {
            return ApiError::new(
                StatusCode::REQUEST_TIMEOUT,
                format!("the upload paused for {} s (the body timeout)", body_timeout.as_secs()),
            );
        }
        source = cause.source();
    }
    match error.status() {
        StatusCode::PAYLOAD_TOO_LARGE => upload_too_large(),
        StatusCode::INTERNAL_SERVER_ERROR => {
            ApiError::bad_request(format!("the upload broke off: {}", error.body_text()))
        }
        status => ApiError::new(status, format!("the form cannot be read: {}", error.body_text())),
    }
}

/// `POST /api/check`.
pub async fn check(
    State(app): State<Arc<App>>,
    form: Result<Multipart, axum::extract::multipart::MultipartRejection>,
) -> Result<Response, ApiError> {
    let form =
        form.map_err(|e| ApiError::new(e.status(), format!("the request is not a multipart form: {}", e.body_text())))?;
    let sent = read_form(form, &app.limits).await?;
    let format = Upload::sniff(&sent.image)?;
    let (width, height) = format.dimensions(&sent.image, &app.limits)?;
    let entry = match &sent.scene {
        Some(id) => Some(entry(&app, Some(&Json::String(id.clone())))?.id.clone()),
        None => None,
    };
    let worker_app = app.clone();
    let (mut json, pictures) = app
        .workers
        .run(Lane::Long, move |renderer| {
            let app = worker_app;
            let mine = decode_image(&sent.image, decoding_limits(&app.limits))
                .map_err(|e| ApiError::bad_request(format!("image: {e}")))?;
            debug_assert_eq!(mine.dimensions(), (width, height));
            let chosen = match &entry {
                Some(id) => app.catalogue.get(id).ok_or_else(|| ApiError::not_found(format!("scene `{id}`")))?,
                None => closest_figure(renderer, &app.catalogue, &mine)?,
            };
            // The image's size last: the exact image is rendered at it, whatever `set` says.
            let mut sized = sent.set.clone();
            sized.push(Override::new("image.width", i64::from(mine.width())));
            sized.push(Override::new("image.height", i64::from(mine.height())));
            let scene = chosen.scene(&sized).map_err(|e| scene_error(chosen, &e))?;
            app.limits.check_scene(&scene)?;
            let checked = check_image(renderer, &mine, &scene, |_, _| {})?;
            report_of(&mine, chosen, &scene, &checked, entry.is_none())
        })
        .await?;
    let id = new_id().map_err(|e| {
        ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, format!("cannot make the report's address: {e}"))
    })?;
    json["report"] = json!(format!("/reports/{id}"));
    json["report_id"] = json!(id);
    json["expires_in_seconds"] = json!(app.reports.lifetime.as_secs());
    let stored = json.to_string();
    app.reports.keep(id, Report::new(stored.clone(), pictures));
    Ok(([(header::CONTENT_TYPE, "application/json"), (header::CACHE_CONTROL, "no-store")], stored).into_response())
}

/// The figure an image looks most like: every figure rendered small (at most 96 pixels wide, one sample)
/// and compared with the image shrunk to the same size.
fn closest_figure<'a>(
    renderer: &mut Renderer,
    catalogue: &'a Catalogue,
    mine: &RgbImage,
) -> Result<&'a Entry, ApiError> {
    let width = mine.width().min(96);
    let height = (u64::from(mine.height()) * u64::from(width) / u64::from(mine.width())).max(1) as u32;
    let small = image::imageops::resize(mine, width, height, image::imageops::FilterType::Triangle);
    let sized = [
        Override::new("image.width", i64::from(width)),
        Override::new("image.height", i64::from(height)),
        Override::new("image.samples", 1),
    ];
    let mut best: Option<(f64, &Entry)> = None;
    for figure in catalogue.entries().filter(|e| e.figure) {
        let scene = figure.scene(&sized).map_err(|e| scene_error(figure, &e))?;
        let rendered = renderer.render_rgb8(&scene)?;
        let rms = compare(&small, &rendered, &vec![false; (width * height) as usize]).mean_abs;
        if best.is_none_or(|(b, _)| rms < b) {
            best = Some((rms, figure));
        }
    }
    best.map(|(_, e)| e).ok_or_else(|| ApiError::bad_request("the server has no figure to match the image with".into()))
}

/// The answer to a check (without its report's address) and the report's pictures.
fn report_of(
    mine: &RgbImage,
    entry: &Entry,
    scene: &Scene,
    checked: &Checked,
    chosen: bool,
) -> Result<(Json, Pictures), ApiError> {
    let summary = Summary::of(checked, scene);
    let difference = Difference::of(mine, checked.exact());
    let (x, y, side) = difference.map.worst_region();
    let mut pictures = vec![
        ("yours", png_bytes(mine)?),
        ("exact", png_bytes(checked.exact())?),
        ("difference", png_bytes(&difference.map.heat_map())?),
    ];
    let diagnosed = summary.mistakes.first().map(|m| m.name);
    if let Some(name) = diagnosed {
        if let Some(candidate) = checked.candidates.iter().find(|c| c.mistake.is_some_and(|m| m.name == name)) {
            pictures.push(("mistake", png_bytes(&candidate.image)?));
        }
    }
    let mut json =
        serde_json::to_value(&summary).map_err(|e| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?;
    json["scene"] = json!(entry.id);
    json["scene_title"] = json!(entry.title);
    json["scene_chosen_by_server"] = json!(chosen);
    json["width"] = json!(mine.width());
    json["height"] = json!(mine.height());
    json["difference_scale"] = json!(difference.map.scale());
    json["worst_region"] = json!({"x": x, "y": y, "width": side, "height": side});
    json["pictures"] = json!(pictures.iter().map(|(name, _)| *name).collect::<Vec<_>>());
    json["mistake_picture"] = json!(diagnosed);
    Ok((json, pictures))
}
