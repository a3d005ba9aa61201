//! `vk-render serve`: the checker and the material explorer in a browser, for a whole class. A thin layer
//! over the library, as the Python package is: routes, limits and pages. The device is opened and the
//! pipelines built once, at start, by a few render workers ([`workers`]); the async threads only move bytes.
//!
//! What it holds a client to is stated in one place ([`limits::Limits`], [`Bounds`]) and in the guide's
//! page for a course's staff, docs/serve.md.

mod api;
mod app;
mod auth;
mod browser;
mod cache;
mod catalogue;
mod check;
mod description;
mod downloads;
mod error;
mod explore;
mod limits;
mod pages;
mod reports;
pub mod site;
mod workers;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use axum::extract::DefaultBodyLimit;
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::IntoResponse;
use axum::routing::{get, post};
use axum::{BoxError, Router};
use clap::Args;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::sync::{watch, Semaphore};
use tower::ServiceBuilder;
use tower_http::compression::CompressionLayer;
use tower_http::set_header::SetResponseHeaderLayer;
use tower_http::timeout::RequestBodyTimeoutLayer;

use vk_render::RendererOptions;

use app::App;
use auth::Access;
use catalogue::Catalogue;
use limits::Limits;
use reports::Reports;
use workers::Workers;

#[derive(Args)]
pub struct ServeArgs {
    /// The address to listen on; `127.0.0.1:0` takes a free port. Any address but a loopback one needs a
    /// token (--token-file or VK_RENDER_TOKEN).
    #[arg(long, value_name = "ADDR:PORT", default_value = "127.0.0.1:8080")]
    listen: SocketAddr,

    /// Also serve every scene file (.toml) of this folder, by its file's stem (repeat for more folders).
    #[arg(long, value_name = "DIR")]
    scenes: Vec<PathBuf>,

    /// The file whose first line is the token (else the environment variable VK_RENDER_TOKEN). A token is
    /// never taken on the command line, which every user of the machine can read.
    #[arg(long, value_name = "FILE")]
    token_file: Option<PathBuf>,

    /// Render workers, each with its own renderer on the device: renders and checks at once.
    #[arg(long, value_name = "N", default_value_t = 2, value_parser = clap::value_parser!(u16).range(1..=64))]
    workers: u16,

    /// Requests that may wait for a worker, in each of two queues (renders and frames; checks and albedos);
    /// past them the server answers 503 with Retry-After.
    #[arg(long, value_name = "N", default_value_t = 32, value_parser = clap::value_parser!(u16).range(1..=4096))]
    queue: u16,

    /// How long a report (and the image checked) is kept, in minutes.
    #[arg(long, value_name = "MINUTES", default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=10080))]
    report_minutes: u32,

    /// The largest upload, in MiB (413 above it).
    #[arg(long, value_name = "MiB", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=256))]
    max_upload_mib: u32,

    /// How long a request may take in all, in seconds (503 after it).
    #[arg(long, value_name = "SECONDS", default_value_t = 120, value_parser = clap::value_parser!(u32).range(1..=3600))]
    deadline: u32,

    /// How long a client has to send a request's headers, in seconds (the connection is closed after it).
    #[arg(long, value_name = "SECONDS", default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=600))]
    header_timeout: u32,

    /// How long a request's body may pause, in seconds (408 after it; the whole request is bounded by
    /// --deadline).
    #[arg(long, value_name = "SECONDS", default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=3600))]
    body_timeout: u32,
}

/// The fixed bounds of the HTTP layer (the client's time to send a request is in [`Limits`]).
pub struct Bounds;

impl Bounds {
    /// Connections at once: past them a new connection is closed at once.
    pub const CONNECTIONS: usize = 1024;
    /// Requests at once (each connection's, and any waiting for a worker): past them 503.
    pub const REQUESTS: usize = 512;
    /// After SIGTERM or Ctrl-C: how long the requests in flight have to be answered.
    pub const GRACE: Duration = Duration::from_secs(20);
    /// Reports kept at most, and their bytes.
    pub const REPORTS: usize = 2000;
    pub const REPORT_BYTES: usize = 256 << 20;
}

/// Serves until SIGTERM or Ctrl-C, then answers the requests in flight and returns.
pub fn run(args: ServeArgs, options: RendererOptions) -> anyhow::Result<()> {
    let access = Access::from_file_or_environment(args.token_file.as_deref())?;
    if !args.listen.ip().is_loopback() && access.is_none() {
        anyhow::bail!(
            "--listen {}: this address is reachable from other machines; give the server a token \
             (--token-file FILE, or the environment variable VK_RENDER_TOKEN), or listen on 127.0.0.1",
            args.listen
        );
    }
    let catalogue = Catalogue::new(&args.scenes)?;
    let described = serde_json::to_string(&description::describe(&catalogue))?;
    let limits = Limits {
        max_upload: args.max_upload_mib as usize * (1 << 20),
        header_timeout: Duration::from_secs(u64::from(args.header_timeout)),
        body_timeout: Duration::from_secs(u64::from(args.body_timeout)),
        ..Limits::default()
    };
    let deadline = Duration::from_secs(u64::from(args.deadline));
    let scenes: Vec<&vk_render::Scene> = catalogue.entries().map(|e| &e.scene).collect();
    let workers = Workers::start(usize::from(args.workers), usize::from(args.queue), deadline, &options, &scenes)
        .context("cannot open the render workers")?;
    let (stop, stopping) = watch::channel(false);
    let app = Arc::new(App {
        catalogue,
        described,
        browser_files: cache::Files::default(),
        workers,
        worker_count: usize::from(args.workers),
        reports: Reports::new(
            Duration::from_secs(u64::from(args.report_minutes) * 60),
            Bounds::REPORTS,
            Bounds::REPORT_BYTES,
        ),
        limits,
        access,
        stopping,
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("serve-io")
        .enable_all()
        .build()
        .context("cannot start the server's threads")?;
    let served = runtime.block_on(serve(app.clone(), args.listen, stop, deadline));
    // The workers finish what they hold and their renderers are destroyed on their threads.
    app.workers.stop();
    served
}

/// The routes and the layers every answer passes through.
fn router(app: Arc<App>, deadline: Duration) -> Router {
    let pages = Router::new()
        .route("/", get(pages::index))
        .route("/index.html", get(pages::index))
        .route("/explore", get(pages::explore))
        .route("/explore.html", get(pages::explore))
        .route("/check", get(pages::check))
        .route("/check.html", get(pages::check))
        .route("/reports/{id}", get(pages::report))
        .route("/signin", get(pages::sign_in_query).post(pages::sign_in_form))
        .route("/static/shaders.json", get(downloads::shaders))
        .route("/static/brdf-templates.json", get(downloads::templates))
        .route("/static/{name}", get(pages::asset))
        .route("/static/{folder}/{name}", get(pages::asset_in_folder));
    let json_api = Router::new()
        .route("/api/scenes", get(api::scenes))
        .route("/api/status", get(api::status))
        .route("/api/render", post(api::render))
        .route("/api/scene-file", post(api::scene_file))
        .route("/api/lobe", post(api::lobe))
        .route("/api/albedo", post(api::albedo))
        .route("/api/reports/{id}", get(api::report))
        .route("/api/reports/{id}/{picture}", get(api::report_picture))
        .route("/api/explore", get(explore::explore))
        .route("/api/mesh", get(downloads::mesh))
        .route("/api/measured", get(downloads::measured))
        .route("/api/analytic", get(downloads::analytic))
        .route("/api/environment", get(downloads::environment))
        .route("/api/environment-albedo", post(api::environment_albedo))
        .layer(DefaultBodyLimit::max(api::MAX_JSON_BYTES));
    // The form's own overhead beside the image: its boundaries, headers and the scene's id.
    let upload = Router::new()
        .route("/api/check", post(check::check))
        .layer(DefaultBodyLimit::max(app.limits.max_upload + (64 << 10)));
    let headers = |name: header::HeaderName, value: &'static str| {
        SetResponseHeaderLayer::overriding(name, HeaderValue::from_static(value))
    };
    Router::new()
        .merge(pages)
        .merge(json_api)
        .merge(upload)
        .fallback(|| async { (StatusCode::NOT_FOUND, "no such page or route\n") })
        .layer(axum::middleware::from_fn_with_state(app.access.clone(), auth::require))
        .layer(
            ServiceBuilder::new()
                .layer(axum::error_handling::HandleErrorLayer::new(|error: BoxError| async move { overloaded(&error) }))
                .load_shed()
                .concurrency_limit(Bounds::REQUESTS)
                .timeout(deadline + Duration::from_secs(5)),
        )
        .layer(RequestBodyTimeoutLayer::new(app.limits.body_timeout))
        .layer(CompressionLayer::new())
        .layer(headers(header::CONTENT_SECURITY_POLICY, pages::CONTENT_SECURITY_POLICY))
        .layer(headers(header::X_CONTENT_TYPE_OPTIONS, "nosniff"))
        .layer(headers(header::X_FRAME_OPTIONS, "DENY"))
        .layer(headers(header::REFERRER_POLICY, "no-referrer"))
        // Requests at debug level (`-vv`); a refusal is an answer, not a server's failure.
        .layer(
            tower_http::trace::TraceLayer::new_for_http()
                .on_failure(tower_http::trace::DefaultOnFailure::new().level(tracing::Level::DEBUG)),
        )
        .with_state(app)
}

/// The answer when the server sheds a request (too many at once) or one outlived its deadline.
fn overloaded(error: &BoxError) -> axum::response::Response {
    if error.is::<tower::timeout::error::Elapsed>() {
        return error::ApiError::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "the request outlived this server's deadline".into(),
        )
        .into_response();
    }
    error::ApiError::busy(1).into_response()
}

/// Accepts connections until a signal, each served by hyper with a deadline on its headers; then stops
/// accepting, lets the requests in flight be answered (within [`Bounds::GRACE`]) and returns.
async fn serve(
    app: Arc<App>,
    address: SocketAddr,
    stop: watch::Sender<bool>,
    deadline: Duration,
) -> anyhow::Result<()> {
    let listener =
        tokio::net::TcpListener::bind(address).await.with_context(|| format!("--listen {address}: cannot listen"))?;
    let bound = listener.local_addr()?;
    println!("listening on http://{bound}");
    if let Some(access) = &app.access {
        println!("sign in: http://{bound}/signin?token={}", access.token_text());
    }
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let router = router(app.clone(), deadline);
    let mut open = tokio::task::JoinSet::new();
    let connections = Arc::new(Semaphore::new(Bounds::CONNECTIONS));
    let stopping = app.stopping.clone();
    let signal = stop_signal();
    tokio::pin!(signal);
    loop {
        let (stream, _peer) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(accepted) => accepted,
                Err(e) => {
                    // Out of file descriptors and the like: wait a moment rather than spin.
                    log::warn!("accept: {e}");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            () = &mut signal => break,
        };
        let Ok(permit) = connections.clone().try_acquire_owned() else {
            drop(stream);
            continue;
        };
        let service = TowerToHyperService::new(router.clone());
        let connection = hyper::server::conn::http1::Builder::new()
            .timer(TokioTimer::new())
            .header_read_timeout(app.limits.header_timeout)
            .serve_connection(TokioIo::new(stream), service)
            .with_upgrades();
        let mut stopping = stopping.clone();
        open.spawn(async move {
            tokio::pin!(connection);
            tokio::select! {
                _ = connection.as_mut() => {}
                _ = stopping.changed() => {
                    // Ends the connection after the request in flight, if any, is answered.
                    connection.as_mut().graceful_shutdown();
                    let _ = connection.await;
                }
            }
            drop(permit);
        });
        while open.try_join_next().is_some() {}
    }
    drop(listener);
    eprintln!("vk-render serve: stopping: no new connections; answering the requests in flight");
    let _ = stop.send(true);
    let answered = async { while open.join_next().await.is_some() {} };
    if tokio::time::timeout(Bounds::GRACE, answered).await.is_err() {
        eprintln!("vk-render serve: requests still open after {} s were dropped", Bounds::GRACE.as_secs());
    }
    Ok(())
}

/// Ctrl-C or SIGTERM.
async fn stop_signal() {
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(e) => {
                log::warn!("cannot catch SIGTERM: {e}");
                std::future::pending::<()>().await;
            }
        }
    };
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        () = terminate => {}
    }
}
