//! Cancellation of work on the CPU. A caller that can be interrupted (Python's
//! Ctrl-C, C's `pixgeo_context_cancel`) runs the work [`within`] a flag; long
//! CPU steps take a watch of it in the calling thread, look at it between
//! pieces of work (in worker threads too) and stop with [`Error::Cancelled`].
//! Work on the device looks at its machine's flag at every run.

use std::{
    cell::RefCell,
    sync::{
        atomic::{AtomicBool, Ordering},
        Arc,
    },
};

use crate::{Error, Result};

thread_local! {
    static FLAG: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// Runs `work` on this thread with `flag` as its cancellation flag.
pub(crate) fn within<T>(flag: Arc<AtomicBool>, work: impl FnOnce() -> T) -> T {
    let before = FLAG.with(|f| f.replace(Some(flag)));
    let result = work();
    FLAG.with(|f| *f.borrow_mut() = before);
    result
}

/// The calling thread's cancellation flag (none: never cancelled), to look
/// at from any thread.
#[derive(Clone, Default)]
pub(crate) struct Watch(Option<Arc<AtomicBool>>);

impl Watch {
    /// The flag the calling thread runs within.
    pub(crate) fn current() -> Self {
        Self(FLAG.with(|f| f.borrow().clone()))
    }

    pub(crate) fn cancelled(&self) -> bool {
        self.0.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// [`Error::Cancelled`] once the flag is set.
    pub(crate) fn check(&self) -> Result<()> {
        match self.cancelled() {
            true => Err(Error::Cancelled),
            false => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::transform::{distance_transform, TransformOptions};

    #[test]
    fn cpu_work_within_a_set_flag_is_cancelled_and_without_it_runs() {
        let mut features = vec![false; 64 * 64];
        features[0] = true;
        let options = TransformOptions::new();
        let flag = Arc::new(AtomicBool::new(true));
        let cancelled = within(flag.clone(), || {
            distance_transform(&features, 64, 64, &options)
        });
        assert!(matches!(cancelled, Err(Error::Cancelled)));
        flag.store(false, Ordering::Relaxed);
        let done = within(flag, || distance_transform(&features, 64, 64, &options)).unwrap();
        assert_eq!(done.distances[64 + 1], 2f64.sqrt());
        // Outside any flag, nothing cancels.
        assert!(!Watch::current().cancelled());
    }
}
