//! Progress bars on stderr for steps that can take seconds: shown only on a
//! terminal, and not beside a `--json` answer.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use pixgeo::Control;

pub struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    /// A bar named `message`, unless stderr is no terminal, `json` is set, or `-q`.
    pub fn new(message: &str, json: bool) -> Self {
        let bar = Self::shown(json).then(|| {
            ProgressBar::new(1)
                .with_style(
                    ProgressStyle::with_template("{msg} {bar:40} {percent}% {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_bar()),
                )
                .with_message(message.to_string())
        });
        Self { bar }
    }

    /// A spinner with the time spent, for a step whose share done is not
    /// known (a few device passes over a large picture), under the same
    /// conditions as [`Self::new`].
    pub fn working(message: &str, json: bool) -> Self {
        let bar = Self::shown(json).then(|| {
            let bar = ProgressBar::new_spinner()
                .with_style(
                    ProgressStyle::with_template("{msg} {spinner} {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                )
                .with_message(message.to_string());
            bar.enable_steady_tick(std::time::Duration::from_millis(200));
            bar
        });
        Self { bar }
    }

    fn shown(json: bool) -> bool {
        !json && !crate::quiet() && std::io::stderr().is_terminal()
    }

    /// A control for the library's options that moves this bar.
    pub fn control(&self) -> Control {
        match self.bar.clone() {
            Some(bar) => Control::new().progress(move |done, total| show(&bar, done, total)),
            None => Control::new(),
        }
    }
}

fn show(bar: &ProgressBar, done: u64, total: u64) {
    bar.set_length(total);
    bar.set_position(done);
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
