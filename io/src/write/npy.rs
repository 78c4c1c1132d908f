//! NumPy `.npy` arrays: label maps (`uint32`) and distance maps (`float32`),
//! row-major with shape `[height, width]`, written in one go or streamed row band
//! by row band.

use std::{fs::File, io::BufWriter, path::Path};

use npyz::WriterBuilder;
use pixgeo::{Error, Result};

use super::output::OutputFile;

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        cause: source,
    }
}

/// An `.npy` file being written value by value in row-major order.
pub struct NpyStream<T: npyz::Serialize + npyz::AutoSerialize + Copy> {
    output: OutputFile,
    writer: npyz::NpyWriter<T, BufWriter<File>>,
    remaining: u64,
}

impl<T: npyz::Serialize + npyz::AutoSerialize + Copy> NpyStream<T> {
    /// Creates `path` (named `*.npy`) for an array of `shape`; the file appears
    /// only when [`NpyStream::finish`] succeeds.
    pub fn create(path: &Path, shape: &[u64]) -> Result<Self> {
        let (output, file) = OutputFile::create(path, "npy", "arrays")?;
        let writer = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(BufWriter::new(file))
            .begin_nd()
            .map_err(|e| io_error(path, e))?;
        Ok(Self {
            output,
            writer,
            remaining: shape.iter().product(),
        })
    }

    /// Appends values.
    pub fn write(&mut self, data: &[T]) -> Result<()> {
        if data.len() as u64 > self.remaining {
            return Err(Error::malformed(format!(
                "{}: more values than the array's shape holds",
                self.output.path().display()
            )));
        }
        self.remaining -= data.len() as u64;
        self.writer
            .extend(data.iter().copied())
            .map_err(|e| io_error(self.output.path(), e))
    }

    /// Finishes the file; every value of the shape must have been written.
    pub fn finish(self) -> Result<()> {
        if self.remaining != 0 {
            return Err(Error::malformed(format!(
                "{}: {} values missing",
                self.output.path().display(),
                self.remaining
            )));
        }
        self.writer
            .finish()
            .map_err(|e| io_error(self.output.path(), e))?;
        self.output.commit()
    }
}

/// Writes `data` (row-major) as an `.npy` array of `shape`.
pub fn write<T>(path: &Path, shape: &[u64], data: &[T]) -> Result<()>
where
    T: npyz::Serialize + npyz::AutoSerialize + Copy,
{
    let expected: u64 = shape.iter().product();
    if expected != data.len() as u64 {
        return Err(Error::malformed(format!(
            "array of {} values does not have shape {shape:?}",
            data.len()
        )));
    }
    let mut stream = NpyStream::create(path, shape)?;
    stream.write(data)?;
    stream.finish()
}
