//! The pages: static HTML, CSS and JavaScript embedded in the binary (no build step, nothing fetched from
//! elsewhere: they work on a network without the Internet), and the headers every answer carries.

use std::sync::Arc;

use axum::extract::State;
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Redirect, Response};
use axum::Form;
use serde::Deserialize;

use super::app::App;
use super::auth::{sign_in, Access, SESSION_COOKIE};

/// One embedded file: its path under /static/, its type and its bytes. The scripts are ES modules, the
/// browser's renderer in renderer/ and the explore page's parts in explore/; `vk-render.wasm` is the
/// library's code the editor and a site's check page run (crates/web/, built for WebAssembly by build.rs).
const STATIC: &[(&str, &str, &[u8])] = &[
    ("style.css", "text/css; charset=utf-8", include_bytes!("pages/style.css")),
    ("icon.svg", "image/svg+xml", include_bytes!("pages/icon.svg")),
    ("site.js", JAVASCRIPT, include_bytes!("pages/site.js")),
    ("common.js", JAVASCRIPT, include_bytes!("pages/common.js")),
    ("wasm.js", JAVASCRIPT, include_bytes!("pages/wasm.js")),
    ("explore.js", JAVASCRIPT, include_bytes!("pages/explore.js")),
    ("explore/state.js", JAVASCRIPT, include_bytes!("pages/explore/state.js")),
    ("explore/frames.js", JAVASCRIPT, include_bytes!("pages/explore/frames.js")),
    ("explore/controls.js", JAVASCRIPT, include_bytes!("pages/explore/controls.js")),
    ("explore/studies.js", JAVASCRIPT, include_bytes!("pages/explore/studies.js")),
    ("explore/charts.js", JAVASCRIPT, include_bytes!("pages/explore/charts.js")),
    ("explore/editor.js", JAVASCRIPT, include_bytes!("pages/explore/editor.js")),
    ("renderer/renderer.js", JAVASCRIPT, include_bytes!("pages/renderer/renderer.js")),
    ("renderer/bindings.js", JAVASCRIPT, include_bytes!("pages/renderer/bindings.js")),
    ("renderer/blocks.js", JAVASCRIPT, include_bytes!("pages/renderer/blocks.js")),
    ("renderer/math.js", JAVASCRIPT, include_bytes!("pages/renderer/math.js")),
    ("renderer/resources.js", JAVASCRIPT, include_bytes!("pages/renderer/resources.js")),
    ("renderer/passes.js", JAVASCRIPT, include_bytes!("pages/renderer/passes.js")),
    ("renderer/probe.js", JAVASCRIPT, include_bytes!("pages/renderer/probe.js")),
    ("check.js", JAVASCRIPT, include_bytes!("pages/check.js")),
    ("report.js", JAVASCRIPT, include_bytes!("pages/report.js")),
    ("vk-render.wasm", "application/wasm", include_bytes!(concat!(env!("OUT_DIR"), "/vk-render.wasm"))),
];

const JAVASCRIPT: &str = "text/javascript; charset=utf-8";

/// The pages and scripts a folder of `vk-render site` holds, by their paths in it: the same files as the
/// server's (its own `static/site.js` aside, which the site writes), where the pages' relative links find them.
pub fn site_files() -> impl Iterator<Item = (String, &'static [u8])> {
    let pages = [("index.html", INDEX), ("explore.html", EXPLORE), ("check.html", CHECK)];
    let scripts = STATIC.iter().filter(|(name, _, _)| name != &"site.js");
    pages
        .into_iter()
        .map(|(name, text)| (name.to_string(), text.as_bytes()))
        .chain(scripts.map(|(name, _, bytes)| (format!("static/{name}"), *bytes)))
}

const INDEX: &str = include_str!("pages/index.html");
const EXPLORE: &str = include_str!("pages/explore.html");
const CHECK: &str = include_str!("pages/check.html");
const REPORT: &str = include_str!("pages/report.html");

/// The Content-Security-Policy of every answer: nothing but this server's own scripts, styles and
/// connections (no inline script; WebAssembly compiled from the server's own `vk-render.wasm`, which
/// Chromium allows only with 'wasm-unsafe-eval'), pictures also from blobs the pages make, never inside
/// another site's frame.
pub const CONTENT_SECURITY_POLICY: &str =
    "default-src 'none'; script-src 'self' 'wasm-unsafe-eval'; style-src 'self'; \
     img-src 'self' blob: data:; connect-src 'self'; form-action 'self'; base-uri 'none'; frame-ancestors 'none'";

fn html(status: StatusCode, page: &'static str) -> Response {
    (status, [(header::CONTENT_TYPE, "text/html; charset=utf-8")], page).into_response()
}

pub async fn index() -> Response {
    html(StatusCode::OK, INDEX)
}

pub async fn explore() -> Response {
    html(StatusCode::OK, EXPLORE)
}

pub async fn check() -> Response {
    html(StatusCode::OK, CHECK)
}

/// A report's page: the same page for every id (its script reads the id from the address and asks the API);
/// never cached, like everything of a report.
pub async fn report() -> Response {
    let mut response = html(StatusCode::OK, REPORT);
    response.headers_mut().insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    response
}

/// `GET /static/NAME`.
pub async fn asset(axum::extract::Path(name): axum::extract::Path<String>) -> Response {
    embedded(&name)
}

/// `GET /static/FOLDER/NAME`: a module of the browser's renderer or of the explore page.
pub async fn asset_in_folder(axum::extract::Path((folder, name)): axum::extract::Path<(String, String)>) -> Response {
    embedded(&format!("{folder}/{name}"))
}

fn embedded(path: &str) -> Response {
    match STATIC.iter().find(|(file, _, _)| *file == path) {
        Some((_, kind, text)) => {
            ([(header::CONTENT_TYPE, *kind), (header::CACHE_CONTROL, "no-cache")], *text).into_response()
        }
        None => (StatusCode::NOT_FOUND, "no such file\n").into_response(),
    }
}

#[derive(Deserialize)]
pub struct SignIn {
    token: Option<String>,
}

/// `GET /signin?token=...` (the link the server prints) and `POST /signin` (the form): the token exchanged
/// for a session cookie and a redirect to the front page, so that the token leaves the address bar.
pub async fn sign_in_with(State(app): State<Arc<App>>, token: Option<SignIn>) -> Response {
    let Some(access) = app.access.as_ref() else { return Redirect::to("/").into_response() };
    match token.and_then(|t| t.token) {
        None => sign_in(StatusCode::OK),
        Some(token) if access.is_token(&token) => session(access),
        Some(_) => sign_in(StatusCode::UNAUTHORIZED),
    }
}

pub async fn sign_in_query(
    state: State<Arc<App>>,
    axum::extract::Query(query): axum::extract::Query<SignIn>,
) -> Response {
    sign_in_with(state, Some(query)).await
}

pub async fn sign_in_form(state: State<Arc<App>>, Form(form): Form<SignIn>) -> Response {
    sign_in_with(state, Some(form)).await
}

fn session(access: &Access) -> Response {
    let value = match access.open_session() {
        Ok(value) => value,
        Err(e) => return (StatusCode::INTERNAL_SERVER_ERROR, format!("cannot open a session: {e}\n")).into_response(),
    };
    let mut response = Redirect::to("/").into_response();
    let cookie = format!("{SESSION_COOKIE}={value}; HttpOnly; SameSite=Strict; Path=/");
    match HeaderValue::from_str(&cookie) {
        Ok(cookie) => {
            response.headers_mut().insert(header::SET_COOKIE, cookie);
        }
        Err(_) => return StatusCode::INTERNAL_SERVER_ERROR.into_response(),
    }
    response
}
