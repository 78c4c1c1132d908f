//! The command line: outputs that load, and clear errors with a non-zero exit.

use std::{
    path::{Path, PathBuf},
    process::Command,
};

use pixgeo_io::npy;

mod interpolate;
mod lloyd;
mod magnitudes;
mod memory;
mod outputs;
mod parity;
mod power;
mod problems;
mod transaction;
mod transform;
mod voronoi;

fn pixgeo<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> (bool, String, String) {
    outcome(Command::new(env!("CARGO_BIN_EXE_pixgeo")).args(args))
}

/// Runs `command` to its end: (success, stdout, stderr).
fn outcome(command: &mut Command) -> (bool, String, String) {
    let out = command.output().expect("run pixgeo");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A `--json` answer: the envelope checked against cli/schema/envelope.json and
/// its result against cli/schema/COMMAND.json; returns the envelope's result.
fn answer(stdout: &str, command: &str) -> serde_json::Value {
    let envelope = enveloped(stdout, command);
    envelope["result"].clone()
}

/// The whole envelope of a `--json` answer, checked as [`answer`] does.
fn enveloped(stdout: &str, command: &str) -> serde_json::Value {
    let schema = |name: &str| -> serde_json::Value {
        let path = format!("{}/schema/{name}.json", env!("CARGO_MANIFEST_DIR"));
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
    };
    let v: serde_json::Value = serde_json::from_str(stdout).unwrap();
    let check = |schema: &serde_json::Value, value: &serde_json::Value, what: &str| {
        let validator = jsonschema::validator_for(schema).unwrap();
        let errors: Vec<String> = validator
            .iter_errors(value)
            .map(|e| e.to_string())
            .collect();
        assert!(errors.is_empty(), "{what}: {errors:?}\n{stdout}");
    };
    check(&schema("envelope"), &v, "envelope");
    check(&schema(command), &v["result"], command);
    assert_eq!(v["command"], command);
    assert_eq!(v["pixgeo_version"], env!("CARGO_PKG_VERSION"));
    v
}

fn temp(name: &str) -> PathBuf {
    // Cargo's folder for integration tests' files: reused by each run, removed
    // by `cargo clean`.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A path in a folder that no test makes, so it exists on no machine.
fn missing(name: &str) -> String {
    let path = temp("never-made").join(name);
    assert!(!path.exists(), "{} exists", path.display());
    path.to_str().unwrap().to_string()
}

/// Writes `data` to `path` as an `.npy` array of `shape`: a raster for the
/// commands to read.
fn write_npy<T: npyz::Serialize + npyz::AutoSerialize + Copy>(
    path: &Path,
    shape: &[u64],
    data: &[T],
) {
    pixgeo_reference::npy::write(path, shape, data).unwrap();
}
