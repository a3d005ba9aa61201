//! The render workers: a few threads, each owning a renderer made at start (its pipelines built for the
//! catalogue's scenes), fed from two bounded queues: quick work (renders, frames, lobes) and long work
//! (checks, albedos), the quick first, and the long on all workers but one, so that a class's checks never
//! stall its explore pages. The async threads never render, encode or decode: they hand work over here and
//! await its answer. A full queue is answered at once (503); work whose client went away before a worker
//! took it is dropped unstarted; work still queued at its deadline is not started.

use std::collections::VecDeque;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
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

/// How long a piece of work takes, which decides its queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lane {
    /// A render, a frame, a lobe: tens of milliseconds.
    Quick,
    /// A check (every mistake rendered), an albedo (a cubature): a second or more.
    Long,
}

/// The work waiting, by lane, and how much long work runs now.
struct Queues {
    quick: VecDeque<Job>,
    long: VecDeque<Job>,
    long_running: usize,
    /// No more work is taken: the workers finish what is queued and end.
    closed: bool,
}

/// What the workers share.
struct Shared {
    queues: Mutex<Queues>,
    ready: Condvar,
    /// How many may wait in each lane, and how many workers may run long work at once.
    capacity: usize,
    long_at_once: usize,
}

/// The pool of render workers.
pub struct Workers {
    shared: Arc<Shared>,
    threads: Mutex<Vec<JoinHandle<()>>>,
    /// Jobs queued or running now.
    pending: Arc<AtomicUsize>,
    deadline: Duration,
    /// A device error injected into the Nth job, for the fault tests (`VK_RENDER_SERVE_FAULT=N`).
    fault: Option<usize>,
    /// How long each job waits on its worker before it runs (`VK_RENDER_SERVE_HOLD_MS`): the stop test's
    /// requests must still be in flight when SIGTERM comes, and on a GPU a render is over in milliseconds.
    hold: Duration,
    jobs: AtomicUsize,
}

impl Workers {
    /// Opens `count` renderers with `options` (one after the other: an error names the first that failed),
    /// each prepared for `scenes`, and starts their threads; `queue` jobs of each lane may wait behind them.
    pub fn start(
        count: usize,
        queue: usize,
        deadline: Duration,
        options: &RendererOptions,
        scenes: &[&Scene],
    ) -> anyhow::Result<Self> {
        let shared = Arc::new(Shared {
            queues: Mutex::new(Queues {
                quick: VecDeque::new(),
                long: VecDeque::new(),
                long_running: 0,
                closed: false,
            }),
            ready: Condvar::new(),
            capacity: queue,
            long_at_once: count.saturating_sub(1).max(1),
        });
        let mut threads = Vec::new();
        for index in 0..count {
            let renderer = Renderer::for_scenes(options.clone(), scenes)?;
            let shared = shared.clone();
            // The first worker takes long work first, the others quick work: neither lane starves the other.
            let prefers = if index == 0 && count > 1 { Lane::Long } else { Lane::Quick };
            let thread = std::thread::Builder::new()
                .name(format!("render-{index}"))
                .spawn(move || work(renderer, &shared, prefers))?;
            threads.push(thread);
        }
        let fault = std::env::var("VK_RENDER_SERVE_FAULT").ok().and_then(|n| n.parse().ok());
        let hold = std::env::var("VK_RENDER_SERVE_HOLD_MS").ok().and_then(|ms| ms.parse().ok());
        Ok(Self {
            shared,
            threads: Mutex::new(threads),
            pending: Arc::new(AtomicUsize::new(0)),
            deadline,
            fault,
            hold: Duration::from_millis(hold.unwrap_or(0)),
            jobs: AtomicUsize::new(0),
        })
    }

    /// Runs `work` on a worker and returns its answer: 503 at once when the queue is full, 503 when it was
    /// not done within the deadline (the work, once started, finishes on its worker: a device wait has its
    /// own deadline), 500 when it panicked.
    pub async fn run<T: Send + 'static>(
        &self,
        lane: Lane,
        work: impl FnOnce(&mut Renderer) -> Result<T, ApiError> + Send + 'static,
    ) -> Result<T, ApiError> {
        let (answer, answered) = oneshot::channel::<Result<T, ApiError>>();
        let answer = Arc::new(Mutex::new(Some(answer)));
        let number = self.jobs.fetch_add(1, Ordering::Relaxed) + 1;
        let injected = self.fault == Some(number);
        let pending = self.pending.clone();
        let reply = answer.clone();
        let hold = self.hold;
        let job = Job {
            work: Box::new(move |renderer| {
                std::thread::sleep(hold);
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
        {
            let mut queues = lock(&self.shared.queues);
            if queues.closed {
                return Err(ApiError::new(
                    axum::http::StatusCode::SERVICE_UNAVAILABLE,
                    "the server is stopping".into(),
                ));
            }
            let waiting = match lane {
                Lane::Quick => &mut queues.quick,
                Lane::Long => &mut queues.long,
            };
            if waiting.len() >= self.shared.capacity {
                return Err(ApiError::busy(1));
            }
            waiting.push_back(job);
        }
        self.shared.ready.notify_one();
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

    /// Takes no more work, lets the workers finish what is queued, and waits for their threads (their
    /// renderers are destroyed on them).
    pub fn stop(&self) {
        lock(&self.shared.queues).closed = true;
        self.shared.ready.notify_all();
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

/// A worker's loop: the next job of the lane it prefers, else of the other (long work while fewer than
/// `long_at_once` workers run some), run when still wanted and within its deadline, until the queues close
/// and empty.
fn work(mut renderer: Renderer, shared: &Shared, prefers: Lane) {
    let order = match prefers {
        Lane::Quick => [Lane::Quick, Lane::Long],
        Lane::Long => [Lane::Long, Lane::Quick],
    };
    loop {
        let (job, lane) = {
            let mut queues = lock(&shared.queues);
            'wait: loop {
                for lane in order {
                    let job = match lane {
                        Lane::Quick => queues.quick.pop_front(),
                        Lane::Long if queues.long_running < shared.long_at_once => queues.long.pop_front(),
                        Lane::Long => None,
                    };
                    if let Some(job) = job {
                        if lane == Lane::Long {
                            queues.long_running += 1;
                        }
                        break 'wait (job, lane);
                    }
                }
                if queues.closed && queues.quick.is_empty() && queues.long.is_empty() {
                    return;
                }
                queues = shared.ready.wait(queues).unwrap_or_else(std::sync::PoisonError::into_inner);
            }
        };
        if (job.wanted)() && Instant::now() <= job.deadline {
            (job.work)(&mut renderer);
            if let Some(invalid) = renderer.take_invalid_values() {
                log::warn!("{invalid}");
            }
        }
        if lane == Lane::Long {
            lock(&shared.queues).long_running -= 1;
            // Another worker may take long work now.
            shared.ready.notify_all();
        }
    }
}
