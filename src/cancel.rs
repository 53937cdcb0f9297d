//! Cooperative cancellation: a shared flag that long computations (beam paths, PRB paths,
//! fits, selections) check between units of work, so the UI can stop them within
//! milliseconds. Sits at the bottom of the crate: every layer may use it.
//!
//! Shaped like bottom's `CancellationToken`: cloning shares the flag; nothing is ever
//! un-cancelled (a new job gets a new token).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A shared flag that stops a running computation.
#[derive(Debug, Clone, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A fresh token, not cancelled.
    pub fn new() -> CancelToken {
        CancelToken::default()
    }

    /// A token nobody cancels, for work short enough to need none (one shot, bounded by its
    /// effort budget): it spares each such shot the allocation of a fresh token. Never call
    /// [`CancelToken::cancel`] on it.
    pub(crate) fn never() -> &'static CancelToken {
        static NEVER: std::sync::LazyLock<CancelToken> = std::sync::LazyLock::new(CancelToken::new);
        &NEVER
    }

    /// Asks every holder of a clone of this token to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`CancelToken::cancel`] has been called on any clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The shared flag itself, for what can only set a flag (a signal handler: the CLI
    /// cancels its command on Ctrl-C by registering this flag for SIGINT).
    pub fn flag(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_flag() {
        let a = CancelToken::new();
        let b = a.clone();
        assert!(!b.is_cancelled());
        a.cancel();
        assert!(b.is_cancelled());
        assert!(!CancelToken::new().is_cancelled());
    }
}
