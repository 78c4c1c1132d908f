//! Points handed to the peers' scripts as `.npy` arrays (n×2 float64).

use std::path::Path;

use glam::DVec2;

/// Writes `points` to `path` as an n×2 float64 array.
pub fn write_npy(path: &Path, points: &[DVec2]) -> anyhow::Result<()> {
    use npyz::WriterBuilder;
    let mut bytes = Vec::new();
    let mut writer = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[points.len() as u64, 2])
        .writer(&mut bytes)
        .begin_nd()?;
    writer.extend(points.iter().flat_map(|p| [p.x, p.y]))?;
    writer.finish()?;
    std::fs::write(path, bytes)?;
    Ok(())
}
