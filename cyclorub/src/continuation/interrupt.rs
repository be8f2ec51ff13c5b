//! A request from outside the driver (Ctrl-C, a notebook, a supervisor) to
//! stop a branch between two points. The branch keeps every point accepted
//! before it and stops with [`StopReason::Interrupted`](super::StopReason).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A flag shared between a driver and whoever may stop it: clones share
/// it, so a signal handler or another thread raises the clone it holds.
#[derive(Clone, Debug, Default)]
pub struct Interrupt {
    flag: Arc<AtomicBool>,
}

impl Interrupt {
    /// A flag not raised.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks every driver holding this flag (or a clone) to stop before its
    /// next point.
    pub fn raise(&self) {
        self.flag.store(true, Ordering::SeqCst);
    }

    /// Whether the stop was asked for.
    pub fn raised(&self) -> bool {
        self.flag.load(Ordering::SeqCst)
    }
}
