//! What every handler of `vk-render serve` shares: the catalogue, the render workers, the reports kept, the
//! limits a client is held to and who may come in. Made once at start (`serve::run`); each handler takes it
//! as axum's state.

use std::sync::Arc;

use tokio::sync::watch;

use super::auth::Access;
use super::cache;
use super::catalogue::Catalogue;
use super::limits::Limits;
use super::reports::Reports;
use super::workers::Workers;

/// What every handler shares.
pub struct App {
    pub catalogue: Catalogue,
    /// `GET /api/scenes`'s answer, made at start.
    pub described: String,
    /// The browser's meshes and measured tables, each made once.
    pub browser_files: cache::Files,
    pub workers: Workers,
    pub worker_count: usize,
    pub reports: Reports,
    pub limits: Limits,
    pub access: Option<Arc<Access>>,
    /// Becomes true on SIGTERM or Ctrl-C: the explore sockets close.
    pub stopping: watch::Receiver<bool>,
}
