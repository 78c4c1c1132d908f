//! Progress bars on stderr for steps that can take seconds: shown only on a
//! terminal, and not beside a `--json` answer.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

pub struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    /// A bar named `message`, unless stderr is no terminal, `json` is set, or `-q`.
    pub fn new(message: &str, json: bool) -> Self {
        let bar = (!json && !crate::quiet() && std::io::stderr().is_terminal()).then(|| {
            ProgressBar::new(1)
                .with_style(
                    ProgressStyle::with_template("{msg} {bar:40} {percent}% {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_bar()),
                )
                .with_message(message.to_string())
        });
        Self { bar }
    }

    /// The library's `progress(done, total)` callback.
    pub fn report(&self, done: u64, total: u64) {
        if let Some(bar) = &self.bar {
            bar.set_length(total);
            bar.set_position(done);
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
