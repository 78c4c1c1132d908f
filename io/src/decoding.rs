//! Third-party decoders (PNG, TIFF, NumPy) run isolated: a panic inside one,
//! a decoder's bug on a file it cannot read, becomes an error naming the
//! file instead of a crash of the command line, the C host or Python.

use std::{
    cell::Cell,
    panic::{catch_unwind, AssertUnwindSafe},
    path::Path,
    sync::Once,
};

use pixgeo::{Error, Result};

thread_local! {
    /// Whether this thread is inside a decoder: its panics are answered, not
    /// reported by the panic hook.
    static DECODING: Cell<bool> = const { Cell::new(false) };
}

/// Runs `decode` on the file at `path` with `decoder` (its name for the
/// message): its answer, or a [`Error::Parse`] where it panicked.
pub fn decoding<T>(path: &Path, decoder: &str, decode: impl FnOnce() -> T) -> Result<T> {
    static QUIET: Once = Once::new();
    QUIET.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !DECODING.get() {
                previous(info);
            }
        }));
    });
    let outer = DECODING.replace(true);
    let outcome = catch_unwind(AssertUnwindSafe(decode));
    DECODING.set(outer);
    outcome.map_err(|payload| {
        let why = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Error::Parse {
            path: path.to_path_buf(),
            message: format!("the {decoder} decoder failed on this file ({why}); it may be damaged, or written in a way the decoder cannot read"),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panicking_decoder_is_an_error_naming_the_file() {
        let e = decoding(Path::new("x.tif"), "TIFF", || -> u8 {
            panic!("assertion failed")
        })
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("x.tif: the TIFF decoder failed") && e.contains("assertion failed"),
            "{e}"
        );
        assert_eq!(decoding(Path::new("x.tif"), "TIFF", || 7).unwrap(), 7);
    }
}
