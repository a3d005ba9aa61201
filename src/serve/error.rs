//! A request that fails gets its status and one line saying why (text/plain), as a command prints its one
//! line on standard error.

use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};

/// A failed request: its status and its line.
#[derive(Debug)]
pub struct ApiError {
    pub status: StatusCode,
    pub message: String,
    /// For 503: when to try again, in seconds.
    pub retry_after: Option<u32>,
}

impl ApiError {
    pub fn new(status: StatusCode, message: String) -> Self {
        Self { status, message, retry_after: None }
    }

    pub fn bad_request(message: String) -> Self {
        Self::new(StatusCode::BAD_REQUEST, message)
    }

    pub fn not_found(message: String) -> Self {
        Self::new(StatusCode::NOT_FOUND, message)
    }

    pub fn too_large(message: String) -> Self {
        Self::new(StatusCode::PAYLOAD_TOO_LARGE, message)
    }

    pub fn unsupported(message: String) -> Self {
        Self::new(StatusCode::UNSUPPORTED_MEDIA_TYPE, message)
    }

    /// Every render worker busy and the queue full.
    pub fn busy(retry_after: u32) -> Self {
        Self {
            status: StatusCode::SERVICE_UNAVAILABLE,
            message: "the server is busy: every render worker is taken and its queue is full; try again".into(),
            retry_after: Some(retry_after),
        }
    }

    /// What the library said of a request: the scene's or the input's fault is the client's (400), anything
    /// else the server's (500).
    pub fn from_library(error: &vk_render::Error) -> Self {
        use vk_render::Error;
        let line = error.to_string().replace('\n', " ");
        match error {
            Error::Scene { .. } | Error::Input { .. } => Self::bad_request(line),
            Error::Timeout { .. } => Self::new(StatusCode::SERVICE_UNAVAILABLE, line),
            _ => Self::new(StatusCode::INTERNAL_SERVER_ERROR, line),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let line = format!("{}\n", self.message.replace('\n', " "));
        let mut response = (self.status, line).into_response();
        let headers = response.headers_mut();
        headers.insert(header::CONTENT_TYPE, HeaderValue::from_static("text/plain; charset=utf-8"));
        if let Some(seconds) = self.retry_after {
            headers.insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        response
    }
}

impl From<vk_render::Error> for ApiError {
    fn from(error: vk_render::Error) -> Self {
        Self::from_library(&error)
    }
}
