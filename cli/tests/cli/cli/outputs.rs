//! What every command shares: refusals, the gallery, the JSON envelope, traces,
//! the sites' grammar, what is reported written, and north-up rasters.

use super::*;

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
    // A device is passed on to the commands that take one.
    let (ok, _, stderr) = pixgeo(&["gallery", dir.to_str().unwrap(), "--device", "lavapipe"]);
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
    assert!(!index.contains("Not drawn here"), "{index}");
}

/// On the CPU the gallery draws what the CPU computes, lists the pictures
/// only a Vulkan device draws, and writes its index.
#[test]
fn gallery_on_the_cpu_skips_and_lists_the_drawings() {
    let dir = temp("gallery-cpu");
    let (ok, _, stderr) = pixgeo(&["gallery", dir.to_str().unwrap(), "--device", "cpu"]);
    assert!(
        ok && stderr.contains("need a Vulkan device and were not drawn"),
        "{stderr}"
    );
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let drawn = index.matches("<img src=").count();
    let skipped = index.matches("Not drawn here").count();
    assert!(
        drawn >= 12 && skipped >= 1,
        "{drawn} drawn, {skipped} skipped"
    );
}

#[test]
fn every_json_answer_is_the_envelope_its_schema_describes() {
    let sites = temp("envelope.csv");
    std::fs::write(&sites, "x,y\n0,0\n4,0\n4,3\n0,3\n2,1\n1,2\n3,2.5\n").unwrap();
    let s = sites.to_str().unwrap();
    let mask = temp("envelope-mask.npy");
    write_npy(&mask, &[2, 3], &[0u8, 1, 0, 0, 0, 1]);
    let mask = mask.to_str().unwrap();
    let runs: [&[&str]; 17] = [
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
        &["hausdorff", "--red", s, "--blue", s, "--method", "grid"],
        &["hausdorff", "--red", s, "--blue", s, "--method", "pixels"],
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
        // What draws on the device says how long its passes took there;
        // small ordinary diagrams are drawn by the CPU pixel algorithms
        // where no GPU is present, and triangulations are built by
        // insertion.
        let on_cpu = envelope["device"].as_str().unwrap().starts_with("cpu");
        // Every command that draws says on what; the sweeps, the grid and
        // insertion draw nothing.
        let picture = !["triangle", "quadrangle", "transform"].contains(&run[0])
            && !run.contains(&"grid")
            && (run[0] != "delaunay" || !on_cpu);
        assert_eq!(envelope["frame"].is_object(), picture, "{run:?}");
        let named = stdout.matches("\"device\"").count();
        assert_eq!(named, 1, "{run:?}: the device is named once");
        let passes = envelope["gpu_ms"].as_object().unwrap();
        assert_eq!(
            !passes.is_empty(),
            picture && !on_cpu,
            "{run:?}: {passes:?}"
        );
    }
}

#[test]
fn small_ordinary_diagrams_answer_the_same_on_the_cpu_without_a_gpu() {
    // (A device named by PIXGEO_DEVICE is kept, as a GPU would be.)
    // Without a GPU a software rasterizer's start outweighs a small
    // picture: the CPU pixel algorithms draw it, bit for bit the same.
    let gpu = pixgeo::machine::has_gpu()
        || std::env::var("PIXGEO_DEVICE").is_ok_and(|d| !d.eq_ignore_ascii_case("auto"));
    let mut outputs = Vec::new();
    for device in [None, Some("lavapipe")] {
        let name = device.unwrap_or("auto");
        let (labels, distances) = (
            temp(&format!("small-{name}.npy")),
            temp(&format!("small-d-{name}.npy")),
        );
        let mut args = vec![
            "voronoi",
            "--random",
            "300",
            "--size",
            "200",
            "--metric",
            "l1",
            "--json",
            "--labels",
            labels.to_str().unwrap(),
            "--distance",
            distances.to_str().unwrap(),
        ];
        args.extend(device.map(|d| ["--device", d]).into_iter().flatten());
        let (ok, stdout, stderr) = pixgeo(&args);
        assert!(ok, "{stderr}");
        let envelope = enveloped(&stdout, "voronoi");
        let on_cpu = envelope["device"].as_str().unwrap().starts_with("cpu");
        assert_eq!(
            on_cpu,
            device.is_none() && !gpu,
            "{name}: {}",
            envelope["device"]
        );
        outputs.push([
            std::fs::read(labels).unwrap(),
            std::fs::read(distances).unwrap(),
        ]);
    }
    assert!(outputs[0] == outputs[1], "the same labels and distances");
}

#[test]
fn trace_holds_the_host_phases_and_the_device_passes() {
    let trace = temp("trace.json");
    let (ok, stdout, stderr) = pixgeo(&[
        "voronoi",
        "--device",
        "lavapipe",
        "--method",
        "cones",
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
    assert!(stderr.contains("does not exist"), "{stderr}");
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
        "alpha", "--random", "30", "--alpha", "0", "-o", p, "--hull", m,
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

#[test]
fn the_frame_places_pixel_centres_as_the_guide_says() {
    // One site: each pixel's distance is its centre's distance to the site,
    // the centre at origin + (i + 0.5, ±(j + 0.5)) / scale, - north-up (row 0
    // the largest y, the default with --bbox), + with --y-axis down.
    let site = temp("centres.csv");
    std::fs::write(&site, "x,y\n3.25,1.5\n").unwrap();
    let distance = temp("centres-d.npy");
    for (y_axis, sign) in [("up", -1.0), ("down", 1.0)] {
        let (ok, stdout, stderr) = pixgeo(&[
            "voronoi",
            "--sites",
            site.to_str().unwrap(),
            "--bbox",
            "0,0,8,4",
            "--size",
            "16",
            "--y-axis",
            y_axis,
            "--distance",
            distance.to_str().unwrap(),
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let frame = enveloped(&stdout, "voronoi")["frame"].clone();
        assert_eq!(frame["y_axis"], y_axis);
        let origin = [
            frame["origin"][0].as_f64().unwrap(),
            frame["origin"][1].as_f64().unwrap(),
        ];
        let scale = frame["scale"].as_f64().unwrap();
        let (w, h) = (
            frame["width"].as_u64().unwrap(),
            frame["height"].as_u64().unwrap(),
        );
        assert_eq!((w, h), (16, 8));
        let d: Vec<f32> = npyz::NpyFile::new(std::fs::File::open(&distance).unwrap())
            .unwrap()
            .into_vec()
            .unwrap();
        for j in 0..h {
            for i in 0..w {
                let x = origin[0] + (i as f64 + 0.5) / scale;
                let y = origin[1] + sign * (j as f64 + 0.5) / scale;
                let truth = ((x - 3.25).powi(2) + (y - 1.5).powi(2)).sqrt();
                let got = d[(j * w + i) as usize] as f64;
                assert!(
                    (got - truth).abs() < 1e-5,
                    "{y_axis} ({i}, {j}): {got} {truth}"
                );
            }
        }
    }
}

#[test]
fn a_tall_box_takes_its_size_as_its_height_whatever_its_aspect() {
    // 10 by 100 at 1024 rows: 102.4 columns, rounded to 102. This was refused
    // ("a height of 1020.0 pixels for width 102, not 1024").
    let labels = temp("tall.npy");
    for (size, shape) in [("1024", [1024u64, 102]), ("300", [300, 30])] {
        let (ok, _, stderr) = pixgeo(&[
            "voronoi",
            "--random",
            "5",
            "--bbox",
            "0,0,10,100",
            "--size",
            size,
            "--labels",
            labels.to_str().unwrap(),
        ]);
        assert!(ok, "{size}: {stderr}");
        let file = npyz::NpyFile::new(std::fs::File::open(&labels).unwrap()).unwrap();
        assert_eq!(file.shape(), shape, "{size}");
    }
}

/// Messages to a full stderr are dropped, never a panic: the exit code alone
/// says what happened. A refusal under `RUST_BACKTRACE=1` prints its
/// message and causes, not a backtrace.
#[test]
fn stderr_full_or_backtraces_asked_for_change_no_answer() {
    let labels = temp("full-stderr.npy");
    let labels = labels.to_str().unwrap();
    let run = |args: &[&str], stderr: std::process::Stdio| {
        Command::new(env!("CARGO_BIN_EXE_pixgeo"))
            .args(args)
            .env("RUST_BACKTRACE", "1")
            .stderr(stderr)
            .output()
            .unwrap()
    };
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
            .into()
    };
    let ok = [
        "voronoi", "--random", "30", "--size", "64", "--labels", labels,
    ];
    assert_eq!(run(&ok, full()).status.code(), Some(0));
    let missing = missing("sites.csv");
    let refused = ["voronoi", "--sites", &missing, "--labels", labels];
    assert_eq!(run(&refused, full()).status.code(), Some(1));
    let out = run(&refused, std::process::Stdio::piped());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr.starts_with("Error: ")
            && stderr.contains("No such file")
            && !stderr.contains("acktrace"),
        "{stderr}"
    );
}

/// Answers on stdout, timings on stderr (or in --json): a run's stdout is
/// the same from run to run.
#[test]
fn timings_go_to_stderr() {
    for args in [
        &["delaunay", "--random", "200"][..],
        &["delaunay", "--random", "200", "--device", "lavapipe"],
        &["settle", "--random", "20", "--size", "64"],
    ] {
        let (ok, stdout, stderr) = pixgeo(args);
        assert!(ok, "{args:?}: {stderr}");
        assert!(!stdout.contains(" ms"), "{args:?}: {stdout}");
        assert!(stderr.contains(" ms"), "{args:?}: {stderr}");
    }
}

/// Completions and manual pages come from the command line's own
/// definition: every command is in each, and bash reads its script.
#[test]
fn completions_and_manual_pages_name_every_command() {
    let commands = [
        "voronoi",
        "hausdorff",
        "diameter",
        "maxdist",
        "settle",
        "lloyd",
        "interpolate",
        "enclose",
        "empty",
        "alpha",
        "triangle",
        "quadrangle",
        "delaunay",
        "transform",
        "gallery",
    ];
    for shell in ["bash", "zsh", "fish"] {
        let (ok, script, stderr) = pixgeo(&["completions", shell]);
        assert!(ok, "{shell}: {stderr}");
        for c in commands {
            assert!(script.contains(c), "{shell} completes no {c}");
        }
        if shell == "bash" {
            let path = temp("completion.bash");
            std::fs::write(&path, &script).unwrap();
            let checked = Command::new("bash").arg("-n").arg(&path).status().unwrap();
            assert!(checked.success(), "bash cannot read its completions");
        }
    }
    let dir = temp("man1");
    let _ = std::fs::remove_dir_all(&dir);
    let (ok, _, stderr) = pixgeo(&["man", dir.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    for page in std::iter::once("pixgeo".to_string()).chain(commands.map(|c| format!("pixgeo-{c}")))
    {
        let text = std::fs::read_to_string(dir.join(format!("{page}.1"))).unwrap();
        assert!(
            text.starts_with(".ie") || text.contains(".TH"),
            "{page}: {}",
            &text[..80]
        );
    }
}

/// Under a geographic system the planar commands say so on stderr.
#[test]
fn planar_work_under_a_geographic_system_warns() {
    let samples = temp("geographic.csv");
    std::fs::write(&samples, "x,y,z\n10,50,1\n11,51,2\n12,50,3\n11,49,4\n").unwrap();
    let raster = temp("geographic.npy");
    let (ok, _, stderr) = pixgeo(&[
        "interpolate",
        "--sites",
        samples.to_str().unwrap(),
        "--value",
        "z",
        "--bbox",
        "9,48,13,52",
        "--size",
        "16",
        "--crs",
        "EPSG:4326",
        "--raster",
        raster.to_str().unwrap(),
    ]);
    assert!(ok && stderr.contains("EPSG:4326 is geographic"), "{stderr}");
}

/// `-` writes an output to stdout, as it streams: `.npy` for rasters, PNG
/// for pictures, GeoJSON for vectors; the answer's lines go to stderr then,
/// and two writers of stdout are refused.
#[test]
fn a_dash_writes_an_output_to_stdout() {
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_pixgeo"))
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&[
        "voronoi", "--random", "10", "--size", "8x6", "--labels", "-",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let path = temp("dash.npy");
    std::fs::write(&path, &out.stdout).unwrap();
    let (shape, labels) = npy::read::<u32>(&path).unwrap();
    assert_eq!((shape, labels.len()), (vec![6, 8], 48));
    assert!(String::from_utf8_lossy(&out.stderr).contains("10 sites"));
    let out = run(&["voronoi", "--random", "10", "--size", "8", "-o", "-"]);
    assert!(out.status.success() && out.stdout.starts_with(b"\x89PNG"));
    let out = run(&["delaunay", "--random", "20", "--geojson", "-"]);
    let geojson: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(geojson["type"], "FeatureCollection");
    for (args, says) in [
        (&["-o", "-", "--labels", "-"][..], "both write to stdout"),
        (
            &["--labels", "-", "--json"],
            "--json and --labels both write to stdout",
        ),
    ] {
        let out = run(&[&["voronoi", "--random", "10", "--size", "8"], args].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(says), "{stderr}");
    }
}
