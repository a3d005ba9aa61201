//! Who may use a server that listens beyond this machine: whoever holds its token. The token comes from a
//! file or the environment (never the command line, which other users can read in the process list); a
//! browser exchanges it once at `/signin` for a session cookie (HttpOnly, SameSite=Strict), a script sends
//! `Authorization: Bearer TOKEN`. Tokens and sessions are compared in constant time. Without either, every
//! route but the sign-in page and its style answers 401.

use std::collections::VecDeque;
use std::path::Path;
use std::sync::{Arc, Mutex};

use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use subtle::ConstantTimeEq;

/// The sign-in page (src/serve/pages/signin.html).
const SIGN_IN: &str = include_str!("pages/signin.html");

/// The sign-in page, with `status` (200 when asked for, 401 in place of a page the token guards).
pub fn sign_in(status: StatusCode) -> Response {
    (status, [(header::CONTENT_TYPE, "text/html; charset=utf-8")], SIGN_IN).into_response()
}

/// The cookie a signed-in browser holds.
pub const SESSION_COOKIE: &str = "vk_render_session";

/// The most sessions kept: past it, the oldest is signed out.
const MAX_SESSIONS: usize = 4096;

/// The shortest token taken: 128 bits in hexadecimal or base64.
const MIN_TOKEN_CHARACTERS: usize = 22;

/// The token and the sessions it opened.
pub struct Access {
    token: Vec<u8>,
    sessions: Mutex<VecDeque<[u8; 32]>>,
}

impl Access {
    /// The token of `--token-file` (its first line), else of `VK_RENDER_TOKEN`; `None` when neither is given.
    pub fn from_file_or_environment(file: Option<&Path>) -> anyhow::Result<Option<Arc<Self>>> {
        let token = match file {
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| anyhow::anyhow!("--token-file {}: cannot read it: {e}", path.display()))?;
                Some((text.lines().next().unwrap_or("").trim().to_string(), format!("--token-file {}", path.display())))
            }
            None => std::env::var("VK_RENDER_TOKEN").ok().map(|t| (t.trim().to_string(), "VK_RENDER_TOKEN".into())),
        };
        let Some((token, from)) = token else { return Ok(None) };
        if token.len() < MIN_TOKEN_CHARACTERS || !token.chars().all(|c| c.is_ascii_graphic()) {
            anyhow::bail!(
                "{from}: a token is at least {MIN_TOKEN_CHARACTERS} printable characters without spaces \
                 (make one with `openssl rand -hex 16`)"
            );
        }
        Ok(Some(Arc::new(Self { token: token.into_bytes(), sessions: Mutex::new(VecDeque::new()) })))
    }

    /// The token, for the sign-in link printed at start.
    pub fn token_text(&self) -> String {
        String::from_utf8_lossy(&self.token).into_owned()
    }

    /// Whether `given` is the token.
    pub fn is_token(&self, given: &str) -> bool {
        bool::from(given.as_bytes().ct_eq(&self.token))
    }

    /// A new session's cookie value (64 hexadecimal digits of the system's random source).
    pub fn open_session(&self) -> std::io::Result<String> {
        let mut bits = [0u8; 32];
        getrandom::fill(&mut bits).map_err(|e| std::io::Error::other(e.to_string()))?;
        let mut sessions = self.sessions.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        sessions.push_back(bits);
        while sessions.len() > MAX_SESSIONS {
            sessions.pop_front();
        }
        Ok(bits.iter().map(|b| format!("{b:02x}")).collect())
    }

    /// Whether the request carries the token (Bearer) or a session's cookie.
    fn admits(&self, headers: &HeaderMap) -> bool {
        let bearer = headers
            .get_all(header::AUTHORIZATION)
            .iter()
            .filter_map(|v| v.to_str().ok())
            .filter_map(|v| v.strip_prefix("Bearer "))
            .any(|token| self.is_token(token.trim()));
        bearer || cookie(headers, SESSION_COOKIE).is_some_and(|value| self.is_session(&value))
    }

    fn is_session(&self, value: &str) -> bool {
        let Some(bits) = hex_32(value) else { return false };
        let sessions = self.sessions.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        // Every kept session compared, each in constant time.
        sessions.iter().fold(false, |found, s| found | bool::from(s.ct_eq(&bits)))
    }
}

/// The value of cookie `name` in the request's Cookie headers.
pub fn cookie(headers: &HeaderMap, name: &str) -> Option<String> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
        .find(|(key, _)| *key == name)
        .map(|(_, value)| value.to_string())
}

fn hex_32(text: &str) -> Option<[u8; 32]> {
    if text.len() != 64 {
        return None;
    }
    let mut bits = [0u8; 32];
    for (i, byte) in bits.iter_mut().enumerate() {
        *byte = u8::from_str_radix(text.get(2 * i..2 * i + 2)?, 16).ok()?;
    }
    Some(bits)
}

/// The paths anyone may ask for: the sign-in page, what it posts to, its style and icon.
fn is_open(path: &str) -> bool {
    matches!(path, "/signin" | "/static/style.css" | "/static/icon.svg")
}

/// Lets a request through when the server has no token, the path is open, or it carries the token or a
/// session; otherwise 401: the sign-in page for a page, one line for the API.
pub async fn require(State(access): State<Option<Arc<Access>>>, request: Request, next: Next) -> Response {
    let Some(access) = access else { return next.run(request).await };
    if is_open(request.uri().path()) || access.admits(request.headers()) {
        return next.run(request).await;
    }
    if request.uri().path().starts_with("/api/") {
        let mut response =
            (StatusCode::UNAUTHORIZED, "this server needs its token: Authorization: Bearer TOKEN\n").into_response();
        response.headers_mut().insert(header::WWW_AUTHENTICATE, header::HeaderValue::from_static("Bearer"));
        return response;
    }
    let mut response = sign_in(StatusCode::UNAUTHORIZED);
    response.headers_mut().insert(header::WWW_AUTHENTICATE, header::HeaderValue::from_static("Bearer"));
    response
}
