//! The commands of the README and the guide, run as a newcomer would paste
//! them: every `pixgeo` line of their shell blocks (and the README's `cargo run
//! -- ...`) must succeed on the sample inputs the repository ships, and write
//! what it names. In the guide, `$ pixgeo ...` lines of transcripts count too,
//! options in `[...]` are left out, and a trailing `# comment` or `> file` is
//! not part of the command.

use std::{path::Path, process::Command};

/// The repository: the README, the guide and the sample inputs.
const MANIFEST: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// The argument lists of the commands in `doc`'s code blocks (those marked
/// `sh` or unmarked).
fn commands(doc: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(Path::new(MANIFEST).join(doc)).unwrap();
    let mut block: Option<bool> = None; // Some(shell?) inside a block
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("```") {
            block = match block {
                None => Some(matches!(line.trim(), "```sh" | "```")),
                Some(_) => None,
            };
            continue;
        }
        if block != Some(true) {
            continue;
        }
        let line = line.strip_prefix("$ ").unwrap_or(line);
        let args = match (
            line.strip_prefix("pixgeo "),
            line.split_once("cargo run --release -- "),
        ) {
            (Some(args), _) => args,
            (None, Some((_, args))) => args,
            _ => continue,
        };
        let args = args.split(" #").next().unwrap_or_default();
        let args = args.split(" > ").next().unwrap_or_default();
        out.push(
            without_optional(args)
                .split_whitespace()
                .map(str::to_string)
                .collect(),
        );
    }
    out
}

/// `text` without its `[...]` groups (nested ones included).
fn without_optional(text: &str) -> String {
    let mut depth = 0;
    text.chars()
        .filter(|&c| {
            match c {
                '[' => depth += 1,
                ']' => depth -= 1,
                _ => return depth == 0,
            }
            false
        })
        .collect()
}

#[test]
fn every_readme_command_runs_on_the_shipped_samples() {
    run_all(&commands("README.md"), "readme");
}

#[test]
fn every_guide_command_runs_on_the_shipped_samples() {
    let commands = commands("docs/guide.md");
    assert!(commands.len() >= 30, "{commands:?}");
    run_all(&commands, "guide");
}

fn run_all(commands: &[Vec<String>], name: &str) {
    assert!(commands.len() >= 5, "{commands:?}");
    let dir = std::env::temp_dir().join(format!("pixgeo-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for args in commands {
        // Sample paths (also `polygon:examples/...`) are relative to the
        // checkout, outputs to the working folder.
        let args: Vec<String> = args
            .iter()
            .map(|a| match a.split_once("examples/") {
                Some((head, rest)) if head.is_empty() || head.ends_with(':') => {
                    format!("{head}{MANIFEST}/examples/{rest}")
                }
                _ => a.clone(),
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
            if flag == "--triangle" {
                assert!(dir.join(format!("{path}.node")).is_file());
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
