//! Seed pixels of digital Voronoi diagrams (Cao, Edelsbrunner and Tan 2015)
//! and the total order on (pixel, seed) pairs that breaks their ties: the
//! squared distance, then the pixel's and then the seed's coordinates,
//! lexicographically. Pixels are (x, y), x the column and y the row; two
//! pixels are neighbours if they share a side or a corner.

use crate::error::{Error, Result};

/// No colour.
pub const NONE: u32 = u32::MAX;

/// A seed pixel: its column and row.
pub type Seed = [i32; 2];

/// A (pixel, seed) pair's place in the total order: squared distance, then
/// the pixel's and the seed's coordinates.
pub type Priority = (i64, i32, i32, i32, i32);

/// The priority of colouring pixel `a` with the seed at `s`: smaller first.
pub fn priority(a: [i32; 2], s: Seed) -> Priority {
    let (dx, dy) = ((a[0] - s[0]) as i64, (a[1] - s[1]) as i64);
    (dx * dx + dy * dy, a[0], a[1], s[0], s[1])
}

/// A clear error for an empty texture, or a seed outside it or repeated.
pub fn check_seeds(width: u32, height: u32, seeds: &[Seed]) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::malformed("the texture has no pixels".into()));
    }
    let mut seen =
        crate::memory::filled(width as usize * height as usize, false, "the seeds' pixels")?;
    for (i, s) in seeds.iter().enumerate() {
        if s[0] < 0 || s[1] < 0 || s[0] >= width as i32 || s[1] >= height as i32 {
            return Err(Error::malformed(format!(
                "seed {i} at {s:?} lies outside the {width}x{height} texture"
            )));
        }
        let pixel = &mut seen[s[1] as usize * width as usize + s[0] as usize];
        if std::mem::replace(pixel, true) {
            return Err(Error::malformed(format!(
                "seed {i} at {s:?} repeats a seed pixel"
            )));
        }
    }
    Ok(())
}

/// The pixels around (x, y) inside a `width` x `height` texture.
pub fn neighbours(x: i32, y: i32, width: u32, height: u32) -> impl Iterator<Item = [i32; 2]> {
    (-1..=1)
        .flat_map(move |dy| (-1..=1).map(move |dx| [x + dx, y + dy]))
        .filter(move |&[a, b]| {
            (a, b) != (x, y) && a >= 0 && b >= 0 && a < width as i32 && b < height as i32
        })
}
