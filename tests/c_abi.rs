//! The C ABI: the header matches the code, and a C program using it builds, runs,
//! and checks its results.

use std::{path::Path, process::Command};

const MANIFEST: &str = env!("CARGO_MANIFEST_DIR");

fn generated_header() -> String {
    let root = Path::new(MANIFEST);
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut out = Vec::new();
    // Only the ABI module: the rest of the crate is not part of the C interface.
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(root.join("src/ffi/mod.rs"))
        .generate()
        .expect("cbindgen parses src/ffi/")
        .write(&mut out);
    String::from_utf8(out).expect("UTF-8 header")
}

#[test]
fn header_matches_the_code() {
    let path = Path::new(MANIFEST).join("include/pixgeo.h");
    let fresh = generated_header();
    if std::env::var("PIXGEO_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &fresh).unwrap();
    }
    let current = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        current == fresh,
        "include/pixgeo.h is out of date with src/ffi/: run PIXGEO_BLESS=1 cargo test --test c_abi"
    );
}

/// The directory holding `libpixgeo.so`: the profile directory of this test binary.
fn library_dir() -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent()
        .and_then(Path::parent)
        .expect("target/<profile>/deps/<test>")
        .to_path_buf()
}

/// Builds `examples/c/voronoi.c` with the system C compiler against the cdylib,
/// once for all tests.
fn build_c_example() -> std::path::PathBuf {
    static BUILT: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    BUILT.get_or_init(compile_c_example).clone()
}

fn compile_c_example() -> std::path::PathBuf {
    let root = Path::new(MANIFEST);
    let lib = library_dir();
    // `cargo test` builds only the rlib; the C example links the cdylib.
    let mut cargo = Command::new(env!("CARGO"));
    cargo.args(["build", "--lib"]).current_dir(root);
    if lib.ends_with("release") {
        cargo.arg("--release");
    }
    assert!(
        cargo.status().expect("run cargo").success(),
        "cargo build --lib failed"
    );
    assert!(
        lib.join("libpixgeo.so").exists(),
        "{} has no libpixgeo.so",
        lib.display()
    );
    let exe = lib.join("voronoi-c");
    let status = Command::new("cc")
        .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-O1", "-g"])
        .arg("-I")
        .arg(root.join("include"))
        .arg(root.join("examples/c/voronoi.c"))
        .arg("-L")
        .arg(&lib)
        .args(["-lpixgeo", "-lm"])
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-o")
        .arg(&exe)
        .status()
        .expect("a C compiler `cc` (tools/setup installs gcc)");
    assert!(status.success(), "the C example does not compile");
    exe
}

#[test]
fn c_example_builds_runs_and_checks_its_results() {
    let exe = build_c_example();
    let out = Command::new(&exe).output().expect("run the C example");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("all checks passed"), "{stdout}");
}

/// memcheck through `examples/c/memcheck`: no invalid access and no leak of
/// pixgeo's, after suppressing the reports `examples/c/valgrind.supp` explains
/// (the validation layer is off: under valgrind it would take minutes).
#[test]
fn c_example_is_clean_under_valgrind() {
    let exe = build_c_example();
    // The command the example ships, so that a user's run is the tests' run.
    let out = Command::new(Path::new(MANIFEST).join("examples/c/memcheck"))
        .arg(&exe)
        .env_remove("PIXGEO_VALIDATION")
        .output()
        .expect("valgrind (tools/setup installs it)");
    let report = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "memcheck found problems:\n{report}");
    assert!(report.contains("ERROR SUMMARY: 0 errors"), "{report}");
}
