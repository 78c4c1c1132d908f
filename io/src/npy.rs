//! NumPy `.npy` arrays read as sites and masks: any numeric dtype as `f64`.

use pixgeo::memory::Gather;
use std::path::Path;

use pixgeo::error::{Error, Result};

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        cause: source,
    }
}

/// Reads an `.npy` array: its shape and values.
pub fn read<T: npyz::Deserialize>(path: &Path) -> Result<(Vec<u64>, Vec<T>)> {
    super::decoding::decoding(path, "NumPy", || read_typed(path))?
}

fn read_typed<T: npyz::Deserialize>(path: &Path) -> Result<(Vec<u64>, Vec<T>)> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let array = npyz::NpyFile::new(&bytes[..]).map_err(|e| io_error(path, e))?;
    let shape = array.shape().to_vec();
    room_for(path, &shape, &bytes, std::mem::size_of::<T>() as u64)?;
    let data = array.into_vec().map_err(|e| io_error(path, e))?;
    Ok((shape, data))
}

/// Refuses an array whose header declares more values than its file holds
/// (`bytes` its whole content), or more than this process can hold as
/// values of `each` bytes, before they are taken.
fn room_for(path: &Path, shape: &[u64], bytes: &[u8], each: u64) -> Result<()> {
    let count = shape.iter().try_fold(1u64, |n, &d| n.checked_mul(d));
    let held = bytes.len() as u64;
    match count {
        Some(n) if n <= held => pixgeo::memory::reserve(n.saturating_mul(each), || {
            format!("{}: {n} values", path.display())
        }),
        _ => Err(Error::Parse {
            path: path.to_path_buf(),
            message: format!(
                "the header declares an array of shape {shape:?}, more values than the file's \
                 {held} bytes hold"
            ),
        }),
    }
}

/// Reads a numeric `.npy` array (floats, integers of any width or bools) as
/// `f64`.
pub fn read_f64(path: &Path) -> Result<(Vec<u64>, Vec<f64>)> {
    super::decoding::decoding(path, "NumPy", || read_widened(path, true))?
}

/// [`read_f64`] for coordinates and values: a bool array, whose 0 and 1
/// would be read as numbers, is refused.
pub fn read_numbers(path: &Path) -> Result<(Vec<u64>, Vec<f64>)> {
    super::decoding::decoding(path, "NumPy", || read_widened(path, false))?
}

fn read_widened(path: &Path, bools: bool) -> Result<(Vec<u64>, Vec<f64>)> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let parse = |e: std::io::Error| Error::Parse {
        path: path.to_path_buf(),
        message: format!("not a NumPy array: {e}"),
    };
    let array = npyz::NpyFile::new(&bytes[..]).map_err(parse)?;
    let shape = array.shape().to_vec();
    let fortran = array.order() == npyz::Order::Fortran;
    // The values as they are read (up to 8 bytes), as doubles, and again
    // reordered where the file holds columns first.
    room_for(path, &shape, &bytes, if fortran { 24 } else { 16 })?;
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
            wide.into_iter().map(|v| v as f64).gather("array values")?
        }
        "i4" => widen(array.into_vec::<i32>().map_err(parse)?),
        "u4" => widen(array.into_vec::<u32>().map_err(parse)?),
        "i2" => widen(array.into_vec::<i16>().map_err(parse)?),
        "u2" => widen(array.into_vec::<u16>().map_err(parse)?),
        "u1" => widen(array.into_vec::<u8>().map_err(parse)?),
        "i1" => widen(array.into_vec::<i8>().map_err(parse)?),
        "b1" if bools => widen(array.into_vec::<bool>().map_err(parse)?),
        "b1" => {
            return Err(Error::Parse {
                path: path.to_path_buf(),
                message: "a bool array holds no coordinates or values: give float64 or integers"
                    .into(),
            })
        }
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
            .gather("row major")?;
        return Ok((shape, row_major));
    }
    Ok((shape, values))
}

#[expect(
    clippy::disallowed_methods,
    reason = "the array the header declared, whose room was reserved before it was read"
)]
fn widen<T: Into<f64>>(values: Vec<T>) -> Vec<f64> {
    values.into_iter().map(Into::into).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write<T: npyz::Serialize + npyz::AutoSerialize + Copy>(
        path: &Path,
        shape: &[u64],
        data: &[T],
    ) {
        pixgeo_reference::npy::write(path, shape, data).unwrap();
    }

    #[test]
    fn every_dtype_read_as_f64_comes_back() {
        let dir = std::env::temp_dir().join(format!("pixgeo-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.npy");
        write(&path, &[2, 2], &[1.5f64, -2.0, 0.0, 1e300]);
        assert_eq!(
            read_f64(&path).unwrap(),
            (vec![2, 2], vec![1.5, -2.0, 0.0, 1e300])
        );
        write(&path, &[3], &[0u8, 7, 255]);
        assert_eq!(read_f64(&path).unwrap().1, [0.0, 7.0, 255.0]);
        write(&path, &[2], &[true, false]);
        assert_eq!(read_f64(&path).unwrap().1, [1.0, 0.0]);
        write(&path, &[2], &[-3i32, 4]);
        assert_eq!(read_f64(&path).unwrap().1, [-3.0, 4.0]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A header that declares 4 GB of values over a file of a few bytes is
    /// refused before anything is taken.
    #[test]
    fn a_header_larger_than_its_file_is_refused() {
        let dir = std::env::temp_dir().join(format!("pixgeo-npy-big-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.npy");
        write(&path, &[4, 2], &[0.0f64; 8]);
        let bytes = std::fs::read(&path).unwrap();
        let at = bytes.windows(5).position(|w| w == b"(4, 2").unwrap();
        let mut patched = bytes.clone();
        // The header's padding of spaces takes the longer shape.
        let big = b"(268435456, 2";
        patched.splice(at..at + 5, big.iter().copied());
        let pad = patched.iter().position(|&b| b == b'\n').unwrap();
        patched.drain(pad - (big.len() - 5)..pad);
        std::fs::write(&path, &patched).unwrap();
        for error in [
            read_f64(&path).unwrap_err().to_string(),
            read::<f64>(&path).unwrap_err().to_string(),
        ] {
            assert!(error.contains("more values than the file"), "{error}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
