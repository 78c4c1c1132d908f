//! Output files written whole or not at all: the bytes go to a temporary file
//! beside the target, renamed over it only once every byte is written, so a
//! failure never leaves a half-written file nor clobbers an existing one.
//! Targets that are not regular files (`/dev/stdout`, `/dev/full`, a pipe) are
//! written in place, since renaming over them would replace the device.

use std::{
    fs::File,
    path::{Path, PathBuf},
};

use pixgeo::{Error, Result};

/// An output file being written; dropped without [`OutputFile::commit`], it
/// leaves nothing behind.
#[derive(Debug)]
pub struct OutputFile {
    target: PathBuf,
    /// The temporary file, while the output is not yet committed; `None` when
    /// the target is written in place.
    temporary: Option<PathBuf>,
}

impl OutputFile {
    /// Starts writing `path` if its name ends in `.{extension}` (any case),
    /// and returns the handle to write through (unbuffered: buffer it, and
    /// flush the buffer before [`OutputFile::commit`], so that every write error
    /// is seen).
    pub fn create(path: &Path, extension: &str, what: &str) -> Result<(Self, File)> {
        Self::create_any(path, &[extension], what)
    }

    /// [`OutputFile::create`] for a file named with any of `extensions`.
    pub fn create_any(path: &Path, extensions: &[&str], what: &str) -> Result<(Self, File)> {
        check_extensions(path, extensions, what)?;
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            cause: source,
        };
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file());
        if special {
            let file = File::options().write(true).open(path).map_err(io)?;
            return Ok((
                Self {
                    target: path.to_path_buf(),
                    temporary: None,
                },
                file,
            ));
        }
        let name = path
            .file_name()
            .ok_or_else(|| Error::InvalidInput(format!("{}: not a file name", path.display())))?;
        let mut temporary_name = std::ffi::OsString::from(".");
        temporary_name.push(name);
        temporary_name.push(format!(".pixgeo-{}.tmp", std::process::id()));
        let temporary = path.with_file_name(temporary_name);
        let file = File::create(&temporary).map_err(io)?;
        Ok((
            Self {
                target: path.to_path_buf(),
                temporary: Some(temporary),
            },
            file,
        ))
    }

    /// The path being written.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Puts the finished file in place of the target.
    pub fn commit(mut self) -> Result<()> {
        if let Some(temporary) = self.temporary.take() {
            std::fs::rename(&temporary, &self.target).map_err(|source| {
                let _ = std::fs::remove_file(&temporary);
                Error::Io {
                    path: self.target.clone(),
                    cause: source,
                }
            })?;
        }
        Ok(())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Some(temporary) = &self.temporary {
            let _ = std::fs::remove_file(temporary);
        }
    }
}

/// Writes a text file through an [`OutputFile`]: `body` writes into a buffer,
/// which is flushed, so that every write error is seen, before the file is put
/// in place.
pub fn write_text(
    path: &Path,
    extension: &str,
    what: &str,
    body: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<()> {
    let (output, file) = OutputFile::create(path, extension, what)?;
    let mut buffer = std::io::BufWriter::new(file);
    body(&mut buffer)
        .and_then(|()| std::io::Write::flush(&mut buffer))
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            cause: source,
        })?;
    output.commit()
}

/// Refuses a file name whose extension does not say the format written into
/// it: `-o map.jpg` would otherwise hold PNG bytes.
pub fn check_extension(path: &Path, extension: &str, what: &str) -> Result<()> {
    check_extensions(path, &[extension], what)
}

/// [`check_extension`] for a file that may be named with any of `extensions`.
pub fn check_extensions(path: &Path, extensions: &[&str], what: &str) -> Result<()> {
    if extension_among(path, extensions).is_some() || is_device(path) {
        return Ok(());
    }
    let dotted: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
    let named: Vec<String> = extensions.iter().map(|e| format!("*.{e}")).collect();
    Err(Error::InvalidInput(format!(
        "{}: {what} are written as {}; name the file {}",
        path.display(),
        dotted.join(" or "),
        named.join(" or ")
    )))
}

/// Which of `extensions` (any case) ends `path`'s name.
pub fn extension_among<'a>(path: &Path, extensions: &[&'a str]) -> Option<&'a str> {
    let extension = path.extension().and_then(|e| e.to_str())?;
    extensions
        .iter()
        .copied()
        .find(|e| e.eq_ignore_ascii_case(extension))
}

/// A path to an existing non-regular file (a device or a pipe), which takes any
/// format: `-o /dev/stdout`.
fn is_device(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Refuses two outputs of one command on the same path, which would leave one
/// overwritten by the other.
pub fn check_distinct<'a>(paths: impl IntoIterator<Item = (&'a str, &'a Path)>) -> Result<()> {
    let paths: Vec<_> = paths.into_iter().collect();
    for (i, (a_name, a)) in paths.iter().enumerate() {
        for (b_name, b) in &paths[i + 1..] {
            if a == b {
                return Err(Error::InvalidInput(format!(
                    "{a_name} and {b_name} both name {}; give each output its own file",
                    a.display()
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn nothing_is_left_unless_committed() {
        let dir = std::env::temp_dir().join(format!("pixgeo-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("a.npy");
        std::fs::write(&target, b"old").unwrap();
        {
            let (_out, mut file) = OutputFile::create(&target, "npy", "arrays").unwrap();
            file.write_all(b"half").unwrap();
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        let (out, mut file) = OutputFile::create(&target, "npy", "arrays").unwrap();
        file.write_all(b"new").unwrap();
        out.commit().unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        assert!(OutputFile::create(&dir.join("a.txt"), "npy", "arrays").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_full_device_is_an_error() {
        let (out, mut file) =
            OutputFile::create(Path::new("/dev/full"), "png", "pictures").unwrap();
        assert!(file.write_all(b"x").is_err());
        out.commit().unwrap();
    }

    #[test]
    fn one_path_for_two_outputs_is_refused() {
        let a = Path::new("x.npy");
        let b = Path::new("y.npy");
        assert!(check_distinct([("--labels", a), ("--distance", b)]).is_ok());
        let e = check_distinct([("--labels", a), ("--distance", a)]).unwrap_err();
        assert!(e.to_string().contains("--labels and --distance"));
    }
}
