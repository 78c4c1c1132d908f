//! What a GPU researcher sees of the machine's work.
//!
//! Every section of a run (a rendering pass, a dispatch, a copy) carries a
//! debug-utils label, and every draw inside a rendering pass a label of its
//! program, so RenderDoc or Nsight show the thesis's steps by name. Images,
//! buffers, pipelines and shader modules carry object names.
//!
//! A machine given a [`Profiler`] also times each section on the device with
//! timestamp queries, and each run on the host; the [`Timeline`] sums the
//! device's milliseconds by pass (`pixgeo_io::trace` writes it as a Chrome
//! trace, which Perfetto opens).

use std::{
    collections::BTreeMap,
    sync::{Arc, Mutex},
    time::Instant,
};

/// One section of a run as the device timed it.
#[derive(Clone, Debug, PartialEq)]
pub struct PassSpan {
    /// What the section did: `render: A+B`, `dispatch K`, … by the programs' names.
    pub label: String,
    /// When it began, in milliseconds since the profiler was made: the host's
    /// time at the submission plus the device's time since the submission's
    /// first timestamp (the two clocks are aligned once per submission).
    pub start_ms: f64,
    /// Its duration on the device; `None` where the queue has no timestamps.
    pub gpu_ms: Option<f64>,
}

/// A span of host time: a machine's run (record, submit and wait), or a phase
/// the caller marks with [`Profiler::phase`].
#[derive(Clone, Debug, PartialEq)]
pub struct HostSpan {
    pub name: String,
    /// Milliseconds since the profiler was made.
    pub start_ms: f64,
    pub ms: f64,
}

/// What a [`Profiler`] has recorded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timeline {
    pub passes: Vec<PassSpan>,
    pub host: Vec<HostSpan>,
}

impl Timeline {
    /// The device's milliseconds summed by pass label (sections the device did
    /// not time are left out).
    pub fn gpu_ms_by_pass(&self) -> BTreeMap<String, f64> {
        let mut sums = BTreeMap::new();
        for pass in &self.passes {
            if let Some(ms) = pass.gpu_ms {
                *sums.entry(pass.label.clone()).or_insert(0.0) += ms;
            }
        }
        sums
    }
}

/// Records what the machines it is given do; clones share one timeline, so
/// one profiler can watch several machines and the caller's own phases.
#[derive(Clone, Debug)]
pub struct Profiler {
    started: Instant,
    timeline: Arc<Mutex<Timeline>>,
}

impl Default for Profiler {
    fn default() -> Self {
        Self::new()
    }
}

impl Profiler {
    pub fn new() -> Self {
        Self {
            started: Instant::now(),
            timeline: Arc::default(),
        }
    }

    /// A copy of what has been recorded so far.
    pub fn timeline(&self) -> Timeline {
        self.lock().clone()
    }

    /// Marks a host phase that lasts until the returned guard is dropped.
    pub fn phase(&self, name: impl Into<String>) -> Phase<'_> {
        Phase {
            profiler: self,
            name: name.into(),
            started: Instant::now(),
        }
    }

    pub(crate) fn ms_since_start(&self, at: Instant) -> f64 {
        at.saturating_duration_since(self.started).as_secs_f64() * 1e3
    }

    pub(crate) fn record_host(&self, name: impl Into<String>, from: Instant, to: Instant) {
        let span = HostSpan {
            name: name.into(),
            start_ms: self.ms_since_start(from),
            ms: to.saturating_duration_since(from).as_secs_f64() * 1e3,
        };
        self.lock().host.push(span);
    }

    pub(crate) fn record_passes(&self, passes: impl IntoIterator<Item = PassSpan>) {
        self.lock().passes.extend(passes);
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Timeline> {
        self.timeline.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A host phase in progress; recorded when dropped.
pub struct Phase<'p> {
    profiler: &'p Profiler,
    name: String,
    started: Instant,
}

impl Drop for Phase<'_> {
    fn drop(&mut self) {
        let name = std::mem::take(&mut self.name);
        self.profiler
            .record_host(name, self.started, Instant::now());
    }
}
