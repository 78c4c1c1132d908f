//! Points handed to the peers' scripts as `.npy` arrays (n×2 float64).

use std::path::Path;

use glam::DVec2;

/// Writes `points` to `path` as an n×2 float64 array.
pub fn write_npy(path: &Path, points: &[DVec2]) -> anyhow::Result<()> {
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
    Ok(pixgeo_reference::npy::write(
        path,
        &[points.len() as u64, 2],
        &flat,
    )?)
}
