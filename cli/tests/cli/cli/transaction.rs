//! Outputs as one transaction: a refused or failed run, and one stopped by a
//! signal, leaves every earlier file as it was and no temporary file behind.

use std::path::{Path, PathBuf};

use super::{pixgeo, temp, write_npy};

/// A fresh folder for one case, holding each of `names` as a sentinel file.
fn folder(case: &str, names: &[&str]) -> PathBuf {
    let dir = temp(&format!("transaction-{case}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for name in names {
        std::fs::write(dir.join(name), "sentinel").unwrap();
    }
    dir
}

/// Every sentinel survived and nothing else is in the folder.
fn untouched(dir: &Path, names: &[&str], what: &str) {
    for name in names {
        let text = std::fs::read(dir.join(name)).unwrap_or_default();
        assert_eq!(text, b"sentinel", "{what}: {name} was replaced");
    }
    let mut left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !names.contains(&n.as_str()))
        .collect();
    left.sort();
    assert!(left.is_empty(), "{what}: left behind {left:?}");
}

/// `args` with each `@name` made a path in `dir`.
fn in_folder(dir: &Path, args: &[&str]) -> Vec<String> {
    args.iter()
        .map(|a| match a.strip_prefix('@') {
            Some(name) => dir.join(name).to_string_lossy().into_owned(),
            None => a.to_string(),
        })
        .collect()
}

/// Runs `args` in a fresh folder (names there written as `@name`): refused
/// before any work (nothing on stderr before the error), with the sentinels
/// untouched.
fn refused(case: &str, names: &[&str], args: &[&str], expected: &str) {
    let dir = folder(case, names);
    let (ok, _, stderr) = pixgeo(&in_folder(&dir, args));
    assert!(!ok, "{case}: accepted");
    assert!(stderr.contains(expected), "{case}: {stderr}");
    assert!(
        stderr.starts_with("Error:"),
        "{case}: work before the refusal: {stderr}"
    );
    untouched(&dir, names, case);
}

#[test]
fn a_refused_output_leaves_the_others_as_they_were() {
    let sites = ["--random", "20", "--size", "32"];
    let with = |rest: &[&'static str]| -> Vec<&'static str> {
        let mut all = vec!["voronoi"];
        all.extend(sites);
        all.extend(rest);
        all
    };
    // An output name refused, before the other is drawn.
    refused(
        "world-file",
        &["g.png", "w.txt"],
        &with(&["-o", "@g.png", "--world-file", "@w.txt"]),
        "world files",
    );
    let settle = ["settle", "--random", "5", "--size", "32"];
    let join = |head: &[&'static str], rest: &[&'static str]| [head, rest].concat();
    refused(
        "settle-world-file",
        &["g.png", "w.txt"],
        &join(&settle, &["-o", "@g.png", "--world-file", "@w.txt"]),
        "world files",
    );
    refused(
        "settle-area",
        &["a.npy", "g.jpg"],
        &join(&settle, &["--area", "@a.npy", "-o", "@g.jpg"]),
        "pictures",
    );
    let alpha = ["alpha", "--random", "30", "--alpha", "0", "--size", "32"];
    refused(
        "alpha",
        &["h.npy", "g.jpg"],
        &join(&alpha, &["--hull", "@h.npy", "-o", "@g.jpg"]),
        "pictures",
    );
}

#[test]
fn an_output_that_cannot_be_written_leaves_the_others() {
    let sites = ["voronoi", "--random", "20", "--size", "32"];
    let join = |rest: &[&'static str]| [&sites[..], rest].concat();
    for (case, rest) in [
        (
            "world-file",
            &["-o", "@g.png", "--world-file", "@no/w.pgw"][..],
        ),
        (
            "cells",
            &[
                "-o",
                "@g.png",
                "--labels",
                "@l.npy",
                "--cells",
                "@no/c.geojson",
            ],
        ),
        ("trace", &["-o", "@g.png", "--trace", "@no/t.json"]),
    ] {
        refused(case, &["g.png", "l.npy"], &join(rest), "does not exist");
    }
    refused(
        "geojson",
        &["g.png"],
        &[
            "delaunay",
            "--random",
            "20",
            "-o",
            "@g.png",
            "--geojson",
            "@no/t.geojson",
        ],
        "does not exist",
    );
    let dir = folder("medial-axis", &["d.npy"]);
    let mask = dir.join("mask.npy");
    write_npy(&mask, &[8, 8], &[1u8; 64]);
    let (ok, _, stderr) = pixgeo(&[
        "transform",
        "--mask",
        mask.to_str().unwrap(),
        "--distance",
        dir.join("d.npy").to_str().unwrap(),
        "--medial-axis",
        dir.join("no/m.npy").to_str().unwrap(),
    ]);
    std::fs::remove_file(&mask).unwrap();
    assert!(!ok && stderr.contains("does not exist"), "{stderr}");
    untouched(&dir, &["d.npy"], "medial axis");
}

#[test]
fn one_file_named_twice_is_refused_however_it_is_spelled() {
    let sites = ["voronoi", "--random", "20", "--size", "32"];
    let join = |rest: &[&'static str]| [&sites[..], rest].concat();
    refused(
        "dot",
        &["s.npy"],
        &join(&["--labels", "@s.npy", "--distance", "@./s.npy"]),
        "both name",
    );
    // A trace is JSON, and named so: it cannot take the cells' file.
    refused(
        "trace-twice",
        &["c.geojson"],
        &join(&["--cells", "@c.geojson", "--trace", "@c.geojson"]),
        "traces are written as .json",
    );
    let dir = folder("link-twice", &["s.npy"]);
    std::os::unix::fs::symlink("s.npy", dir.join("t.npy")).unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--random",
        "20",
        "--labels",
        dir.join("s.npy").to_str().unwrap(),
        "--distance",
        dir.join("t.npy").to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("both name"), "{stderr}");
    std::fs::remove_file(dir.join("t.npy")).unwrap();
    untouched(&dir, &["s.npy"], "a link to another output");
}

#[test]
fn a_link_is_written_through_to_its_file() {
    let dir = folder("link", &["real.png"]);
    let link = dir.join("link.png");
    std::os::unix::fs::symlink("real.png", &link).unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--random",
        "20",
        "--size",
        "32",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    let bytes = std::fs::read(dir.join("real.png")).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
}

#[test]
fn a_signal_removes_every_temporary_file() {
    // 128 plus the signal's number, as shells and supervisors expect.
    for (signal, code) in [("INT", 130), ("TERM", 143), ("HUP", 129)] {
        let names = ["l.npy", "d.npy"];
        let dir = folder(&format!("signal-{signal}"), &names);
        let child = std::process::Command::new(env!("CARGO_BIN_EXE_pixgeo"))
            .args([
                "voronoi", "--random", "3000", "--size", "6000", "--device", "cpu", "--metric",
                "l1",
            ])
            .arg("--labels")
            .arg(dir.join("l.npy"))
            .arg("--distance")
            .arg(dir.join("d.npy"))
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Into the computing or the writing; the run takes several seconds.
        std::thread::sleep(std::time::Duration::from_millis(1500));
        let killed = std::process::Command::new("kill")
            .arg(format!("-{signal}"))
            .arg(child.id().to_string())
            .status()
            .unwrap();
        assert!(killed.success());
        let status = child.wait_with_output().unwrap().status;
        assert_eq!(status.code(), Some(code), "SIG{signal}");
        untouched(&dir, &names, &format!("SIG{signal}"));
    }
}

#[test]
fn the_same_input_gives_the_same_bytes() {
    // Every output of a few commands, run three times: byte for byte alike,
    // whatever the threads' and the device's timing (the dual of a flooding
    // came in the order its invocations finished, and Delaunay meshes with it).
    let dir = folder("bytes", &[]);
    let mask = dir.join("mask.npy");
    let cells: Vec<u8> = (0..64 * 48)
        .map(|k| u8::from(k % 7 == 0 || k % 13 == 0))
        .collect();
    write_npy(&mask, &[48, 64], &cells);
    let runs: [&[&str]; 5] = [
        &[
            "voronoi",
            "--random",
            "400",
            "--size",
            "96",
            "--labels",
            "@a.npy",
            "--distance",
            "@b.npy",
            "--cells",
            "@c.geojson",
            "-o",
            "@d.png",
        ],
        &[
            "delaunay",
            "--random",
            "20000",
            "--geojson",
            "@e.geojson",
            "--triangle",
            "@f",
        ],
        &[
            "settle", "--random", "20", "--size", "48", "--area", "@g.npy", "-o", "@h.png",
        ],
        &[
            "alpha", "--random", "200", "--alpha", "-0.02", "--size", "64", "--hull", "@i.npy",
        ],
        &[
            "transform",
            "--mask",
            "@mask.npy",
            "--distance",
            "@j.npy",
            "--indices",
            "@k.npy",
            "--medial-axis",
            "@l.npy",
        ],
    ];
    let outputs = [
        "a.npy",
        "b.npy",
        "c.geojson",
        "d.png",
        "e.geojson",
        "f.node",
        "f.ele",
        "g.npy",
        "h.png",
        "i.npy",
        "j.npy",
        "k.npy",
        "l.npy",
    ];
    let mut first: Vec<Vec<u8>> = Vec::new();
    for round in 0..3 {
        for run in runs {
            let (ok, _, stderr) = pixgeo(&in_folder(&dir, run));
            assert!(ok, "{run:?}: {stderr}");
        }
        let bytes: Vec<Vec<u8>> = outputs
            .iter()
            .map(|n| std::fs::read(dir.join(n)).unwrap())
            .collect();
        if round == 0 {
            first = bytes;
        } else {
            for (name, (a, b)) in outputs.iter().zip(first.iter().zip(&bytes)) {
                assert!(a == b, "{name} differs in run {round}");
            }
        }
    }
}

/// An output that names a folder is refused before any file is touched, by
/// every command that writes several.
#[test]
fn an_output_naming_a_folder_is_refused_first() {
    let dir = folder("folder-output", &[]);
    let mask = dir.join("mask.npy");
    write_npy(&mask, &[16, 16], &[false; 256]);
    let samples = dir.join("s.csv");
    std::fs::write(&samples, "x,y,z\n1,1,1\n50,5,2\n20,60,3\n").unwrap();
    let (mask, samples) = (mask.to_str().unwrap(), samples.to_str().unwrap());
    let cases: [(&str, Vec<&str>); 4] = [
        (
            "voronoi",
            vec![
                "voronoi", "--random", "20", "--size", "32", "--labels", "@l.npy", "-o", "@d.png",
            ],
        ),
        (
            "lloyd",
            vec![
                "lloyd", "--random", "20", "--size", "32", "--labels", "@l.npy", "-o", "@d.png",
            ],
        ),
        (
            "interpolate",
            vec![
                "interpolate",
                "--sites",
                samples,
                "--value",
                "z",
                "--size",
                "32",
                "--raster",
                "@d.npy",
                "-o",
                "@l.png",
            ],
        ),
        (
            "transform",
            vec![
                "transform",
                "--mask",
                mask,
                "--distance",
                "@l.npy",
                "--indices",
                "@d.npy",
            ],
        ),
    ];
    for (case, args) in cases {
        let names = ["l.npy", "l.png"];
        let dir = folder(&format!("folder-{case}"), &names);
        for d in ["d.png", "d.npy"] {
            std::fs::create_dir(dir.join(d)).unwrap();
        }
        let (ok, _, stderr) = pixgeo(&in_folder(&dir, &args));
        assert!(!ok && stderr.contains("is a folder"), "{case}: {stderr}");
        for d in ["d.png", "d.npy"] {
            std::fs::remove_dir(dir.join(d)).unwrap();
        }
        untouched(&dir, &names, case);
    }
}
