//! The render workers: a few threads, each owning a renderer made at start (its pipelines built for the
//! catalogue's scenes), fed from one bounded queue. The async threads never render, encode or decode: they
//! hand work over here and await its answer. A full queue is answered at once (503); work whose client went
//! away before a worker took it is dropped unstarted; work still queued at its deadline is not started.

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use tokio::sync::oneshot;

use vk_render::{Renderer, RendererOptions, Scene};

use super::error::ApiError;

/// One piece of work: it runs on a worker's renderer unless its client has gone or its deadline passed.
struct Job {
    work: Box<dyn FnOnce(&mut Renderer) + Send>,
    /// Whether the client still waits (its answer's receiver is alive).
    wanted: Box<dyn Fn() -> bool + Send>,
    deadline: Instant,
}

/// The pool of render workers.
pub struct Workers {
    queue: Mutex<Option<SyncSender<Job>>>,
    threads: Mutex<Vec<JoinHandle<()>>>,
    /// Jobs queued or running now.
    pending: Arc<AtomicUsize>,
    deadline: Duration,
    /// A device error injected into the Nth job, for the fault tests (`VK_RENDER_SERVE_FAULT=N`).
    fault: Option<usize>,
    jobs: AtomicUsize,
}

impl Workers {
    /// Opens `count` renderers with `options` (one after the other: an error names the first that failed),
    /// each prepared for `scenes`, and starts their threads; `queue` jobs may wait behind them.
    pub fn start(
        count: usize,
        queue: usize,
        deadline: Duration,
        options: &RendererOptions,
        scenes: &[&Scene],
    ) -> anyhow::Result<Self> {
        let (sender, receiver) = sync_channel::<Job>(queue);
        let receiver = Arc::new(Mutex::new(receiver));
        let mut threads = Vec::new();
        for index in 0..count {
            let renderer = Renderer::for_scenes(options.clone(), scenes)?;
            let receiver = receiver.clone();
            let thread =
                std::thread::Builder::new().name(format!("render-{index}")).spawn(move || work(renderer, &receiver))?;
            threads.push(thread);
        }
        let fault = std::env::var("VK_RENDER_SERVE_FAULT").ok().and_then(|n| n.parse().ok());
        Ok(Self {
            queue: Mutex::new(Some(sender)),
            threads: Mutex::new(threads),
            pending: Arc::new(AtomicUsize::new(0)),
            deadline,
            fault,
            jobs: AtomicUsize::new(0),
        })
    }

    /// Runs `work` on a worker and returns its answer: 503 at once when the queue is full, 503 when it was
    /// not done within the deadline (the work, once started, finishes on its worker: a device wait has its
    /// own deadline), 500 when it panicked.
    pub async fn run<T: Send + 'static>(
        &self,
        work: impl FnOnce(&mut Renderer) -> Result<T, ApiError> + Send + 'static,
    ) -> Result<T, ApiError> {
        let (answer, answered) = oneshot::channel::<Result<T, ApiError>>();
        let answer = Arc::new(Mutex::new(Some(answer)));
        let number = self.jobs.fetch_add(1, Ordering::Relaxed) + 1;
        let injected = self.fault == Some(number);
        let pending = self.pending.clone();
        let reply = answer.clone();
        let job = Job {
            work: Box::new(move |renderer| {
                let result = if injected {
                    Err(ApiError::from_library(&vk_render::Error::Vulkan(ash::vk::Result::ERROR_DEVICE_LOST)))
                } else {
                    std::panic::catch_unwind(AssertUnwindSafe(|| work(renderer))).unwrap_or_else(|panic| {
                        let what = panic
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_string()))
                            .unwrap_or_default();
                        Err(ApiError::new(
                            axum::http::StatusCode::INTERNAL_SERVER_ERROR,
                            format!("the render failed inside vk-render (a bug: {what})"),
                        ))
                    })
                };
                if let Some(reply) = lock(&reply).take() {
                    let _ = reply.send(result);
                }
            }),
            wanted: Box::new(move || lock(&answer).as_ref().is_some_and(|a| !a.is_closed())),
            deadline: Instant::now() + self.deadline,
        };
        let sent = match lock(&self.queue).as_ref() {
            Some(queue) => queue.try_send(job),
            None => {
                return Err(ApiError::new(axum::http::StatusCode::SERVICE_UNAVAILABLE, "the server is stopping".into()))
            }
        };
        match sent {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => return Err(ApiError::busy(1)),
            Err(TrySendError::Disconnected(_)) => {
                return Err(ApiError::new(axum::http::StatusCode::SERVICE_UNAVAILABLE, "the server is stopping".into()))
            }
        }
        let _counted = Counted::new(pending);
        match tokio::time::timeout(self.deadline, answered).await {
            Ok(Ok(result)) => result,
            Ok(Err(_)) => Err(ApiError::new(
                axum::http::StatusCode::SERVICE_UNAVAILABLE,
                format!("the work waited past this server's deadline of {} s", self.deadline.as_secs()),
            )),
            Err(_) => Err(ApiError::new(
                axum::http::StatusCode::SERVICE_UNAVAILABLE,
                format!("the work took longer than this server's deadline of {} s", self.deadline.as_secs()),
            )),
        }
    }

    /// Jobs queued or running now.
    pub fn pending(&self) -> usize {
        self.pending.load(Ordering::Relaxed)
    }

    /// Takes no more work, lets the workers finish what they hold, and waits for their threads (their
    /// renderers are destroyed on them).
    pub fn stop(&self) {
        lock(&self.queue).take();
        for thread in lock(&self.threads).drain(..) {
            let _ = thread.join();
        }
    }
}

/// Counts a job in [`Workers::pending`] while its request waits.
struct Counted(Arc<AtomicUsize>);

impl Counted {
    fn new(count: Arc<AtomicUsize>) -> Self {
        count.fetch_add(1, Ordering::Relaxed);
        Self(count)
    }
}

impl Drop for Counted {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Relaxed);
    }
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A worker's loop: the next job, run when still wanted and within its deadline, until the queue closes.
fn work(mut renderer: Renderer, jobs: &Mutex<Receiver<Job>>) {
    loop {
        let job = match lock(jobs).recv() {
            Ok(job) => job,
            Err(_) => return,
        };
        if !(job.wanted)() || Instant::now() > job.deadline {
            continue;
        }
        (job.work)(&mut renderer);
        if let Some(invalid) = renderer.take_invalid_values() {
            log::warn!("{invalid}");
        }
    }
}
