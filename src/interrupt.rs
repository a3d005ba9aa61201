//! A request to stop a long computation early, for embedders that cannot kill the process (the Python
//! package turns Ctrl-C into one). The command line never sets it: its signals end the process.
//!
//! The request is process-wide and checked at safe points: between the exact mode's passes, the CPU
//! reference's rows, the albedo probe's refinements and `check`'s candidate renders. A computation that
//! sees it returns [`Error::Interrupted`] and leaves its renderer ready for the next call.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every computation in progress to stop at its next safe point.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Withdraws the request (once the interrupted computations have returned).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// `Err(Error::Interrupted)` when a stop was requested.
///
/// # Errors
/// `Error::Interrupted`.
pub fn check() -> Result<()> {
    if requested() {
        Err(Error::Interrupted)
    } else {
        Ok(())
    }
}
