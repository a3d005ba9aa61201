//! The explore page's frames over a WebSocket. The page sends the state of its controls (a render request's
//! JSON) whenever one moves; the server keeps the latest state only, renders a motion frame of it (the
//! preview's: half size, one sample, the environment's fast mode) as soon as the workers can, and once the
//! state has not changed for [`SETTLE`], the still frame: the very PNG `POST /api/render` and `vk-render
//! render` make. A frame whose state was overtaken before it was sent is dropped: latest wins, and no queue
//! grows. Each frame is a text message (its kind and size) followed by a binary one (its PNG). A page whose
//! browser draws the motion frames asks for the still frame alone (`"still": true`).

use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::extract::ws::{CloseFrame, Message, WebSocket, WebSocketUpgrade};
use axum::extract::State;
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use futures_util::{SinkExt, StreamExt};
use serde_json::{json, Map, Value as Json};
use tokio::sync::watch;

use vk_render::render::interactive::motion_scene;

use super::api::{json_object, rendered_png, requested_scene};
use super::app::App;
use super::error::ApiError;
use super::workers::Lane;

/// How long the controls must rest before the still frame is rendered.
pub const SETTLE: Duration = Duration::from_millis(150);

/// The largest message the page may send.
pub const MAX_MESSAGE_BYTES: usize = 16 << 10;

/// The most messages a second a page may send (a control dragged sends about 60): past it the socket is
/// closed as a flood.
pub const MAX_MESSAGES_PER_SECOND: u32 = 240;

/// A state's fields: a render request's, and `still` (true: the still frame only, which a page whose browser
/// draws the motion frames asks for once its controls rest).
const STATE_FIELDS: [&str; 8] = ["scene", "set", "width", "height", "samples", "view", "environment_mode", "still"];

/// `GET /api/explore`: the WebSocket, for pages of this server only (a browser's Origin must be this
/// server's own address; a script without an Origin is let through, with the token like any request).
pub async fn explore(State(app): State<Arc<App>>, headers: HeaderMap, upgrade: WebSocketUpgrade) -> Response {
    if let Some(origin) = headers.get(header::ORIGIN) {
        let host = headers.get(header::HOST).and_then(|h| h.to_str().ok()).unwrap_or("");
        let origin = origin.to_str().unwrap_or("");
        let own = [format!("http://{host}"), format!("https://{host}")];
        if !own.iter().any(|o| o == origin) {
            return ApiError::new(StatusCode::FORBIDDEN, format!("Origin {origin}: not this server's page"))
                .into_response();
        }
    }
    upgrade
        .max_message_size(MAX_MESSAGE_BYTES)
        .max_frame_size(MAX_MESSAGE_BYTES)
        .on_upgrade(move |socket| frames(app, socket))
}

/// What the page asked for last, numbered.
#[derive(Clone, Default)]
struct Wanted {
    state: Option<Map<String, Json>>,
    number: u64,
}

async fn frames(app: Arc<App>, socket: WebSocket) {
    let (mut sink, mut stream) = socket.split();
    let (wanted, mut latest) = watch::channel(Wanted::default());
    let (errors, mut error_lines) = tokio::sync::mpsc::channel::<String>(4);
    let mut stopping = app.stopping.clone();
    // The reader: each message replaces the state; a flood or a message past the limits closes the socket.
    let reader = async move {
        let (mut second, mut count) = (Instant::now(), 0u32);
        while let Some(Ok(message)) = stream.next().await {
            if second.elapsed() >= Duration::from_secs(1) {
                (second, count) = (Instant::now(), 0);
            }
            count += 1;
            if count > MAX_MESSAGES_PER_SECOND {
                return Some(format!("more than {MAX_MESSAGES_PER_SECOND} messages a second"));
            }
            let text = match message {
                Message::Text(text) => text,
                Message::Close(_) => return None,
                Message::Binary(_) => return Some("the page sends text messages only".into()),
                Message::Ping(_) | Message::Pong(_) => continue,
            };
            match json_object(text.as_bytes(), &STATE_FIELDS) {
                Ok(state) => wanted.send_modify(|w| {
                    w.state = Some(state);
                    w.number += 1;
                }),
                Err(e) => {
                    let _ = errors.try_send(e.message);
                }
            }
        }
        None
    };
    let writer = async {
        let mut shown_still: Option<u64> = None;
        let mut scene_of_last: Option<String> = None;
        'changes: loop {
            tokio::select! {
                changed = latest.changed() => if changed.is_err() { return },
                Some(line) = error_lines.recv() => {
                    if send_error(&mut sink, line).await.is_err() { return }
                    continue;
                }
                _ = stopping.changed() => return,
            }
            // Motion frames while the state keeps changing (each sent when done: it is at most one state
            // behind, and the next is of the newest); the first frame of a scene is a still one.
            loop {
                let Wanted { state: Some(state), number } = latest.borrow_and_update().clone() else {
                    continue 'changes;
                };
                let id = state.get("scene").and_then(Json::as_str).map(str::to_string);
                if scene_of_last.is_none() || scene_of_last != id || state.get("still") == Some(&Json::Bool(true)) {
                    break;
                }
                match frame(&app, &state, true).await {
                    Ok(frame) => {
                        if send(&mut sink, "motion", number, frame).await.is_err() {
                            return;
                        }
                    }
                    Err(e) if e.status == StatusCode::SERVICE_UNAVAILABLE => tokio::time::sleep(BUSY_WAIT).await,
                    Err(e) => {
                        if send_error(&mut sink, e.message).await.is_err() {
                            return;
                        }
                        continue 'changes;
                    }
                }
                match tokio::time::timeout(SETTLE, latest.changed()).await {
                    Ok(Ok(())) => continue,
                    Ok(Err(_)) => return,
                    Err(_) => break,
                }
            }
            // The still frame of the latest state, unless it is shown already; dropped when overtaken (the
            // newer state's frames follow at once, as its change is still marked).
            loop {
                let Wanted { state: Some(state), number } = latest.borrow_and_update().clone() else {
                    continue 'changes;
                };
                if shown_still == Some(number) {
                    continue 'changes;
                }
                scene_of_last = state.get("scene").and_then(Json::as_str).map(str::to_string);
                match frame(&app, &state, false).await {
                    Ok(frame) if !latest.has_changed().unwrap_or(true) => {
                        if send(&mut sink, "still", number, frame).await.is_err() {
                            return;
                        }
                        shown_still = Some(number);
                        continue 'changes;
                    }
                    Ok(_) => continue 'changes,
                    Err(e) if e.status == StatusCode::SERVICE_UNAVAILABLE => tokio::time::sleep(BUSY_WAIT).await,
                    Err(e) => {
                        scene_of_last = None;
                        if send_error(&mut sink, e.message).await.is_err() {
                            return;
                        }
                        continue 'changes;
                    }
                }
            }
        }
    };
    let reason = tokio::select! {
        reason = reader => reason,
        () = writer => None,
    };
    let close = match reason {
        Some(why) => CloseFrame { code: axum::extract::ws::close_code::POLICY, reason: why.into() },
        None => CloseFrame { code: axum::extract::ws::close_code::AWAY, reason: "".into() },
    };
    let _ = sink.send(Message::Close(Some(close))).await;
}

/// How long a frame waits for a worker when all are busy, before it asks again.
const BUSY_WAIT: Duration = Duration::from_millis(25);

async fn send_error(
    sink: &mut futures_util::stream::SplitSink<WebSocket, Message>,
    line: String,
) -> Result<(), axum::Error> {
    sink.send(Message::Text(json!({"error": line}).to_string().into())).await
}

/// A rendered frame: its size and its PNG.
struct Frame {
    width: u32,
    height: u32,
    png: Vec<u8>,
}

async fn frame(app: &Arc<App>, state: &Map<String, Json>, motion: bool) -> Result<Frame, ApiError> {
    let (_, scene) = requested_scene(app, state)?;
    let scene = if motion { motion_scene(&scene) } else { scene };
    app.workers
        .run(Lane::Quick, move |renderer| {
            Ok(Frame { width: scene.image.width, height: scene.image.height, png: rendered_png(renderer, &scene)? })
        })
        .await
}

async fn send(
    sink: &mut futures_util::stream::SplitSink<WebSocket, Message>,
    kind: &str,
    number: u64,
    frame: Frame,
) -> Result<(), axum::Error> {
    let header = json!({"kind": kind, "state": number, "width": frame.width, "height": frame.height});
    sink.send(Message::Text(header.to_string().into())).await?;
    sink.send(Message::Binary(frame.png.into())).await
}
