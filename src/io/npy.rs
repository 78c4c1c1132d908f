//! NumPy `.npy` arrays: label maps (`uint32`) and distance maps (`float32`),
//! row-major with shape `[height, width]`.

use std::{fs::File, io::BufWriter, path::Path};

use npyz::WriterBuilder;

use crate::error::{Error, Result};

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes `data` (row-major) as an `.npy` array of `shape`.
pub fn write<T>(path: &Path, shape: &[u64], data: &[T]) -> Result<()>
where
    T: npyz::Serialize + npyz::AutoSerialize + Copy,
{
    let expected: u64 = shape.iter().product();
    if expected != data.len() as u64 {
        return Err(Error::InvalidInput(format!(
            "array of {} values does not have shape {shape:?}",
            data.len()
        )));
    }
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    let mut writer = npyz::WriteOptions::new()
        .default_dtype()
        .shape(shape)
        .writer(BufWriter::new(file))
        .begin_nd()
        .map_err(|e| io_error(path, e))?;
    writer
        .extend(data.iter().copied())
        .map_err(|e| io_error(path, e))?;
    writer.finish().map_err(|e| io_error(path, e))
}

/// Reads an `.npy` array: its shape and values.
pub fn read<T: npyz::Deserialize>(path: &Path) -> Result<(Vec<u64>, Vec<T>)> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let array = npyz::NpyFile::new(&bytes[..]).map_err(|e| io_error(path, e))?;
    let shape = array.shape().to_vec();
    let data = array.into_vec().map_err(|e| io_error(path, e))?;
    Ok((shape, data))
}
