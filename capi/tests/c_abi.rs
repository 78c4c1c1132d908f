//! The C ABI: the header matches the code, and a C program using it builds, runs,
//! and checks its results.

use std::{path::Path, process::Command};

const MANIFEST: &str = env!("CARGO_MANIFEST_DIR");

fn generated_header() -> String {
    let root = Path::new(MANIFEST);
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(root.join("src/lib.rs"))
        .generate()
        .expect("cbindgen parses capi/src/")
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
        "capi/include/pixgeo.h is out of date with capi/src/: run PIXGEO_BLESS=1 cargo test -p pixgeo-capi"
    );
}

/// Installs the C library with `tools/install` into a prefix inside this test
/// profile's target directory, once for all tests: the library this test
/// build made, so nothing is compiled twice. The tests build the C examples as
/// a user would, from the prefix with pkg-config alone.
fn installed_prefix() -> &'static Path {
    static PREFIX: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    PREFIX.get_or_init(|| {
        let exe = std::env::current_exe().expect("test binary path");
        // target/<profile>/deps/<test>, beside the library's own build.
        let deps = exe.parent().expect("target/<profile>/deps");
        let prefix = deps.parent().expect("target/<profile>").join("c-prefix");
        let status = Command::new(Path::new(MANIFEST).join("../tools/install"))
            .arg(&prefix)
            .arg("--built")
            .arg(deps)
            .status()
            .expect("run tools/install");
        assert!(status.success(), "tools/install failed");
        prefix
    })
}

/// `pkg-config ARGS pixgeo` against the installed prefix, split into words.
fn pkg_config(args: &[&str]) -> Vec<String> {
    let out = Command::new("pkg-config")
        .args(args)
        .arg("pixgeo")
        .env("PKG_CONFIG_PATH", installed_prefix().join("lib/pkgconfig"))
        .output()
        .expect("pkg-config (tools/setup installs it)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .expect("UTF-8 flags")
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// How an example links pixgeo.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Linking {
    /// `pkg-config --cflags --libs pixgeo`: the shared library.
    Shared,
    /// `pkg-config --static --libs pixgeo`, naming the archive: the static
    /// library and its `Libs.private`.
    Static,
}

/// Builds `capi/examples/NAME.c` with the system C compiler, once per linking.
fn build_c_example(name: &'static str, linking: Linking) -> std::path::PathBuf {
    type Built = std::collections::HashMap<(&'static str, Linking), std::path::PathBuf>;
    static BUILT: std::sync::Mutex<Option<Built>> = std::sync::Mutex::new(None);
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    built
        .get_or_insert_with(Default::default)
        .entry((name, linking))
        .or_insert_with(|| compile_c_example(name, linking))
        .clone()
}

fn compile_c_example(name: &str, linking: Linking) -> std::path::PathBuf {
    let prefix = installed_prefix();
    let mut flags = pkg_config(&["--cflags"]);
    flags.extend(match linking {
        Linking::Shared => pkg_config(&["--libs"]),
        Linking::Static => pkg_config(&["--static", "--libs"])
            .into_iter()
            .map(|f| {
                if f == "-lpixgeo" {
                    "-l:libpixgeo.a".into()
                } else {
                    f
                }
            })
            .collect(),
    });
    let exe = prefix.join(format!("{name}-{linking:?}").to_lowercase());
    let status = Command::new("cc")
        .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-O1", "-g"])
        .arg(Path::new(MANIFEST).join(format!("examples/{name}.c")))
        .args(&flags)
        .arg("-lm")
        .arg("-o")
        .arg(&exe)
        .status()
        .expect("a C compiler `cc` (tools/setup installs gcc)");
    assert!(
        status.success(),
        "capi/examples/{name}.c does not compile with {flags:?}"
    );
    exe
}

/// Runs a built example, finding the shared library where it was installed.
fn run_example(command: &mut Command) {
    let out = command
        .env("LD_LIBRARY_PATH", installed_prefix().join("lib"))
        .output()
        .expect("run the C example");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("all checks passed"), "{stdout}");
}

#[test]
fn the_installed_library_names_its_soname() {
    let lib = installed_prefix().join("lib");
    let version = env!("CARGO_PKG_VERSION");
    let soname = "libpixgeo.so.0.1";
    assert!(
        version.starts_with("0.1."),
        "update the SONAME with the version"
    );
    assert_eq!(
        std::fs::read_link(lib.join("libpixgeo.so")).unwrap(),
        Path::new(soname)
    );
    assert_eq!(
        std::fs::read_link(lib.join(soname)).unwrap(),
        Path::new(&format!("libpixgeo.so.{version}"))
    );
    assert!(
        lib.join("libpixgeo.a").exists() && installed_prefix().join("include/pixgeo.h").exists()
    );
}

#[test]
fn shapes_example_builds_runs_and_checks_its_results() {
    for linking in [Linking::Shared, Linking::Static] {
        run_example(&mut Command::new(build_c_example("shapes", linking)));
    }
}

#[test]
fn a_host_with_little_memory_gets_a_status_not_an_abort() {
    run_example(&mut Command::new(build_c_example(
        "memory",
        Linking::Shared,
    )));
}

#[test]
fn c_example_builds_runs_and_checks_its_results() {
    for linking in [Linking::Shared, Linking::Static] {
        run_example(&mut Command::new(build_c_example("voronoi", linking)));
    }
}

/// memcheck through `capi/examples/memcheck`: no invalid access and no leak of
/// pixgeo's, after suppressing the reports `capi/examples/valgrind.supp` explains
/// (the validation layer is off: under valgrind it would take minutes).
#[test]
fn c_example_is_clean_under_valgrind() {
    for name in ["voronoi", "shapes"] {
        let exe = build_c_example(name, Linking::Shared);
        // The command the example ships, so that a user's run is the tests' run.
        let out = Command::new(Path::new(MANIFEST).join("examples/memcheck"))
            .arg(&exe)
            .env_remove("PIXGEO_VALIDATION")
            .env("LD_LIBRARY_PATH", installed_prefix().join("lib"))
            .output()
            .expect("valgrind (tools/setup installs it)");
        let report = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success(),
            "memcheck found problems in {name}:\n{report}"
        );
        assert!(report.contains("ERROR SUMMARY: 0 errors"), "{report}");
    }
}
