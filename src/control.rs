//! How a caller follows and stops long work: one [`Control`] in a problem's
//! options carries the progress callback and the cancellation flag. A front
//! end that runs several problems under one flag (Python's Ctrl-C, C's
//! `pixgeo_context_cancel`) runs them all [`Control::run`].

use std::{
    fmt,
    sync::{atomic::AtomicBool, Arc},
};

use crate::cancel;

/// A progress callback, `report(done, total)`, callable from any thread.
pub type Report = dyn Fn(u64, u64) + Send + Sync;

/// Progress and cancellation for one call. The default reports nothing and
/// stops only when the work it runs within (see [`Control::run`]) is cancelled.
#[derive(Clone, Default)]
pub struct Control {
    progress: Option<Arc<Report>>,
    cancel: Option<Arc<AtomicBool>>,
}

impl Control {
    pub fn new() -> Self {
        Self::default()
    }

    /// Calls `report(done, total)` as the work goes on.
    pub fn progress(mut self, report: impl Fn(u64, u64) + Send + Sync + 'static) -> Self {
        self.progress = Some(Arc::new(report));
        self
    }

    /// Stops the work with [`crate::Error::Cancelled`] once `flag` is set.
    pub fn cancel(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel = Some(flag);
        self
    }

    /// Reports `done` of `total` to the progress callback, if any.
    pub fn report(&self, done: u64, total: u64) {
        if let Some(report) = &self.progress {
            report(done, total);
        }
    }

    /// Runs `work` on this thread within this control's cancellation flag;
    /// without one, within the flag the caller already runs within.
    pub fn run<T>(&self, work: impl FnOnce() -> T) -> T {
        match &self.cancel {
            Some(flag) => cancel::within(flag.clone(), work),
            None => work(),
        }
    }
}

impl fmt::Debug for Control {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Control")
            .field("progress", &self.progress.is_some())
            .field("cancel", &self.cancel.is_some())
            .finish()
    }
}

/// Two controls are the same when they share their callback and their flag.
impl PartialEq for Control {
    fn eq(&self, other: &Self) -> bool {
        same(&self.progress, &other.progress) && same(&self.cancel, &other.cancel)
    }
}

fn same<T: ?Sized>(a: &Option<Arc<T>>, b: &Option<Arc<T>>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => Arc::ptr_eq(a, b),
        (a, b) => a.is_none() && b.is_none(),
    }
}
