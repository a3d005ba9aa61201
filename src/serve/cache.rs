//! Files made once and shared: the browser's files that are made from the catalogue, kept by the server
//! for as long as it runs.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use axum::body::Bytes;
use axum::http::StatusCode;

use super::error::ApiError;

/// The browser's files that are made from the catalogue (a mesh's vertices, a measured table's floats), each
/// made once, on a blocking thread, by the first request for it, and shared by every request after it (and by
/// those waiting for it): their memory is bounded by the catalogue, not by how many ask at once. Only keys
/// of the catalogue's own objects and materials get here.
#[derive(Default)]
pub struct Files(Mutex<HashMap<String, Arc<tokio::sync::OnceCell<Bytes>>>>);

impl Files {
    /// The file `key`: made by `make` on a blocking thread by the first caller, the same bytes for every
    /// caller after it.
    pub async fn get(
        &self,
        key: String,
        make: impl FnOnce() -> Result<Vec<u8>, ApiError> + Send + 'static,
    ) -> Result<Bytes, ApiError> {
        let cell = self.0.lock().unwrap_or_else(|p| p.into_inner()).entry(key).or_default().clone();
        cell.get_or_try_init(|| async {
            tokio::task::spawn_blocking(make)
                .await
                .map_err(|e| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, format!("the file's task failed: {e}")))?
                .map(Bytes::from)
        })
        .await
        .cloned()
    }
}
