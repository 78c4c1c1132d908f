//! The README's commands, run as a newcomer would paste them: every `pixgeo`
//! line of its shell blocks (and the first command's `cargo run -- ...`) must
//! succeed on the sample inputs the repository ships, and write what it names.

use std::{path::Path, process::Command};

const MANIFEST: &str = env!("CARGO_MANIFEST_DIR");

/// The argument lists of the README's commands.
fn commands() -> Vec<Vec<String>> {
    let readme = std::fs::read_to_string(Path::new(MANIFEST).join("README.md")).unwrap();
    let mut in_shell = false;
    let mut out = Vec::new();
    for line in readme.lines() {
        if line.starts_with("```") {
            in_shell = line == "```sh";
            continue;
        }
        if !in_shell {
            continue;
        }
        let args = match (
            line.strip_prefix("pixgeo "),
            line.split_once("cargo run --release -- "),
        ) {
            (Some(args), _) => args,
            (None, Some((_, args))) => args,
            _ => continue,
        };
        out.push(args.split_whitespace().map(str::to_string).collect());
    }
    out
}

#[test]
fn every_readme_command_runs_on_the_shipped_samples() {
    let commands = commands();
    assert!(commands.len() >= 5, "{commands:?}");
    let dir = std::env::temp_dir().join(format!("pixgeo-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for args in commands {
        // Sample paths are relative to the checkout, outputs to the working folder.
        let args: Vec<String> = args
            .iter()
            .map(|a| match a.strip_prefix("examples/") {
                Some(rest) => format!("{MANIFEST}/examples/{rest}"),
                None => a.clone(),
            })
            .collect();
        let out = Command::new(env!("CARGO_BIN_EXE_pixgeo"))
            .args(&args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "pixgeo {}: {stderr}", args.join(" "));
        for (flag, path) in args.iter().zip(args.iter().skip(1)) {
            if ["-o", "--labels", "--distance"].contains(&flag.as_str()) {
                assert!(
                    dir.join(path).is_file(),
                    "pixgeo {}: no {path}",
                    args.join(" ")
                );
            }
            if flag == "--out" {
                assert!(dir.join(format!("{path}.node")).is_file());
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
