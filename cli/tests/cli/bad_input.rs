//! Every command over a matrix of bad inputs: files that are empty, malformed,
//! of an unknown format or not there; numbers beyond reason; options that
//! contradict each other; outputs that cannot be written. Each must exit 1 or 2
//! with a message naming the problem, never panic, and leave no output file.

use std::{
    path::{Path, PathBuf},
    process::{Command, Stdio},
};

fn dir() -> PathBuf {
    // Cargo's folder for integration tests' files: reused by each run, removed
    // by `cargo clean`.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_input");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes the named input files once.
fn inputs() -> PathBuf {
    let dir = dir();
    let files: &[(&str, &[u8])] = &[
        ("ok.csv", b"x,y\n10,10\n40,12\n25,40\n5,30\n33,3\n"),
        ("empty.csv", b"x,y\n"),
        ("one.csv", b"1,1\n"),
        ("same.csv", b"3,3\n3,3\n3,3\n3,3\n"),
        ("line.csv", b"0,0\n1,1\n2,2\n3,3\n"),
        ("nan.csv", b"1,2\nnan,3\n4,5\n"),
        ("inf.csv", b"1,2\ninf,3\n4,5\n"),
        ("badnum.csv", b"1,2x\n3,4\n5,6\n"),
        ("third.csv", b"1,2,3\n4,5,6\n"),
        ("id.csv", b"x,y,id\n1,2,0\n3,4,1\n"),
        ("bad.json", b"[[1, 2], [3]]"),
        ("trunc.json", b"[[1, 2], [3, 4"),
        ("binary.csv", &[0xff, 0xfe, 0x00, 0x01]),
        ("sites.xlsx", b"1,2\n3,4\n"),
        ("notnpy.npy", b"1,2\n3,4\n"),
        ("poly.geojson", br#"{"type": "Polygon", "coordinates": []}"#),
        ("far.csv", b"0,0\n1e300,1e300\n-1e300,5\n7,-1e300\n"),
        (
            "bool.npy",
            b"\x93NUMPY\x01\x00v\x00{'descr': '|b1', 'fortran_order': False, 'shape': (3, 2), }                                                          \n\x01\x00\x00\x01\x01\x01",
        ),
    ];
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    dir
}

/// Runs pixgeo in `dir`: the exit code and stderr.
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_pixgeo"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("run pixgeo");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The bad inputs every command that reads sites shares, with the words its
/// message must hold.
const SITE_FILES: &[(&str, &str)] = &[
    ("empty.csv", "no sites"),
    ("nan.csv", "non-finite"),
    ("inf.csv", "non-finite"),
    ("badnum.csv", "line 1, column 2"),
    ("third.csv", "header"),
    ("id.csv", "`id`"),
    ("bad.json", "site 1"),
    ("trunc.json", "JSON"),
    ("binary.csv", "UTF-8"),
    ("sites.xlsx", "unknown site file format"),
    ("notnpy.npy", "NumPy"),
    ("bool.npy", "bool array holds no coordinates"),
    ("poly.geojson", "Polygon"),
    ("missing.csv", "No such file"),
];

#[test]
fn every_command_refuses_bad_input_clearly() {
    let dir = inputs();
    // (arguments before the site file, the option that takes it, after).
    let site_commands: &[(&[&str], &str, &[&str])] = &[
        (
            &["voronoi"],
            "--sites",
            &["--size", "32", "--labels", "out.npy"],
        ),
        (
            &["settle"],
            "--sites",
            &["--size", "32", "--area", "out.npy"],
        ),
        (&["diameter"], "--sites", &[]),
        (&["hausdorff", "--red", "ok.csv"], "--blue", &[]),
        (&["maxdist", "--blue", "ok.csv"], "--red", &[]),
        (&["enclose", "--circle"], "--sites", &["-o", "out.png"]),
        (&["empty", "--circle"], "--sites", &["-o", "out.png"]),
        (
            &["alpha", "--alpha", "0.01"],
            "--sites",
            &["--hull", "out.npy"],
        ),
        (&["triangle"], "--sites", &[]),
        (&["quadrangle"], "--sites", &[]),
        (&["delaunay"], "--sites", &["-o", "out.png"]),
    ];
    let mut cases: Vec<(Vec<String>, &str)> = Vec::new();
    for (before, option, after) in site_commands {
        for (file, expect) in SITE_FILES {
            let mut args: Vec<String> = before.iter().map(|s| s.to_string()).collect();
            args.extend([option.to_string(), file.to_string()]);
            args.extend(after.iter().map(|s| s.to_string()));
            cases.push((args, expect));
        }
    }
    // Each line: the arguments, split at spaces, and what the message must say.
    let specific: &[(&str, &str)] = &[
        // Degenerate sets where a command needs more.
        ("delaunay --sites one.csv", "one point"),
        ("delaunay --sites same.csv", "one point"),
        ("delaunay --sites line.csv", "one line"),
        ("delaunay --random 1", "one point"),
        ("triangle --sites one.csv", "three"),
        ("quadrangle --sites line.csv", "four distinct"),
        // Numbers beyond reason.
        ("delaunay --random 10 --grid 4294967295", "larger than"),
        ("delaunay --random 10 -o out.png --size 100000", "100000"),
        ("voronoi --random 5 --size 0 --labels out.npy", "at least 1"),
        (
            "voronoi --random 5 --size 99999999 --labels out.npy",
            "too large",
        ),
        (
            "voronoi --random 5 --bbox -1e308,-1e308,1e308,1e308 --labels out.npy",
            "finite",
        ),
        (
            "settle --random 5 --bbox -1e308,-1e308,1e308,1e308 --area out.npy",
            "finite",
        ),
        (
            "voronoi --random 5 --bbox 0,0,1,1e9 --size 64 --labels out.npy",
            "height",
        ),
        (
            "voronoi --random 5 --mode fan:100000000 --labels out.npy",
            "65536",
        ),
        (
            "voronoi --random 5 --mode fan --epsilon 1e-300 --labels out.npy",
            "epsilon",
        ),
        (
            "voronoi --random 5 --mode fan --epsilon nan --labels out.npy",
            "epsilon",
        ),
        ("voronoi --random 5 --contours 0 -o out.png", "positive"),
        ("lloyd --random 5 --size 64 --tolerance NaN", "not NaN"),
        (
            "voronoi --random 5 --metric lp:1e-9 --labels out.npy",
            "0.01",
        ),
        // Options that contradict each other or would be ignored.
        (
            "voronoi --random 5 --labels out.npy -o out.npy",
            "both name",
        ),
        (
            "voronoi --random 5 --labels out.npy --distance out.npy",
            "both name",
        ),
        (
            "voronoi --random 5 --epsilon 2 --labels out.npy",
            "--mode fan",
        ),
        ("voronoi --random 5 --contours 4", "-o"),
        ("voronoi --random 5 --degree 2 --each-level", "-o"),
        (
            "voronoi --random 5 --peel --labels out.npy",
            "--degree or --order",
        ),
        (
            "voronoi --random 5 --device cpu --mode fan --labels out.npy",
            "exact",
        ),
        (
            "voronoi --random 5 --method flood --speedup quadtree --labels out.npy",
            "flooding",
        ),
        (
            "hausdorff --red ok.csv --blue ok.csv --method pixels --device cpu",
            "CPU",
        ),
        // Outputs named for another format.
        ("voronoi --random 5 -o out.jpg", ".png"),
        ("voronoi --random 5 --labels out.txt", ".npy"),
        ("settle --random 5 --area out.png", ".npy"),
        ("alpha --sites ok.csv --alpha 0.01 --hull out.csv", ".npy"),
        // Outputs that cannot be written.
        ("voronoi --random 5 -o no/such/dir/out.png", "no/such/dir"),
        ("voronoi --random 5 -o /dev/full", "No space"),
        // Environment.
        (
            "voronoi --random 5 --device no-such-device --labels out.npy",
            "no-such-device",
        ),
    ];
    for (args, expect) in specific {
        cases.push((args.split(' ').map(str::to_string).collect(), expect));
    }
    let mut failures = Vec::new();
    for (args, expect) in &cases {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, stderr) = run(&dir, &refs);
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("out") || n.contains(".pixgeo-"))
            .collect();
        for name in &leftovers {
            let _ = std::fs::remove_file(dir.join(name));
        }
        let problem = if !matches!(code, Some(1 | 2)) {
            Some(format!("exit {code:?}"))
        } else if stderr.contains("panicked") {
            Some("a panic".into())
        } else if !stderr.contains(expect) {
            Some(format!("no `{expect}` in the message"))
        } else if !leftovers.is_empty() {
            Some(format!("left {leftovers:?}"))
        } else {
            None
        };
        if let Some(problem) = problem {
            let first = stderr.lines().next().unwrap_or_default();
            failures.push(format!("{args:?}: {problem}: {first}"));
        }
    }
    eprintln!("{} bad inputs tried", cases.len());
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn a_reader_that_has_gone_ends_the_answer_quietly() {
    let dir = inputs();
    let mut child = Command::new(env!("CARGO_BIN_EXE_pixgeo"))
        .args(["delaunay", "--random", "3000", "--json"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run pixgeo");
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
