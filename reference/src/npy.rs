//! `.npy` files as NumPy writes them, for the tests to hand pixgeo's readers
//! and for the peers' scripts to read.

use std::path::Path;

use npyz::WriterBuilder;

/// Writes `data` (row-major) to `path` as an array of `shape`.
pub fn write<T: npyz::Serialize + npyz::AutoSerialize + Copy>(
    path: &Path,
    shape: &[u64],
    data: &[T],
) -> std::io::Result<()> {
    let mut bytes = Vec::new();
    let mut writer = npyz::WriteOptions::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut bytes)
        .begin_nd()?;
    writer.extend(data.iter().copied())?;
    writer.finish()?;
    std::fs::write(path, bytes)
}
