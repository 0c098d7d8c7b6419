//! Cooperative cancellation of a running detection.
//!
//! A [`StopToken`] is a shared flag. A detection run on a rayon pool built by
//! [`StopToken::pool_builder`] (or on the current thread inside [`StopToken::scope`]) checks it
//! at task granularity in the methods' parallel loops: once [`StopToken::stop`] is called, the
//! remaining particles are skipped and the detection returns [`DetectError::Interrupted`]
//! instead of labels. A detection elsewhere (rayon's global pool, a pool built without a token)
//! never sees a token and always runs to the end.
//!
//! The check is one thread-local read and one relaxed atomic load per particle or task, so a
//! method's loop costs the same with or without a token. What is stopped is the work still
//! queued: a particle being classified finishes first, so a stop takes effect within the time
//! of one particle's classification per worker.
//!
//! ```
//! use boundary_core::stop::{self, StopToken};
//! use boundary_core::DetectError;
//!
//! let token = StopToken::new();
//! let pool = token.pool_builder().num_threads(2).build().unwrap();
//! token.stop();
//! let outcome = pool.install(|| {
//!     // What a method's loop does between its tasks.
//!     stop::check()
//! });
//! assert_eq!(outcome, Err(DetectError::Interrupted));
//! ```

use crate::DetectError;
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

thread_local! {
    /// The token of the pool (or [`StopToken::scope`]) this thread works for, if any.
    static CURRENT: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// A flag that stops the detections running under it (module docs).
#[derive(Debug, Clone, Default)]
pub struct StopToken {
    flag: Arc<AtomicBool>,
}

impl StopToken {
    /// A token not yet stopped.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks every detection running under this token to stop. Idempotent; callable from any
    /// thread (a signal handler's thread, a UI thread).
    pub fn stop(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }

    /// Whether [`stop`](Self::stop) was called.
    pub fn is_stopped(&self) -> bool {
        self.flag.load(Ordering::Relaxed)
    }

    /// A rayon pool builder whose worker threads check this token: run the detection with
    /// `builder.build()?.install(|| detector.detect(&set, r))`. Further settings (the number
    /// of threads) are the caller's.
    pub fn pool_builder(&self) -> rayon::ThreadPoolBuilder {
        let flag = self.flag.clone();
        rayon::ThreadPoolBuilder::new().start_handler(move |_| {
            let flag = flag.clone();
            CURRENT.with(|current| *current.borrow_mut() = Some(flag));
        })
    }

    /// Runs `f` on the current thread with this token as its own (work that `f` sends to a
    /// rayon pool checks that pool's token instead). The previous token of the thread is back
    /// when `f` returns, and when it panics.
    pub fn scope<R>(&self, f: impl FnOnce() -> R) -> R {
        /// Puts the thread's previous token back when dropped, on return or unwinding.
        struct Restore(Option<Arc<AtomicBool>>);
        impl Drop for Restore {
            fn drop(&mut self) {
                let previous = self.0.take();
                CURRENT.with(|current| *current.borrow_mut() = previous);
            }
        }
        let _restore = Restore(CURRENT.with(|current| current.replace(Some(self.flag.clone()))));
        f()
    }
}

/// Whether the token of the current thread (if it has one) was stopped: a method's loop skips
/// its remaining work when this is true, and then returns [`check`]'s error.
#[inline]
pub fn requested() -> bool {
    CURRENT.with(|current| {
        current
            .borrow()
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed))
    })
}

/// `Err(DetectError::Interrupted)` when [`requested`], else `Ok(())`: the line after a
/// method's parallel loop, so that a stopped loop's partial results are never returned.
#[inline]
pub fn check() -> Result<(), DetectError> {
    if requested() {
        Err(DetectError::Interrupted)
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::sync::atomic::AtomicUsize;

    #[test]
    fn without_a_token_nothing_is_requested() {
        assert!(!requested());
        assert_eq!(check(), Ok(()));
        // The global pool has no token either.
        assert!(!rayon::iter::repeat_n((), 64).any(|()| requested()));
    }

    #[test]
    fn a_stopped_token_is_seen_by_every_worker_of_its_pool_and_not_by_others() {
        let token = StopToken::new();
        let pool = token.pool_builder().num_threads(3).build().unwrap();
        assert!(!pool.install(|| (0..1000).into_par_iter().any(|_| requested())));
        token.stop();
        assert!(token.is_stopped());
        assert!(pool.install(|| (0..1000).into_par_iter().all(|_| requested())));
        assert_eq!(pool.install(check), Err(DetectError::Interrupted));
        // Another pool, and this thread, are not stopped.
        let other = StopToken::new()
            .pool_builder()
            .num_threads(2)
            .build()
            .unwrap();
        assert_eq!(other.install(check), Ok(()));
        assert_eq!(check(), Ok(()));
    }

    #[test]
    fn a_stop_during_a_loop_skips_the_remaining_work() {
        let token = StopToken::new();
        let pool = token.pool_builder().num_threads(2).build().unwrap();
        let done = AtomicUsize::new(0);
        let n = 100_000;
        let outcome = pool.install(|| {
            (0..n).into_par_iter().with_max_len(16).for_each(|i| {
                if requested() {
                    return;
                }
                if i == 0 {
                    token.stop();
                }
                done.fetch_add(1, Ordering::Relaxed);
            });
            check()
        });
        assert_eq!(outcome, Err(DetectError::Interrupted));
        let done = done.into_inner();
        assert!(
            done < n,
            "{done} of {n} particles classified after the stop"
        );
    }

    #[test]
    fn scope_sets_the_token_of_this_thread_and_restores_it() {
        let token = StopToken::new();
        token.stop();
        assert_eq!(token.scope(check), Err(DetectError::Interrupted));
        assert_eq!(check(), Ok(()));
        // Nested scopes restore the outer token; a panic in a scope restores it too.
        let outer = StopToken::new();
        outer.scope(|| {
            assert_eq!(token.scope(check), Err(DetectError::Interrupted));
            assert_eq!(check(), Ok(()));
            let panicked =
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| token.scope(|| panic!())));
            assert!(panicked.is_err());
            assert_eq!(
                check(),
                Ok(()),
                "the stopped inner token is gone after the panic"
            );
            outer.stop();
            assert_eq!(
                check(),
                Err(DetectError::Interrupted),
                "the outer token is back"
            );
        });
        assert_eq!(check(), Ok(()));
    }
}
