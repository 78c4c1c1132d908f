//! The command line: outputs that load, and clear errors with a non-zero exit.

use std::{
    path::{Path, PathBuf},
    process::Command,
};

use pixgeo::io::npy;

fn pixgeo<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_pixgeo"))
        .args(args)
        .output()
        .expect("run pixgeo");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A `--json` answer: the envelope checked against docs/schema/envelope.json and
/// its result against docs/schema/COMMAND.json; returns the envelope's result.
fn answer(stdout: &str, command: &str) -> serde_json::Value {
    let envelope = enveloped(stdout, command);
    envelope["result"].clone()
}

/// The whole envelope of a `--json` answer, checked as [`answer`] does.
fn enveloped(stdout: &str, command: &str) -> serde_json::Value {
    let schema = |name: &str| -> serde_json::Value {
        let path = format!("{}/../docs/schema/{name}.json", env!("CARGO_MANIFEST_DIR"));
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

#[test]
fn voronoi_writes_picture_arrays_and_json() {
    let sites = temp("sites.csv");
    std::fs::write(&sites, "x,y\n10,10\n50.5,20\n30,45\n").unwrap();
    let (png, labels, dist) = (temp("v.png"), temp("l.npy"), temp("d.npy"));
    let (ok, stdout, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "--distance",
        dist.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let envelope = enveloped(&stdout, "voronoi");
    assert_eq!(envelope["frame"]["width"], 64);
    assert_eq!(envelope["result"]["stats"]["sites"], 3);
    assert!(envelope["timings_ms"]["render"].is_number());
    let (shape, l): (Vec<u64>, Vec<u32>) = npy::read(&labels).unwrap();
    assert_eq!(shape, vec![48, 64]);
    // Pixel (i, j) is centred at world (i, j): (10, 10) belongs to site 0.
    assert_eq!(l[10 * 64 + 10], 0);
    assert_eq!(l[45 * 64 + 30], 2);
    let (_, d): (Vec<u64>, Vec<f32>) = npy::read(&dist).unwrap();
    assert_eq!(d[10 * 64 + 10], 0.0);
    assert!((d[10 * 64 + 13] - 3.0).abs() < 1e-6);
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
}

#[test]
fn voronoi_reads_weights_and_shapes() {
    // Thesis Figs. 3.38 and 3.45: weighted points, a segment, a circle and an arc.
    let sites = temp("mixed.json");
    std::fs::write(
        &sites,
        r#"{"sites": [{"point": [8, 8], "m": 2},
                      {"segment": [[40, 5], [60, 5]]},
                      {"circle": {"center": [20, 36], "radius": 6}},
                      {"arc": {"center": [50, 36], "radius": 8, "start": 0, "end": 3.1416}, "a": 1}]}"#,
    )
    .unwrap();
    let (labels, dist) = (temp("ml.npy"), temp("md.npy"));
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--size",
        "64x48",
        "--labels",
        labels.to_str().unwrap(),
        "--distance",
        dist.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, l): (Vec<u64>, Vec<u32>) = npy::read(&labels).unwrap();
    let (_, d): (Vec<u64>, Vec<f32>) = npy::read(&dist).unwrap();
    // On the segment, at the circle's centre (6 away), above the arc's middle.
    assert_eq!((l[5 * 64 + 50], d[5 * 64 + 50]), (1, 0.0));
    assert_eq!(l[36 * 64 + 20], 2);
    assert!((d[36 * 64 + 20] - 6.0).abs() < 1e-4);
    assert_eq!(l[44 * 64 + 50], 3);
    assert!((d[44 * 64 + 50] - 1.0).abs() < 1e-4);
    // The CPU gives the same labels; fans stay within a pixel.
    let cpu_labels = temp("mlc.npy");
    let fan_dist = temp("mdf.npy");
    for (flags, out) in [
        (["--device", "cpu"], &cpu_labels),
        (["--mode", "fan"], &fan_dist),
    ] {
        let kind = if out == &cpu_labels {
            "--labels"
        } else {
            "--distance"
        };
        let mut a = vec![
            "voronoi",
            "--sites",
            sites.to_str().unwrap(),
            "--size",
            "64x48",
        ];
        a.extend(flags);
        a.extend([kind, out.to_str().unwrap()]);
        let (ok, _, stderr) = pixgeo(&a);
        assert!(ok, "{flags:?}: {stderr}");
    }
    let (_, c): (Vec<u64>, Vec<u32>) = npy::read(&cpu_labels).unwrap();
    assert_eq!(c, l);
    // Tiles of 20 pixels give the same labels.
    let tiled = temp("mlt.npy");
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--size",
        "64x48",
        "--max-tile",
        "20",
        "--labels",
        tiled.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, t): (Vec<u64>, Vec<u32>) = npy::read(&tiled).unwrap();
    assert_eq!(t, l);
    let (_, f): (Vec<u64>, Vec<f32>) = npy::read(&fan_dist).unwrap();
    assert!(f.iter().zip(&d).all(|(a, b)| (a - b).abs() <= 1.05));
    // Weights in CSV columns; a bad weight names its site.
    let csv = temp("weights.csv");
    std::fs::write(&csv, "x,y,m,a\n10,10,1,0\n50,20,0,0\n").unwrap();
    let (ok, _, stderr) = pixgeo(&["voronoi", "--sites", csv.to_str().unwrap(), "--size", "32"]);
    assert!(!ok && stderr.contains("site 1"), "{stderr}");
}

#[test]
fn voronoi_windows_tile_into_the_whole_picture() {
    let sites = temp("window.csv");
    std::fs::write(
        &sites,
        "x,y\n10,10\n50.5,20\n30,45\n0,0\n63,47\n31,23\n-20,30\n",
    )
    .unwrap();
    let s = sites.to_str().unwrap();
    let whole = temp("whole.npy");
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        s,
        "--size",
        "64x48",
        "--labels",
        whole.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, l): (Vec<u64>, Vec<u32>) = npy::read(&whole).unwrap();
    // Two windows side by side are the whole picture, column for column.
    let mut halves = Vec::new();
    for (window, name) in [("0,0,25,48", "w0.npy"), ("25,0,39,48", "w1.npy")] {
        let out = temp(name);
        let args = [
            "voronoi", "--sites", s, "--size", "64x48", "--window", window,
        ];
        let (ok, _, stderr) = pixgeo(&[&args[..], &["--labels", out.to_str().unwrap()]].concat());
        assert!(ok, "{stderr}");
        let (shape, v): (Vec<u64>, Vec<u32>) = npy::read(&out).unwrap();
        assert_eq!(shape[0], 48);
        halves.push((shape[1] as usize, v));
    }
    for j in 0..48 {
        let row = [&halves[0].1[j * 25..][..25], &halves[1].1[j * 39..][..39]].concat();
        assert_eq!(row, l[j * 64..][..64], "row {j}");
    }
    for (window, message) in [
        ("60,0,10,10", "inside the 64x48 picture"),
        ("1,2,3", "four numbers"),
        ("a,b,c,d", "whole pixels"),
    ] {
        let (ok, _, stderr) = pixgeo(&[
            "voronoi", "--sites", s, "--size", "64x48", "--window", window,
        ]);
        assert!(!ok && stderr.contains(message), "{window}: {stderr}");
    }
    let (ok, _, stderr) = pixgeo(&[
        "voronoi", "--sites", s, "--size", "64x48", "--window", "0,0,8,8", "--device", "cpu",
    ]);
    assert!(!ok && stderr.contains("--window takes"), "{stderr}");
}

#[test]
fn random_sites_with_bbox_and_fan_mode() {
    let (ok, stdout, stderr) = pixgeo(&[
        "voronoi",
        "--random",
        "50",
        "--seed",
        "3",
        "--size",
        "80",
        "--bbox",
        "-1,-1,1,0",
        "--mode",
        "fan:16",
        "--speedup",
        "quadtree",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let envelope = enveloped(&stdout, "voronoi");
    let (frame, summary) = (&envelope["frame"], &envelope["result"]);
    assert_eq!(
        (frame["width"].clone(), frame["height"].clone()),
        (80.into(), 40.into())
    );
    let group = &summary["stats"]["groups"][0];
    assert_eq!(
        (group["kind"].as_str(), group["size"].as_u64()),
        (Some("fan"), Some(16))
    );
}

#[test]
fn bad_input_fails_with_a_message() {
    let cases: Vec<(Vec<String>, &str)> = {
        let empty = temp("empty.csv");
        std::fs::write(&empty, "x,y\n").unwrap();
        let nan = temp("nan.csv");
        std::fs::write(&nan, "1,2\nnan,3\n").unwrap();
        let bad = temp("bad.json");
        std::fs::write(&bad, "[[1, 2], [3]]").unwrap();
        let s = |p: &PathBuf| p.to_str().unwrap().to_string();
        vec![
            (vec!["--sites".into(), s(&empty)], "no sites"),
            (vec!["--sites".into(), s(&nan)], "non-finite"),
            (vec!["--sites".into(), s(&bad)], "site 1"),
            (vec!["--sites".into(), missing("sites.csv")], "No such file"),
            (vec!["--random".into(), "0".into()], "at least one"),
            (
                vec!["--random".into(), "5".into(), "--size".into(), "0".into()],
                "at least 1",
            ),
            (
                vec![
                    "--random".into(),
                    "5".into(),
                    "--size".into(),
                    "99999999".into(),
                ],
                "too large",
            ),
            (
                vec![
                    "--random".into(),
                    "5".into(),
                    "--mode".into(),
                    "cone".into(),
                ],
                "unknown mode",
            ),
            (
                vec![
                    "--random".into(),
                    "5".into(),
                    "--mode".into(),
                    "fan:2".into(),
                ],
                "at least 3",
            ),
            (
                vec![
                    "--random".into(),
                    "5".into(),
                    "--bbox".into(),
                    "0,0,0,1".into(),
                ],
                "XMIN < XMAX",
            ),
            (vec![], "--sites FILE or --random N"),
        ]
    };
    for (args, expect) in cases {
        let mut all = vec!["voronoi".to_string()];
        all.extend(args.iter().cloned());
        let refs: Vec<&str> = all.iter().map(String::as_str).collect();
        let (ok, _, stderr) = pixgeo(&refs);
        assert!(!ok, "{args:?} should fail");
        assert!(
            stderr.contains(expect),
            "{args:?}: expected `{expect}` in: {stderr}"
        );
    }
}

#[test]
fn gallery_renders_every_picture_and_an_index() {
    let dir = temp("gallery");
    let (ok, _, stderr) = pixgeo(&["gallery", dir.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let pictures: Vec<&str> = index
        .split("<img src=\"")
        .skip(1)
        .map(|s| &s[..s.find('"').unwrap()])
        .collect();
    assert!(pictures.len() >= 12, "{index}");
    for p in pictures {
        if p.ends_with(".svg") {
            let svg = std::fs::read_to_string(dir.join(p)).unwrap();
            assert!(svg.starts_with("<svg") && svg.contains("<path"), "{p}");
            continue;
        }
        let img = image::open(dir.join(p)).unwrap_or_else(|e| panic!("{p}: {e}"));
        assert!(img.width() >= 256, "{p}");
    }
    assert!(index.contains("<code>pixgeo voronoi"), "commands shown");
}

#[test]
fn higher_order_diagrams_write_level_arrays_and_pictures() {
    let sites = temp("ho.csv");
    std::fs::write(&sites, "10,10\n50.5,20\n30,45\n5,40\n").unwrap();
    let (png, labels, dist) = (temp("ho.png"), temp("hol.npy"), temp("hod.npy"));
    let s = sites.to_str().unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        s,
        "--size",
        "64x48",
        "--degree",
        "3",
        "--each-level",
        "-o",
        png.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "--distance",
        dist.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (shape, l): (Vec<u64>, Vec<u32>) = npy::read(&labels).unwrap();
    assert_eq!(shape, vec![48, 64, 3]);
    // Pixel (10, 10): site 0 at 0, site 3 at sqrt 925, site 2 at sqrt 1625.
    let p = (10 * 64 + 10) * 3;
    assert_eq!(&l[p..p + 3], &[0, 3, 2]);
    let (_, d): (Vec<u64>, Vec<f32>) = npy::read(&dist).unwrap();
    assert_eq!(d[p], 0.0);
    assert!((d[p + 2] - 1625f32.sqrt()).abs() < 1e-4);
    for level in 1..=3 {
        assert!(temp(&format!("ho-{level}.png")).exists());
    }
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        s,
        "--size",
        "64x48",
        "--order",
        "2",
        "--labels",
        labels.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, l): (Vec<u64>, Vec<u32>) = npy::read(&labels).unwrap();
    assert_eq!(&l[(10 * 64 + 10) * 2..][..2], &[0, 3]);
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        s,
        "--size",
        "64x48",
        "--furthest",
        "--labels",
        labels.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, l): (Vec<u64>, Vec<u32>) = npy::read(&labels).unwrap();
    assert_eq!(l[10 * 64 + 10], 1);
    // Levels need a positive count.
    let (ok, _, stderr) = pixgeo(&["voronoi", "--sites", s, "--degree", "0"]);
    assert!(!ok && stderr.contains("levels"), "{stderr}");
}

#[test]
fn distance_commands_answer_with_the_pair() {
    let (red, blue) = (temp("red.csv"), temp("blue.csv"));
    std::fs::write(&red, "0,0\n1,0\n0,1\n").unwrap();
    std::fs::write(&blue, "0,0.5\n3,4\n").unwrap();
    let (r, b) = (red.to_str().unwrap(), blue.to_str().unwrap());
    let (ok, stdout, stderr) = pixgeo(&["hausdorff", "--red", r, "--blue", b, "--json"]);
    assert!(ok, "{stderr}");
    let v = answer(&stdout, "hausdorff");
    // Blue (3, 4) is sqrt(18) from red (0, 1), its nearest.
    assert_eq!(v["hausdorff"], 18f64.sqrt());
    assert_eq!(v["blue_to_red"]["blue"]["index"], 1);
    assert_eq!(v["blue_to_red"]["red"]["index"], 2);
    let (ok, stdout, stderr) = pixgeo(&["diameter", "--sites", b, "--json"]);
    assert!(ok, "{stderr}");
    let v = answer(&stdout, "diameter");
    assert_eq!(v["distance"], (9.0f64 + 3.5 * 3.5).sqrt());
    let (ok, stdout, stderr) = pixgeo(&["maxdist", "--red", r, "--blue", b]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("maximum distance 5 "), "{stdout}");
    let (ok, _, stderr) = pixgeo(&["hausdorff", "--red", r, "--blue", &missing("blue.csv")]);
    assert!(!ok && stderr.contains("blue"), "{stderr}");
    // Under --json the failure is an envelope on stdout too.
    let args = [
        "hausdorff",
        "--red",
        r,
        "--blue",
        &missing("blue.csv"),
        "--json",
    ];
    let (ok, stdout, stderr) = pixgeo(&args);
    assert!(!ok && stderr.contains("blue"), "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let path = format!("{}/../docs/schema/error.json", env!("CARGO_MANIFEST_DIR"));
    let schema = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    assert!(validator.is_valid(&v), "{stdout}");
    assert_eq!(v["command"], "hausdorff");
    let message = v["error"]["message"].as_str().unwrap();
    assert!(
        message.contains("blue") && stderr.contains(message),
        "{stdout}"
    );
}

#[test]
fn the_cpu_pixel_algorithm_gives_the_same_diagram() {
    let (gpu, cpu) = (temp("gpu.npy"), temp("cpu.npy"));
    for (device, out) in [("auto", &gpu), ("cpu", &cpu)] {
        let (ok, _, stderr) = pixgeo(&[
            "voronoi",
            "--random",
            "300",
            "--size",
            "120x90",
            "--device",
            device,
            "--labels",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
    }
    let (shape, a): (Vec<u64>, Vec<u32>) = npy::read(&gpu).unwrap();
    let (cpu_shape, b): (Vec<u64>, Vec<u32>) = npy::read(&cpu).unwrap();
    assert_eq!(shape, cpu_shape);
    // Random real coordinates: no ties, so every label agrees.
    assert_eq!(a, b);
    let (ok, _, stderr) = pixgeo(&[
        "voronoi", "--random", "30", "--device", "cpu", "--mode", "fan",
    ]);
    assert!(!ok && stderr.contains("exact"), "{stderr}");
}

#[test]
fn settle_answers_with_the_same_map_on_every_path() {
    let sites = temp("rivals.csv");
    std::fs::write(&sites, "x,y\n10,10\n50.5,20\n30,45\n8,40\n").unwrap();
    let own = temp("own.csv");
    std::fs::write(&own, "x,y\n55,44\n").unwrap();
    let run = |name: &str, extra: &[&str]| {
        let (png, area) = (temp(&format!("{name}.png")), temp(&format!("{name}.npy")));
        let mut args = vec![
            "settle",
            "--sites",
            sites.to_str().unwrap(),
            "--own",
            own.to_str().unwrap(),
            "--size",
            "64x48",
            "-o",
            png.to_str().unwrap(),
            "--area",
            area.to_str().unwrap(),
            "--json",
        ];
        args.extend_from_slice(extra);
        let (ok, stdout, stderr) = pixgeo(&args);
        assert!(ok, "{stderr}");
        let summary = answer(&stdout, "settle");
        let (shape, a): (Vec<u64>, Vec<u32>) = npy::read(&area).unwrap();
        assert_eq!(shape, vec![48, 64]);
        let img = image::open(&png).unwrap();
        assert_eq!((img.width(), img.height()), (64, 48));
        (summary, a)
    };
    let (spans, a) = run("spans", &[]);
    let (faithful, b) = run("faithful", &["--method", "faithful"]);
    let (cpu, c) = run("cpu", &["--device", "cpu"]);
    assert_eq!(a, b);
    assert_eq!(a, c);
    let best = spans["settle"]["area_pixels"].as_u64().unwrap();
    assert_eq!(a.iter().copied().max().unwrap() as u64, best);
    assert_eq!(faithful["settle"], spans["settle"]);
    assert_eq!(cpu["settle"], spans["settle"]);
    let refined = &spans["refined"];
    assert!(refined["area"].as_f64().unwrap() >= refined["start_area_pixels"].as_f64().unwrap());
    // Other metrics have no exact refinement.
    let (l1, _) = run("l1", &["--metric", "l1"]);
    assert!(l1["refined"].is_null());
}

#[test]
fn settle_rejects_bad_requests() {
    let (ok, _, stderr) = pixgeo(&["settle", "--random", "0"]);
    assert!(!ok && stderr.contains("at least one"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&[
        "settle", "--random", "3", "--device", "cpu", "--method", "faithful",
    ]);
    assert!(!ok && stderr.contains("faithful"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&["settle", "--random", "3", "--metric", "lp:-1"]);
    assert!(!ok && stderr.contains("p > 0"), "{stderr}");
}

#[test]
fn enclose_and_empty_print_exact_homothets() {
    let sites = temp("homothet.csv");
    std::fs::write(&sites, "x,y\n0,0\n4,0\n0,3\n").unwrap();
    let s = sites.to_str().unwrap();
    let (ok, stdout, stderr) = pixgeo(&["enclose", "--sites", s, "--json", "--size", "128"]);
    assert!(ok, "{stderr}");
    let v = answer(&stdout, "enclose");
    // The right triangle's smallest circle is on its hypotenuse: radius 2.5.
    assert!(
        (v["exact"]["scale"].as_f64().unwrap() - 2.5).abs() < 1e-9,
        "{stdout}"
    );
    let region = temp("region.json");
    std::fs::write(&region, "[[[0,0],[4,0],[4,3],[0,3]]]").unwrap();
    let (ok, stdout, stderr) = pixgeo(&[
        "empty",
        "--sites",
        s,
        "--region",
        region.to_str().unwrap(),
        "--size",
        "128",
    ]);
    assert!(ok, "{stderr}");
    // On the top side at x = 25/8: as far from (0, 3) as from (4, 0).
    assert!(
        stdout.contains("centre (3.125, 3), scale 3.125"),
        "{stdout}"
    );
    assert!(stdout.contains("distance transform"), "{stdout}");
    // Both pixel stages, asked for by name, reach the same exact answer.
    for (stage, name) in [
        ("cones", "\"cones\""),
        ("transform", "\"distance_transform\""),
    ] {
        let (ok, stdout, stderr) = pixgeo(&[
            "empty",
            "--sites",
            s,
            "--region",
            region.to_str().unwrap(),
            "--pixel-stage",
            stage,
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let v = answer(&stdout, "empty");
        assert_eq!(v["pixel_stage"].to_string(), name, "{stdout}");
        assert!((v["exact"]["scale"].as_f64().unwrap() - 3.125).abs() < 1e-9);
    }
    let kite = temp("kite.csv");
    std::fs::write(&kite, "1,0\n0,1\n-1,0\n0,-2\n").unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "empty",
        "--sites",
        s,
        "--polygon",
        kite.to_str().unwrap(),
        "--pixel-stage",
        "transform",
    ]);
    assert!(!ok && stderr.contains("use cones"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&["enclose", "--sites", s, "--order", "9"]);
    assert!(!ok && stderr.contains("cannot enclose 9 of 3"), "{stderr}");
}

#[test]
fn alpha_writes_mask_picture_and_json() {
    let sites = temp("alpha.csv");
    std::fs::write(&sites, "x,y\n0,0\n10,0\n10,10\n0,10\n5,5\n").unwrap();
    let s = sites.to_str().unwrap();
    let (mask, png) = (temp("alpha.npy"), temp("alpha.png"));
    let (ok, stdout, stderr) = pixgeo(&[
        "alpha",
        "--sites",
        s,
        "--alpha",
        "-0.16",
        "--size",
        "64",
        "--mask",
        mask.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v = answer(&stdout, "alpha");
    let (w, h) = (v["width"].as_u64().unwrap(), v["height"].as_u64().unwrap());
    let (shape, inside) = npy::read::<u8>(&mask).unwrap();
    assert_eq!(shape, vec![h, w]);
    let count = inside.iter().filter(|&&b| b == 1).count() as u64;
    assert_eq!(count, v["inside"].as_u64().unwrap());
    // Discs of radius 6.25 bite into the square's sides but cannot reach its
    // centre: the hull is some of the square, which is a fifth of the picture.
    assert!(count > 0 && count < w * h / 4, "{count} of {w}x{h}");
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
    // Radius 2 is below the smallest enclosing circle's (about 7.07).
    let (ok, _, stderr) = pixgeo(&["alpha", "--sites", s, "--alpha", "0.5"]);
    assert!(
        !ok && stderr.contains("smallest enclosing circle"),
        "{stderr}"
    );
    let (ok, stdout, stderr) = pixgeo(&["alpha", "--sites", s, "--alpha", "0.1", "--size", "64"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("method hull"), "{stdout}");
}

#[test]
fn triangle_and_quadrangle_print_exact_areas() {
    let sites = temp("area.csv");
    let s = sites.to_str().unwrap();
    // A unit square's corners and a point just off its diagonal.
    std::fs::write(&sites, "x,y\n0,0\n10,0\n10,10\n0,10\n5,5.5\n").unwrap();
    // The sweep by default, the thesis's roofs on a Vulkan device.
    for device in [&[][..], &["--device", "lavapipe", "--size", "64"]] {
        let with = |args: &[&str]| -> Vec<String> {
            args.iter().chain(device).map(|a| a.to_string()).collect()
        };
        let (ok, stdout, stderr) = pixgeo(&with(&["triangle", "--sites", s, "--json"]));
        assert!(ok, "{stderr}");
        let v = answer(&stdout, "triangle");
        // (0,0), (10,10), (5,5.5): half of |10 * 5.5 - 10 * 5| = 2.5.
        assert_eq!(v["area"].as_f64().unwrap(), 2.5, "{stdout}");
        let by = if device.is_empty() { "sweep" } else { "pixels" };
        assert_eq!(v["decided_by"], by, "{stdout}");
        let (ok, stdout, stderr) = pixgeo(&with(&["triangle", "--sites", s, "--max"]));
        assert!(ok, "{stderr}");
        assert!(
            stdout.starts_with("largest triangle: area 50\n"),
            "{stdout}"
        );
        let (ok, stdout, stderr) = pixgeo(&with(&["quadrangle", "--sites", s, "--max"]));
        assert!(ok, "{stderr}");
        assert!(
            stdout.starts_with("largest quadrangle: area 100\n"),
            "{stdout}"
        );
    }
    let (ok, _, stderr) = pixgeo(&["quadrangle", "--sites", s, "--size", "0"]);
    assert!(
        !ok && stderr.contains("2 to 16384 pixels, not 0"),
        "{stderr}"
    );
    let (ok, _, stderr) = pixgeo(&["quadrangle", "--sites", s, "--size", "64"]);
    assert!(
        !ok && stderr.contains("the cpu sweep draws none"),
        "{stderr}"
    );
}

#[test]
fn voronoi_floods_and_jump_floods_seed_pixels() {
    let sites = temp("seeds.csv");
    std::fs::write(&sites, "x,y\n3,4\n40,10\n20,30\n55,40\n").unwrap();
    let s = sites.to_str().unwrap();
    for method in ["flood", "jfa"] {
        let labels = temp(&format!("{method}.npy"));
        let (ok, stdout, stderr) = pixgeo(&[
            "voronoi",
            "--sites",
            s,
            "--size",
            "64x48",
            "--method",
            method,
            "--labels",
            labels.to_str().unwrap(),
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let v = answer(&stdout, "voronoi");
        assert_eq!(v["method"], method);
        let (shape, map) = npy::read::<u32>(&labels).unwrap();
        assert_eq!(shape, vec![48, 64]);
        // Each site's own pixel is its own, and pixel (0, 0) is nearest site 0.
        assert_eq!(map[4 * 64 + 3], 0);
        assert_eq!(map[30 * 64 + 20], 2);
        assert_eq!(map[0], 0);
    }
    std::fs::write(&sites, "x,y\n3,4\n3.2,4.1\n20,30\n").unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "voronoi", "--sites", s, "--size", "64x48", "--method", "flood",
    ]);
    assert!(!ok && stderr.contains("fall in pixel"), "{stderr}");
}

#[test]
fn delaunay_writes_triangle_files_json_and_a_picture() {
    let sites = temp("dt.csv");
    let mut text = String::from("x,y\n");
    for k in 0..200 {
        // A jittered lattice with one repeated point.
        let (x, y) = (
            (k % 20) as f64 + 0.001 * (k * 7 % 13) as f64,
            (k / 20) as f64,
        );
        text += &format!("{x},{y}\n");
    }
    text += "0,0\n";
    std::fs::write(&sites, text).unwrap();
    let (prefix, png) = (temp("mesh"), temp("dt.png"));
    let (ok, stdout, stderr) = pixgeo(&[
        "delaunay",
        "--sites",
        sites.to_str().unwrap(),
        "--triangle",
        prefix.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--check",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("1 repeated"), "{stdout}");
    assert!(stdout.contains("digital triangulation valid"), "{stdout}");
    assert!(stdout.contains("every edge locally Delaunay"), "{stdout}");
    let node = std::fs::read_to_string(prefix.with_extension("node")).unwrap();
    let ele = std::fs::read_to_string(prefix.with_extension("ele")).unwrap();
    assert!(node.starts_with("201 2 0 0\n"), "{node}");
    let header: Vec<usize> = ele
        .lines()
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(header[1..], [3, 0]);
    assert_eq!(ele.lines().count(), header[0] + 1);
    assert!(image::open(&png).is_ok());

    let (ok, stdout, _) = pixgeo(&["delaunay", "--sites", sites.to_str().unwrap(), "--json"]);
    assert!(ok);
    let json = answer(&stdout, "delaunay");
    assert_eq!(json["triangles"].as_array().unwrap().len(), header[0]);
    assert_eq!(json["duplicates"][0], serde_json::json!([200, 0]));

    std::fs::write(&sites, "0,0\n1,1\n2,2\n").unwrap();
    let (ok, _, stderr) = pixgeo(&["delaunay", "--sites", sites.to_str().unwrap()]);
    assert!(!ok && stderr.contains("one line"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&["delaunay"]);
    assert!(!ok && stderr.contains("--sites"), "{stderr}");
}

#[test]
fn every_json_answer_is_the_envelope_its_schema_describes() {
    let sites = temp("envelope.csv");
    std::fs::write(&sites, "x,y\n0,0\n4,0\n4,3\n0,3\n2,1\n1,2\n3,2.5\n").unwrap();
    let s = sites.to_str().unwrap();
    let mask = temp("envelope-mask.npy");
    npy::write(&mask, &[2, 3], &[0u8, 1, 0, 0, 0, 1]).unwrap();
    let mask = mask.to_str().unwrap();
    let runs: [&[&str]; 16] = [
        &["voronoi", "--random", "6", "--size", "32"],
        &["voronoi", "--random", "6", "--size", "32", "--order", "2"],
        &[
            "voronoi", "--random", "6", "--size", "32", "--degree", "2", "--peel",
        ],
        &["voronoi", "--random", "6", "--size", "32", "--furthest"],
        &[
            "voronoi", "--random", "6", "--size", "32", "--method", "jfa",
        ],
        &["settle", "--random", "6", "--size", "32"],
        &["hausdorff", "--red", s, "--blue", s],
        &["diameter", "--sites", s],
        &["maxdist", "--red", s, "--blue", s],
        &["enclose", "--sites", s],
        &["empty", "--sites", s],
        &["alpha", "--sites", s, "--alpha", "0"],
        &["triangle", "--sites", s, "--max"],
        &["quadrangle", "--sites", s],
        &["delaunay", "--sites", s],
        &["transform", "--mask", mask],
    ];
    for run in runs {
        let mut args = run.to_vec();
        args.push("--json");
        let (ok, stdout, stderr) = pixgeo(&args);
        assert!(ok, "{run:?}: {stderr}");
        let envelope = enveloped(&stdout, run[0]);
        // Every command that draws says on what; the sweeps draw nothing.
        let picture = !["triangle", "quadrangle", "transform"].contains(&run[0]);
        assert_eq!(envelope["frame"].is_object(), picture, "{run:?}");
        let named = stdout.matches("\"device\"").count();
        assert_eq!(named, 1, "{run:?}: the device is named once");
        // What draws on the device says how long its passes took there.
        let passes = envelope["gpu_ms"].as_object().unwrap();
        assert_eq!(!passes.is_empty(), picture, "{run:?}: {passes:?}");
    }
}

#[test]
fn trace_holds_the_host_phases_and_the_device_passes() {
    let trace = temp("trace.json");
    let (ok, stdout, stderr) = pixgeo(&[
        "voronoi",
        "--random",
        "50",
        "--size",
        "64",
        "--json",
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains(&format!("wrote {}", trace.display())));
    let envelope = enveloped(&stdout, "voronoi");
    let events: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&trace).unwrap()).unwrap();
    let spans: Vec<&serde_json::Value> = events["traceEvents"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["ph"] == "X")
        .collect();
    let on = |tid: u64| spans.iter().filter(move |e| e["tid"] == tid);
    assert!(on(1).any(|e| e["name"] == "pixgeo voronoi"));
    assert!(on(1).any(|e| e["name"] == "run"));
    // Every pass the envelope times is on the device's track, and no other.
    let mut traced: Vec<String> = on(2).map(|e| e["name"].as_str().unwrap().into()).collect();
    traced.sort();
    traced.dedup();
    let timed: Vec<String> = envelope["gpu_ms"]
        .as_object()
        .unwrap()
        .keys()
        .cloned()
        .collect();
    assert_eq!(traced, timed);
    assert!(spans.iter().all(|e| e["dur"].as_f64().unwrap() >= 0.0));

    let trace = missing("t.json");
    let (ok, _, stderr) = pixgeo(&["voronoi", "--random", "5", "--trace", &trace]);
    assert!(!ok);
    assert!(
        stderr.contains(&format!("writing the trace {trace}")),
        "{stderr}"
    );
}

#[test]
fn sites_beyond_memory_are_refused_up_front() {
    // Under a 1.5 GB address-space limit, 5 million sites (about 2.6 GB of
    // work) are an error with exit 1, not an abort partway through.
    let command = format!(
        "ulimit -v 1500000 && exec '{}' voronoi --random 5000000 --size 64 --device cpu",
        env!("CARGO_BIN_EXE_pixgeo")
    );
    let out = Command::new("bash")
        .args(["-c", &command])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("5000000 sites need about 2.6 GB"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn point_commands_share_one_grammar_for_their_sites() {
    // --random N --seed S and --sites - (CSV on stdin) wherever points are read.
    let file = temp("grammar.csv");
    let csv = "x,y\n0,0\n4,0\n4,3\n0,3\n2,1\n1,2.5\n";
    std::fs::write(&file, csv).unwrap();
    let stdin = |args: &[&str]| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pixgeo"))
            .args(args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(csv.as_bytes())
            .unwrap();
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let f = file.to_str().unwrap();
    for command in [
        &["triangle"][..],
        &["quadrangle", "--max"],
        &["diameter"],
        &["alpha", "--alpha", "0"],
        &["delaunay"],
        &["enclose"],
        &["empty"],
    ] {
        fn with<'a>(command: &[&'a str], sites: &[&'a str]) -> Vec<&'a str> {
            let mut args = command.to_vec();
            args.extend_from_slice(sites);
            args.push("--json");
            args
        }
        let (ok, from_file, stderr) = pixgeo(&with(command, &["--sites", f]));
        assert!(ok, "{command:?}: {stderr}");
        let from_stdin = stdin(&with(command, &["--sites", "-"]));
        assert_eq!(
            answer(&from_stdin, command[0]),
            answer(&from_file, command[0])
        );
        let (ok, a, stderr) = pixgeo(&with(command, &["--random", "40", "--seed", "7"]));
        assert!(ok, "{command:?}: {stderr}");
        let (_, b, _) = pixgeo(&with(command, &["--random", "40", "--seed", "7"]));
        let (_, c, _) = pixgeo(&with(command, &["--random", "40", "--seed", "8"]));
        let (a, b, c) = (
            answer(&a, command[0]),
            answer(&b, command[0]),
            answer(&c, command[0]),
        );
        assert_eq!(a, b, "{command:?}: one seed, one answer");
        assert_ne!(a, c, "{command:?}: another seed, other points");
        let (ok, _, stderr) = pixgeo(command);
        assert!(!ok && stderr.contains("--sites"), "{command:?}: {stderr}");
    }
}

#[test]
fn files_written_are_reported_and_quiet_says_nothing() {
    let (png, mask) = (temp("q.png"), temp("q.npy"));
    let (p, m) = (png.to_str().unwrap(), mask.to_str().unwrap());
    let args = [
        "alpha", "--random", "30", "--alpha", "0", "-o", p, "--mask", m,
    ];
    let (ok, _, stderr) = pixgeo(&args);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains(&format!("wrote {p}")) && stderr.contains(&format!("wrote {m}")),
        "{stderr}"
    );
    for command in [
        &args[..],
        &["voronoi", "--random", "5", "--size", "32", "-o", p, "-q"],
        &[
            "delaunay",
            "--random",
            "30",
            "--triangle",
            p.trim_end_matches(".png"),
            "--quiet",
        ],
    ] {
        let mut with = command.to_vec();
        if command[0] == "alpha" {
            with.push("-q");
        }
        let (ok, _, stderr) = pixgeo(&with);
        assert!(ok && stderr.is_empty(), "{with:?}: {stderr}");
    }
}

#[test]
fn size_is_the_longer_side_where_the_sites_set_the_box() {
    let sites = temp("size.csv");
    std::fs::write(&sites, "x,y\n0,0\n4,0\n4,3\n0,3\n2,1\n").unwrap();
    let s = sites.to_str().unwrap();
    for command in [
        &["triangle", "--sites", s, "--device", "lavapipe"][..],
        &["diameter", "--sites", s],
        &["hausdorff", "--red", s, "--blue", s],
        &["alpha", "--sites", s, "--alpha", "0"],
        &["enclose", "--sites", s],
    ] {
        let mut args = command.to_vec();
        args.extend(["--size", "64x64"]);
        let (ok, _, stderr) = pixgeo(&args);
        assert!(
            !ok && stderr.contains("give the longer side's pixels"),
            "{args:?}: {stderr}"
        );
        let mut args = command.to_vec();
        args.extend(["--size", "64"]);
        let (ok, _, stderr) = pixgeo(&args);
        assert!(ok, "{args:?}: {stderr}");
    }
}

#[test]
fn a_bad_point_set_is_named_as_the_user_named_it() {
    let (bad, good) = (temp("red-nan.csv"), temp("blue.csv"));
    std::fs::write(&bad, "x,y\n1,nan\n").unwrap();
    std::fs::write(&good, "x,y\n0,0\n1,1\n").unwrap();
    let (b, g) = (bad.to_str().unwrap(), good.to_str().unwrap());
    for (args, name) in [
        (["hausdorff", "--red", b, "--blue", g], "the red points"),
        (["maxdist", "--red", g, "--blue", b], "the blue points"),
    ] {
        let (ok, _, stderr) = pixgeo(&args);
        assert!(
            !ok && stderr.contains(name) && stderr.contains("non-finite"),
            "{stderr}"
        );
    }
}

#[test]
fn transform_reads_png_and_npy_masks_and_writes_scipy_layout() {
    let (w, h) = (7u32, 5u32);
    let features = [(1u32, 2u32), (5, 4)]; // (column, row)
    let png = temp("mask.png");
    let mut picture = image::GrayImage::new(w, h);
    for &(x, y) in &features {
        picture.put_pixel(x, y, image::Luma([200]));
    }
    picture.save(&png).unwrap();
    let (d, i) = (temp("transform-d.npy"), temp("transform-i.npy"));
    let (ok, stdout, stderr) = pixgeo(&[
        "transform",
        "--mask",
        png.to_str().unwrap(),
        "--distance",
        d.to_str().unwrap(),
        "--indices",
        i.to_str().unwrap(),
        "--sampling",
        "2,1",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("2 feature pixels"), "{stdout}");
    let (shape, distances) = npy::read::<f64>(&d).unwrap();
    assert_eq!(shape, [5, 7]);
    let (shape, indices) = npy::read::<i32>(&i).unwrap();
    assert_eq!(shape, [2, 5, 7]);
    for y in 0..h {
        for x in 0..w {
            let p = (y * w + x) as usize;
            let offset = |&(fx, fy): &(u32, u32)| {
                let (dy, dx) = (2.0 * (y as f64 - fy as f64), x as f64 - fx as f64);
                (dy * dy + dx * dx).sqrt()
            };
            let nearest = features.iter().map(offset).fold(f64::INFINITY, f64::min);
            assert_eq!(distances[p], nearest, "pixel ({x}, {y})");
            let (row, column) = (indices[p] as u32, indices[35 + p] as u32);
            assert_eq!(offset(&(column, row)), nearest, "pixel ({x}, {y})");
        }
    }

    // Each pixel's nearest component: the two features are two components,
    // numbered by their first pixel row by row.
    let (c, picture) = (temp("transform-c.npy"), temp("transform.png"));
    let (ok, stdout, stderr) = pixgeo(&[
        "transform",
        "--mask",
        png.to_str().unwrap(),
        "--components",
        c.to_str().unwrap(),
        "-o",
        picture.to_str().unwrap(),
    ]);
    assert!(ok && stdout.contains("in 2 components"), "{stdout}{stderr}");
    let (shape, components) = npy::read::<u32>(&c).unwrap();
    assert_eq!(shape, [5, 7]);
    for (p, &component) in components.iter().enumerate() {
        let (x, y) = (p as u32 % w, p as u32 / w);
        let d = |&(fx, fy): &(u32, u32)| (x as f64 - fx as f64).hypot(y as f64 - fy as f64);
        let (first, second) = (d(&features[0]), d(&features[1]));
        if first != second {
            assert_eq!(component, u32::from(second < first), "pixel ({x}, {y})");
        }
    }
    assert!(image::open(&picture).is_ok());

    // No feature: infinite distances and -1 indices; L1 from an .npy mask.
    let empty = temp("empty-mask.npy");
    npy::write(&empty, &[2, 2], &[0.0f64; 4]).unwrap();
    let (ok, stdout, _) = pixgeo(&[
        "transform",
        "--mask",
        empty.to_str().unwrap(),
        "--indices",
        i.to_str().unwrap(),
    ]);
    assert!(ok && stdout.contains("no feature"), "{stdout}");
    assert_eq!(npy::read::<i32>(&i).unwrap().1, [-1; 8]);

    for (args, message) in [
        (vec!["--sampling", "0,1", "--json"], "above 0"),
        (vec![], "nothing to write"),
        (vec!["--distance", "d.png"], "name the file *.npy"),
        (
            vec!["--metric", "lp:0.5", "--sampling", "1,2", "--json"],
            "equal sampling",
        ),
    ] {
        let mut run = vec!["transform", "--mask", png.to_str().unwrap()];
        run.extend(args);
        let (ok, _, stderr) = pixgeo(&run);
        assert!(!ok && stderr.contains(message), "{run:?}: {stderr}");
    }
    // The medial axis of a bar of 7 free rows between two rows of features.
    let (bar, axis) = (temp("bar-mask.npy"), temp("bar-axis.npy"));
    let border: Vec<u8> = (0..20 * 9)
        .map(|p| u8::from(p % 20 == 0 || p % 20 == 19 || p / 20 == 0 || p / 20 == 8))
        .collect();
    npy::write(&bar, &[9, 20], &border).unwrap();
    let run = [
        "transform",
        "--mask",
        bar.to_str().unwrap(),
        "--medial-axis",
    ];
    let (ok, stdout, stderr) = pixgeo(&[&run[..], &[axis.to_str().unwrap(), "--json"]].concat());
    assert!(
        ok && stdout.contains("\"medial_axis_pixels\""),
        "{stdout}{stderr}"
    );
    let (shape, on) = npy::read::<bool>(&axis).unwrap();
    assert_eq!(shape, [9, 20]);
    for x in 8..12 {
        let rows: Vec<usize> = (0..9).filter(|&y| on[y * 20 + x]).collect();
        assert_eq!(rows, [4], "column {x}");
    }
    let (ok, _, stderr) =
        pixgeo(&[&run[..], &[axis.to_str().unwrap(), "--prune-angle", "200"]].concat());
    assert!(!ok && stderr.contains("pruning"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&[
        "transform",
        "--mask",
        bar.to_str().unwrap(),
        "--prune",
        "2",
        "--json",
    ]);
    assert!(!ok && stderr.contains("--medial-axis"), "{stderr}");
    let cube = temp("cube-mask.npy");
    npy::write(&cube, &[2, 2, 2], &[1u8; 8]).unwrap();
    let (ok, _, stderr) = pixgeo(&["transform", "--mask", cube.to_str().unwrap(), "--json"]);
    assert!(!ok && stderr.contains("2-D array"), "{stderr}");
}

/// Rows of a (rows, columns, bands) array in the other order.
fn flipped<T: Copy>(values: &[T], width: usize, bands: usize) -> Vec<T> {
    values
        .chunks(width * bands)
        .rev()
        .flatten()
        .copied()
        .collect()
}

#[test]
fn north_up_rasters_are_the_y_down_ones_flipped() {
    let polygon = temp("north-up-triangle.csv");
    std::fs::write(&polygon, "x,y\n1,0\n0,2\n-0.5,-0.3\n").unwrap();
    let shapes = temp("north-up-shapes.json");
    std::fs::write(
        &shapes,
        r#"[{"arc": {"center": [10, 10], "radius": 5, "start": 0.3, "end": 2.0}}, [30, 20],
            {"segment": [[5, 25], [20, 28]], "m": 2}]"#,
    )
    .unwrap();
    let metric = format!("polygon:{}", polygon.display());
    let base = ["--bbox", "0,0,40,30", "--size", "120"];
    // Flooding is left out: its digital diagram breaks ties by pixel order.
    let runs: [(&[&str], usize); 4] = [
        (&["voronoi", "--random", "30", "--seed", "4"], 1),
        (
            &[
                "voronoi", "--random", "30", "--seed", "4", "--metric", &metric,
            ],
            1,
        ),
        (
            &["voronoi", "--random", "30", "--seed", "4", "--order", "2"],
            2,
        ),
        (&["voronoi", "--sites", shapes.to_str().unwrap()], 1),
    ];
    for (run, bands) in runs {
        let arrays: Vec<Vec<u32>> = ["up", "down"]
            .iter()
            .map(|axis| {
                let labels = temp(&format!("north-up-{axis}.npy"));
                let mut args: Vec<&str> = [run, &base[..]].concat();
                args.extend(["--labels", labels.to_str().unwrap(), "--y-axis", axis]);
                let (ok, _, stderr) = pixgeo(&args);
                assert!(ok, "{args:?}: {stderr}");
                npy::read::<u32>(&labels).unwrap().1
            })
            .collect();
        assert_eq!(arrays[0], flipped(&arrays[1], 120, bands), "{run:?}");
        assert!(
            arrays[0] != arrays[1],
            "{run:?}: the diagram is not symmetric"
        );
    }

    // --bbox makes north-up the default; the envelope says so, in the user's
    // coordinates.
    let (ok, stdout, stderr) = pixgeo(&[
        "settle",
        "--random",
        "10",
        "--seed",
        "2",
        "--bbox",
        "0,0,40,30",
        "--size",
        "40",
        "--crs",
        "EPSG:32633",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v = enveloped(&stdout, "settle");
    assert_eq!(v["frame"]["y_axis"], "up");
    assert_eq!(
        v["frame"]["bbox"],
        serde_json::json!([0.0, 0.0, 40.0, 30.0])
    );
    assert_eq!(v["frame"]["origin"], serde_json::json!([0.0, 30.0]));
    assert_eq!(v["frame"]["crs"], "EPSG:32633");
    let point = &v["result"]["refined"]["point"];
    let (x, y) = (point[0].as_f64().unwrap(), point[1].as_f64().unwrap());
    assert!(
        (0.0..=40.0).contains(&x) && (0.0..=30.0).contains(&y),
        "{point}"
    );
    let (ok, stdout, _) = pixgeo(&["voronoi", "--random", "5", "--size", "16", "--json"]);
    assert!(ok && enveloped(&stdout, "voronoi")["frame"]["y_axis"] == "down");

    for (args, message) in [
        (vec!["--crs", "4326"], "EPSG:N"),
        (vec!["--crs", "EPSG:99999"], "1024 to 32766"),
        (vec!["--labels", "l.png"], "name the file *.npy or *.tif"),
        (vec!["--world-file", "w.txt"], "*.tfw"),
        (vec!["--cells", "c.json"], "*.geojson"),
        (vec!["-o", "v.gif"], "*.png or *.svg"),
        (
            vec!["--cells", "c.geojson", "--window", "0,0,4,4"],
            "drop --window",
        ),
    ] {
        let mut run = vec!["voronoi", "--random", "5", "--size", "16"];
        run.extend(args);
        let (ok, _, stderr) = pixgeo(&run);
        assert!(!ok && stderr.contains(message), "{run:?}: {stderr}");
    }
}
