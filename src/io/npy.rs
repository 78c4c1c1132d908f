//! NumPy `.npy` arrays: label maps (`uint32`) and distance maps (`float32`),
//! row-major with shape `[height, width]`, written in one go or streamed row band
//! by row band.

use std::{fs::File, io::BufWriter, path::Path};

use npyz::WriterBuilder;

use super::output::OutputFile;
use crate::error::{Error, Result};

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
            return Err(Error::InvalidInput(format!(
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
            return Err(Error::InvalidInput(format!(
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
        return Err(Error::InvalidInput(format!(
            "array of {} values does not have shape {shape:?}",
            data.len()
        )));
    }
    let mut stream = NpyStream::create(path, shape)?;
    stream.write(data)?;
    stream.finish()
}

/// Reads an `.npy` array: its shape and values.
pub fn read<T: npyz::Deserialize>(path: &Path) -> Result<(Vec<u64>, Vec<T>)> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let array = npyz::NpyFile::new(&bytes[..]).map_err(|e| io_error(path, e))?;
    let shape = array.shape().to_vec();
    let data = array.into_vec().map_err(|e| io_error(path, e))?;
    Ok((shape, data))
}

/// Reads a numeric `.npy` array (floats or integers of any width) as `f64`.
pub fn read_f64(path: &Path) -> Result<(Vec<u64>, Vec<f64>)> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let parse = |e: std::io::Error| Error::Parse {
        path: path.to_path_buf(),
        message: format!("not a NumPy array: {e}"),
    };
    let array = npyz::NpyFile::new(&bytes[..]).map_err(parse)?;
    let shape = array.shape().to_vec();
    let fortran = array.order() == npyz::Order::Fortran;
    let descr = array.dtype().descr();
    // `descr` is the header's Python literal, quotes included: `'<f8'`.
    let values = match descr.trim_matches('\'').trim_start_matches(['<', '|', '=']) {
        "f8" => array.into_vec::<f64>().map_err(parse)?,
        "f4" => widen(array.into_vec::<f32>().map_err(parse)?),
        "i8" => {
            let wide = array.into_vec::<i64>().map_err(parse)?;
            // Beyond 2^53 an integer has no f64 of its own: refuse, never round.
            if let Some(v) = wide.iter().find(|v| v.unsigned_abs() > 1 << 53) {
                return Err(Error::Parse {
                    path: path.to_path_buf(),
                    message: format!("{v} is beyond 2^53 and would not be read exactly"),
                });
            }
            wide.into_iter().map(|v| v as f64).collect()
        }
        "i4" => widen(array.into_vec::<i32>().map_err(parse)?),
        "u4" => widen(array.into_vec::<u32>().map_err(parse)?),
        "i2" => widen(array.into_vec::<i16>().map_err(parse)?),
        "u2" => widen(array.into_vec::<u16>().map_err(parse)?),
        "u1" => widen(array.into_vec::<u8>().map_err(parse)?),
        "i1" => widen(array.into_vec::<i8>().map_err(parse)?),
        "b1" => widen(array.into_vec::<bool>().map_err(parse)?),
        _ => {
            return Err(Error::Parse {
                path: path.to_path_buf(),
                message: format!(
                    "arrays of dtype {descr} are not read: use float64, float32, bool or little-endian integers"
                ),
            })
        }
    };
    if fortran && shape.len() == 2 {
        // Column-major on disk: give the rows in order.
        let (rows, columns) = (shape[0] as usize, shape[1] as usize);
        let row_major = (0..rows * columns)
            .map(|k| values[(k % columns) * rows + k / columns])
            .collect();
        return Ok((shape, row_major));
    }
    Ok((shape, values))
}

fn widen<T: Into<f64>>(values: Vec<T>) -> Vec<f64> {
    values.into_iter().map(Into::into).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_dtype_read_as_f64_comes_back() {
        let dir = std::env::temp_dir().join(format!("pixgeo-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.npy");
        write(&path, &[2, 2], &[1.5f64, -2.0, 0.0, 1e300]).unwrap();
        assert_eq!(
            read_f64(&path).unwrap(),
            (vec![2, 2], vec![1.5, -2.0, 0.0, 1e300])
        );
        write(&path, &[3], &[0u8, 7, 255]).unwrap();
        assert_eq!(read_f64(&path).unwrap().1, [0.0, 7.0, 255.0]);
        write(&path, &[2], &[true, false]).unwrap();
        assert_eq!(read_f64(&path).unwrap().1, [1.0, 0.0]);
        write(&path, &[2], &[-3i32, 4]).unwrap();
        assert_eq!(read_f64(&path).unwrap().1, [-3.0, 4.0]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
