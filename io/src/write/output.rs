//! Output files written whole or not at all, and all of a command's together:
//! each goes to a temporary file beside its target, and only when the command
//! has finished every output are they renamed into place ([`finish`]). A
//! failure, a refusal or a signal (SIGINT, SIGTERM, SIGHUP) removes every
//! temporary file and leaves the targets as they were ([`abandon`]). Targets
//! that are not regular files (`/dev/stdout`, `/dev/full`, a pipe) are written
//! in place, since renaming over them would replace the device; a symbolic
//! link is written through, to the file it names.

use std::{
    fs::File,
    path::{Path, PathBuf},
    sync::Mutex,
};

use pixgeo::{Error, Result};

/// The command's outputs: the files being written, those finished and waiting
/// to be put in place, the targets (resolved) claimed by options and those
/// written, each with what named it, and the lines that tell of them.
#[derive(Default)]
struct Transaction {
    temporaries: Vec<PathBuf>,
    staged: Vec<(PathBuf, PathBuf)>,
    claimed: Vec<(PathBuf, String)>,
    written: Vec<(PathBuf, String)>,
    announced: Vec<PathBuf>,
    /// The option whose output goes to stdout (`-`).
    stdout: Option<String>,
    /// Whether the answer is printed as JSON, on stdout.
    json: bool,
}

static TRANSACTION: Mutex<Option<Transaction>> = Mutex::new(None);

fn with<T>(f: impl FnOnce(&mut Transaction) -> T) -> T {
    let mut guard = TRANSACTION.lock().unwrap_or_else(|e| e.into_inner());
    f(guard.get_or_insert_with(Transaction::default))
}

/// Claims `path` for the output `option` names: refused where another option
/// of the command names the same file (after following links and `.` and
/// `..`), or where its folder does not exist.
pub fn claim(path: &Path, option: &str) -> Result<()> {
    if is_stdout(path) || resolve(path).is_ok_and(|t| t == Path::new("/dev/stdout")) {
        return with(|t| match (&t.stdout, t.json) {
            (Some(other), _) if other != option => Err(Error::malformed(format!(
                "{other} and {option} both write to stdout; give one of them a file"
            ))),
            (_, true) => Err(Error::malformed(format!(
                "--json and {option} both write to stdout; give {option} a file"
            ))),
            _ => {
                t.stdout = Some(option.to_string());
                Ok(())
            }
        });
    }
    if is_device(path) {
        return Ok(());
    }
    let target = resolve(path)?;
    with(|t| match t.claimed.iter().find(|(p, _)| *p == target) {
        Some((_, other)) if other != option => Err(Error::malformed(format!(
            "{other} and {option} both name {}; give each output its own file",
            path.display()
        ))),
        Some(_) => Ok(()),
        None => {
            t.claimed.push((target, option.to_string()));
            Ok(())
        }
    })
}

/// The file `path` writes: the target of a link, in a folder that exists,
/// not a folder itself.
fn resolve(path: &Path) -> Result<PathBuf> {
    if let Ok(target) = std::fs::canonicalize(path) {
        if target.is_dir() {
            return Err(Error::malformed(format!(
                "{} is a folder; give the output a file name",
                path.display()
            )));
        }
        return Ok(target);
    }
    let name = path
        .file_name()
        .ok_or_else(|| Error::malformed(format!("{}: not a file name", path.display())))?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let folder = std::fs::canonicalize(parent).map_err(|_| {
        Error::malformed(format!(
            "{}: the folder {} does not exist",
            path.display(),
            parent.display()
        ))
    })?;
    Ok(folder.join(name))
}

/// Puts every finished output in place, in the order they were finished, and
/// returns those to tell of.
pub fn finish() -> Result<Vec<PathBuf>> {
    let (staged, announced) = with(|t| {
        t.claimed.clear();
        t.written.clear();
        (
            std::mem::take(&mut t.staged),
            std::mem::take(&mut t.announced),
        )
    });
    let mut renames = staged.into_iter();
    for (temporary, target) in renames.by_ref() {
        if let Err(source) = std::fs::rename(&temporary, &target) {
            let _ = std::fs::remove_file(&temporary);
            for (rest, _) in renames {
                let _ = std::fs::remove_file(rest);
            }
            return Err(Error::Io {
                path: target,
                cause: source,
            });
        }
        with(|t| t.temporaries.retain(|p| *p != temporary));
    }
    Ok(announced)
}

/// Removes every temporary file, finished or not: the targets stay as they
/// were.
pub fn abandon() {
    with(|t| {
        for path in t.temporaries.drain(..) {
            let _ = std::fs::remove_file(path);
        }
        *t = Transaction::default();
    });
}

/// Tells of `path` once the outputs are in place.
pub fn announce(path: &Path) {
    with(|t| t.announced.push(path.to_path_buf()));
}

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
        // Outputs that are not claimed up front take stdout as they open.
        if is_stdout(path) && !stdout_taken() {
            claim(path, what)?;
        }
        if is_device(path) {
            let device = if is_stdout(path) {
                Path::new("/dev/stdout")
            } else {
                path
            };
            let file = File::options().write(true).open(device).map_err(io)?;
            return Ok((
                Self {
                    target: path.to_path_buf(),
                    temporary: None,
                },
                file,
            ));
        }
        let target = resolve(path)?;
        with(|t| match t.written.iter().find(|(p, _)| *p == target) {
            Some((_, other)) => Err(Error::malformed(format!(
                "{} would be written twice, as {other} and as {what}; give each output \
                 its own file",
                path.display()
            ))),
            None => {
                t.written.push((target.clone(), what.to_string()));
                Ok(())
            }
        })?;
        let name = target.file_name().expect("a resolved file name");
        let mut temporary_name = std::ffi::OsString::from(".");
        temporary_name.push(name);
        temporary_name.push(format!(".pixgeo-{}.tmp", std::process::id()));
        let temporary = target.with_file_name(temporary_name);
        with(|t| t.temporaries.push(temporary.clone()));
        let file = File::create(&temporary).map_err(io)?;
        Ok((
            Self {
                target,
                temporary: Some(temporary),
            },
            file,
        ))
    }

    /// The path being written.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// A folder for scratch files that go with the output: its own, or the
    /// system's for a device such as `/dev/stdout`, written in place.
    pub fn scratch_folder(&self) -> PathBuf {
        match &self.temporary {
            Some(t) => t
                .parent()
                .map_or_else(std::env::temp_dir, Path::to_path_buf),
            None => std::env::temp_dir(),
        }
    }

    /// Marks the file finished: it is put in place with the command's other
    /// outputs by [`finish`].
    pub fn commit(mut self) -> Result<()> {
        if let Some(temporary) = self.temporary.take() {
            let target = self.target.clone();
            with(|t| t.staged.push((temporary, target)));
        }
        Ok(())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Some(temporary) = &self.temporary {
            let _ = std::fs::remove_file(temporary);
            with(|t| {
                t.temporaries.retain(|p| p != temporary);
                t.written.retain(|(p, _)| *p != self.target);
            });
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
    Err(Error::malformed(format!(
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
/// format: `-o /dev/stdout`, or `-`, stdout.
fn is_device(path: &Path) -> bool {
    is_stdout(path) || std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Whether `path` is `-`, as Unix tools name stdout.
fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Says whether the command prints its answer as JSON: stdout is then the
/// answer's, and no output may take it.
pub fn answers_as_json(json: bool) {
    with(|t| t.json = json);
}

/// Whether an output goes to stdout: answers then go to stderr.
pub fn stdout_taken() -> bool {
    with(|t| t.stdout.is_some())
}

/// Refuses two outputs of one command on the same file (after following links
/// and `.` and `..`), and outputs in folders that do not exist, before any
/// work: each option with its path, if given.
pub fn check_distinct<'a>(
    paths: impl IntoIterator<Item = (&'a str, Option<&'a Path>)>,
) -> Result<()> {
    paths
        .into_iter()
        .filter_map(|(option, path)| Some((option, path?)))
        .try_for_each(|(option, path)| claim(path, option))
}

/// Held by the tests that use the process's transaction, one at a time.
#[cfg(test)]
pub static TRANSACTION_TESTS: Mutex<()> = Mutex::new(());

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// One test, as the transaction is the process's: outputs in place only
    /// once finished, nothing left when dropped or abandoned, one file named
    /// twice refused however it is spelled.
    #[test]
    fn outputs_are_put_in_place_together() {
        let _one = TRANSACTION_TESTS.lock().unwrap_or_else(|e| e.into_inner());
        let dir = std::env::temp_dir().join(format!("pixgeo-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.npy"), dir.join("b.npy"));
        std::fs::write(&a, b"old").unwrap();
        {
            let (_out, mut file) = OutputFile::create(&a, "npy", "arrays").unwrap();
            file.write_all(b"half").unwrap();
        }
        assert_eq!(std::fs::read(&a).unwrap(), b"old");
        let (out, mut file) = OutputFile::create(&a, "npy", "arrays").unwrap();
        file.write_all(b"new").unwrap();
        out.commit().unwrap();
        let (out, mut file) = OutputFile::create(&b, "npy", "arrays").unwrap();
        file.write_all(b"more").unwrap();
        out.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"old");
        finish().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"new");
        assert_eq!(std::fs::read(&b).unwrap(), b"more");
        let (out, _) = OutputFile::create(&a, "npy", "arrays").unwrap();
        out.commit().unwrap();
        abandon();
        assert_eq!(std::fs::read(&a).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        assert!(OutputFile::create(&dir.join("a.txt"), "npy", "arrays").is_err());
        let dotted = dir.join(".").join("a.npy");
        let ok = check_distinct([("--labels", Some(a.as_path())), ("--distance", Some(&b))]);
        assert!(ok.is_ok());
        let e = check_distinct([("--labels", Some(a.as_path())), ("--ties", Some(&dotted))]);
        assert!(e.unwrap_err().to_string().contains("--labels and --ties"));
        let e = check_distinct([("-o", Some(dir.join("no/x.png").as_path()))]).unwrap_err();
        assert!(e.to_string().contains("does not exist"));
        abandon();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_full_device_is_an_error() {
        let _one = TRANSACTION_TESTS.lock().unwrap_or_else(|e| e.into_inner());
        let (out, mut file) =
            OutputFile::create(Path::new("/dev/full"), "png", "pictures").unwrap();
        assert!(file.write_all(b"x").is_err());
        out.commit().unwrap();
    }
}
