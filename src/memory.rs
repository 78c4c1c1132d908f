//! Host memory asked for before it is taken. An allocation that fails aborts
//! the process (the CLI, a C host, a Python interpreter alike), so work that
//! scales with its input checks first that the process can have what it will
//! hold, and is refused with the size it needs otherwise.

use crate::{Error, Result};

/// Refuses work that will hold `bytes` of host memory at once when this
/// process cannot have them: more than its control group allows, or more than
/// an allocation of that size can get (its address-space limit, the kernel's
/// overcommit rule). The probe reserves address space only and gives it back.
pub fn reserve(bytes: u64, what: impl FnOnce() -> String) -> Result<()> {
    let probe =
        || usize::try_from(bytes).is_ok_and(|b| Vec::<u8>::new().try_reserve_exact(b).is_ok());
    // Reading the control group's files costs more than a small allocation.
    let within_group = bytes < 1 << 20 || bytes <= cgroup_room();
    if within_group && probe() {
        Ok(())
    } else {
        Err(Error::HostMemory {
            what: what(),
            bytes,
        })
    }
}

/// [`reserve`] for a picture of `width` × `height` pixels holding
/// `bytes_per_pixel` bytes for each.
pub fn reserve_picture(width: u32, height: u32, bytes_per_pixel: u64, what: &str) -> Result<()> {
    let pixels = width as u64 * height as u64;
    reserve(pixels.saturating_mul(bytes_per_pixel), || {
        format!("{what} of {width}x{height} pixels ({bytes_per_pixel} bytes a pixel)")
    })
}

/// Host memory an algorithm may take per site, at most: the ordinary Voronoi
/// diagram's cones, footprints and sort keys (docs/tuning.md has the figures).
pub const MEMORY_PER_SITE: u64 = 512;

/// Refuses `n` sites when the process cannot have their working memory
/// ([`MEMORY_PER_SITE`] bytes each): where sites enter pixgeo, before they
/// are copied.
pub fn reserve_sites(n: usize) -> Result<()> {
    reserve((n as u64).saturating_mul(MEMORY_PER_SITE), || {
        format!("{n} sites ({MEMORY_PER_SITE} bytes a site)")
    })
}

/// A vector of `len` copies of `value`, or the [`reserve`] error where the
/// process cannot have it. Allocations that grow with the input go through
/// here, [`room`] or [`Gather`]: clippy refuses `vec!`, `Vec::with_capacity`
/// and `collect` elsewhere in the library (`clippy.toml`).
#[allow(clippy::disallowed_macros)]
pub fn filled<T: Clone>(len: usize, value: T, what: &str) -> Result<Vec<T>> {
    reserve_values::<T>(len, what)?;
    Ok(vec![value; len])
}

/// An empty vector with room for `len` values, or the [`reserve`] error
/// where the process cannot have it.
#[allow(clippy::disallowed_methods)]
pub fn room<T>(len: usize, what: &str) -> Result<Vec<T>> {
    reserve_values::<T>(len, what)?;
    Ok(Vec::with_capacity(len))
}

/// Collecting that asks for its room first: the library's `collect`, which
/// clippy refuses elsewhere in it (`clippy.toml`).
pub trait Gather: Iterator + Sized {
    /// Collects into `C` once the process can have the most values the
    /// iterator says it yields (its upper bound, or its lower where it has
    /// none), or gives the [`reserve`] error.
    #[allow(clippy::disallowed_methods)]
    fn gather<C: FromIterator<Self::Item>>(self, what: &str) -> Result<C> {
        let (low, high) = self.size_hint();
        reserve_values::<Self::Item>(high.unwrap_or(low), what)?;
        Ok(self.collect())
    }

    /// [`Gather::gather`] of fallible values: the first error, or them all.
    fn try_gather<T, C: FromIterator<T>>(self, what: &str) -> Result<C>
    where
        Self: Iterator<Item = Result<T>>,
    {
        self.gather::<Result<C>>(what)?
    }
}

impl<I: Iterator> Gather for I {}

/// Below this many bytes an allocation is not probed: a process that cannot
/// have it cannot go on anyway, and the probe would double the cost of the
/// small vectors built in loops.
const UNPROBED_BYTES: u64 = 1 << 16;

fn reserve_values<T>(len: usize, what: &str) -> Result<()> {
    let bytes = (len as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    if bytes < UNPROBED_BYTES {
        return Ok(());
    }
    reserve(bytes, || format!("{what} ({len} values)"))
}

/// What this process's control group (cgroup v2) leaves it; unlimited
/// elsewhere.
fn cgroup_room() -> u64 {
    let read = |name: &str| {
        std::fs::read_to_string(format!("/sys/fs/cgroup/{name}"))
            .ok()
            .and_then(|s| s.trim().parse::<u64>().ok())
    };
    match (read("memory.max"), read("memory.current")) {
        (Some(max), Some(current)) => max.saturating_sub(current),
        _ => u64::MAX,
    }
}

/// A size in the unit that shows it: "3.2 GB", "12.0 MB", "512 bytes".
pub fn amount(bytes: u64) -> String {
    match bytes {
        n if n >= 1_000_000_000 => format!("{:.1} GB", n as f64 / 1e9),
        n if n >= 1_000_000 => format!("{:.1} MB", n as f64 / 1e6),
        n if n >= 1_000 => format!("{:.1} kB", n as f64 / 1e3),
        n => format!("{n} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gather_refuses_what_no_process_can_hold_before_taking_any() {
        let huge = (0..u64::MAX / 4).map(|i| i as f64);
        match huge.gather::<Vec<f64>>("samples") {
            Err(Error::HostMemory { what, bytes }) => {
                assert!(what.starts_with("samples ("), "{what}");
                assert!(bytes >= 1 << 62);
            }
            other => panic!("{:?}", other.map(|v| v.len())),
        }
        let fallible = (0..u64::MAX / 4).map(|i| Ok(i as f64));
        assert!(matches!(
            fallible.try_gather::<_, Vec<f64>>("samples"),
            Err(Error::HostMemory { .. })
        ));
        let small: Vec<u32> = (0..5).gather("ids").unwrap();
        assert_eq!(small, [0, 1, 2, 3, 4]);
    }
}
