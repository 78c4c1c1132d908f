//! The other problems' commands: distances, settle, homothets, alpha hulls,
//! extremal triangles and quadrangles, Delaunay.

use super::*;

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
    let path = format!("{}/schema/error.json", env!("CARGO_MANIFEST_DIR"));
    let schema = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    assert!(validator.is_valid(&v), "{stdout}");
    assert_eq!(v["command"], "hausdorff");
    let message = v["error"]["message"].as_str().unwrap();
    assert!(
        message.contains("blue") && stderr.contains(message),
        "{stdout}"
    );
    // A refused input names why, by kind.
    let two = temp("two.csv");
    std::fs::write(&two, "x,y\n0,0\n1,1\n").unwrap();
    let (ok, stdout, _) = pixgeo(&["triangle", "--sites", two.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(!ok && validator.is_valid(&v), "{stdout}");
    let reason = &v["error"]["reason"];
    assert_eq!(
        (&reason["kind"], &reason["needed"], &reason["given"]),
        (&"too_few".into(), &3.into(), &2.into()),
        "{stdout}"
    );
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
    let (ok, _, stderr) = pixgeo(&["enclose", "--sites", s, "--at-least", "9"]);
    assert!(!ok && stderr.contains("cannot enclose 9 of 3"), "{stderr}");
}

#[test]
fn empty_reads_geojson_polygons_as_its_region_and_breaks_ties_alike() {
    // A square with a square hole as rings, as a GeoJSON Polygon in a
    // FeatureCollection (closed rings) and as a MultiPolygon: one region. Two
    // corners tie exactly; every run names the same, the lower x.
    let sites = temp("geojson-region.csv");
    std::fs::write(&sites, "x,y\n2,2\n8,3\n5,8\n").unwrap();
    let rings = "[[0,0],[10,0],[10,10],[0,10],[0,0]],[[4,4],[6,4],[6,6],[4,6],[4,4]]";
    let files = [
        (
            "rings.json",
            format!(
                "[{}]",
                rings.replace(",[0,0]]", "]").replace(",[4,4]]", "]")
            ),
        ),
        (
            "polygon.geojson",
            format!(
                r#"{{"type":"FeatureCollection","features":[{{"type":"Feature","properties":{{}},"geometry":{{"type":"Polygon","coordinates":[{rings}]}}}}]}}"#
            ),
        ),
        (
            "multi.geojson",
            format!(r#"{{"type":"MultiPolygon","coordinates":[[{rings}]]}}"#),
        ),
    ];
    let mut answers = Vec::new();
    for (name, text) in files {
        let region = temp(name);
        std::fs::write(&region, text).unwrap();
        for _ in 0..2 {
            let (ok, stdout, stderr) = pixgeo(&[
                "empty",
                "--sites",
                sites.to_str().unwrap(),
                "--region",
                region.to_str().unwrap(),
                "--json",
            ]);
            assert!(ok, "{name}: {stderr}");
            let v = answer(&stdout, "empty");
            answers.push(v["exact"].to_string());
        }
    }
    assert!(answers.iter().all(|a| a == &answers[0]), "{answers:?}");
    assert!(answers[0].contains("[0.0,10.0]"), "{}", answers[0]);
    let line = temp("line.geojson");
    std::fs::write(&line, r#"{"type":"Polygon","coordinates":[]}"#).unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "empty",
        "--sites",
        sites.to_str().unwrap(),
        "--region",
        line.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("ring"), "{stderr}");
}

#[test]
fn empty_among_points_and_segments_is_the_nearest_double_far_from_the_origin() {
    // Two points and a segment inside a box of side 10, at the origin and
    // moved by 1e15: the same circle, its radius the double nearest the exact
    // one (a root of a quadratic in the segment's normal), no bound left.
    let mut radii = Vec::new();
    for far in [0.0, 1e15] {
        let (sites, region) = (temp("far-sites.json"), temp("far-box.json"));
        let at = |x: f64, y: f64| format!("[{:?}, {:?}]", far + x, far + y);
        std::fs::write(
            &sites,
            format!(
                r#"{{"sites": [{{"point": {}}}, {{"point": {}}}, {{"segment": [{}, {}]}}]}}"#,
                at(3.0, 4.0),
                at(7.0, 1.0),
                at(2.0, 8.0),
                at(6.0, 9.0)
            ),
        )
        .unwrap();
        std::fs::write(
            &region,
            format!(
                "[[{}, {}, {}, {}]]",
                at(0.0, 0.0),
                at(10.0, 0.0),
                at(10.0, 10.0),
                at(0.0, 10.0)
            ),
        )
        .unwrap();
        let (ok, stdout, stderr) = pixgeo(&[
            "empty",
            "--sites",
            sites.to_str().unwrap(),
            "--region",
            region.to_str().unwrap(),
            "--inside",
            "--json",
            "--size",
            "256",
        ]);
        assert!(ok, "{far}: {stderr}");
        let v = answer(&stdout, "empty");
        assert_eq!(v["tolerance"].as_f64(), Some(0.0), "{stdout}");
        radii.push(v["exact"]["scale"].as_f64().unwrap());
    }
    assert_eq!(radii, [3.630264097376426; 2]);
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
        "--hull",
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
        !ok && stderr.contains("the CPU's rotational sweep draws none"),
        "{stderr}"
    );
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
fn a_json_key_given_twice_is_refused() {
    // `{"x": 1, "x": 20}` would read as 20 with no word said.
    let sites = temp("twice.json");
    std::fs::write(&sites, r#"[{"x": 1, "y": 2, "x": 20}, {"x": 5, "y": 5}]"#).unwrap();
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--size",
        "16",
    ]);
    assert!(!ok && stderr.contains("\"x\" is given twice"), "{stderr}");
}

/// The commands with a CPU algorithm give the same answer on every device,
/// and without any Vulkan driver compute on the CPU, saying so on stderr and
/// in the envelope's `fallback`.
#[test]
fn every_device_gives_the_same_answer_and_a_fallback_is_announced() {
    let red = temp("routes-red.csv");
    let blue = temp("routes-blue.csv");
    std::fs::write(&red, "x,y\n0,0\n4,0\n4,3\n0,3\n2,1.5\n").unwrap();
    std::fs::write(&blue, "x,y\n1,1\n9,0.5\n3,3\n").unwrap();
    let (red, blue) = (red.to_str().unwrap(), blue.to_str().unwrap());
    let lattice = temp("routes-lattice.csv");
    let points: String = (0..64).map(|k| format!("{},{}\n", k % 8, k / 8)).collect();
    std::fs::write(&lattice, format!("x,y\n{points}")).unwrap();
    let lattice = lattice.to_str().unwrap();
    let labels = temp("routes-labels.npy");
    let labels = labels.to_str().unwrap();
    let furthest = [
        "--sites",
        lattice,
        "--size",
        "40",
        "--furthest",
        "--bbox",
        "-1,-1,9,9",
        "--labels",
        labels,
    ];
    let commands: [(&str, Vec<&str>, &str); 3] = [
        ("delaunay", vec!["--sites", lattice], "triangles"),
        ("hausdorff", vec!["--red", red, "--blue", blue], "hausdorff"),
        ("voronoi", furthest.to_vec(), "labels"),
    ];
    let none = temp("no-driver.json");
    for (command, args, key) in commands {
        let run = |device: Option<&str>, no_driver: bool| {
            let mut all: Vec<&str> = vec![command];
            all.extend(&args);
            all.push("--json");
            if let Some(d) = device {
                all.extend(["--device", d]);
            }
            let mut c = Command::new(env!("CARGO_BIN_EXE_pixgeo"));
            if no_driver {
                c.env("VK_DRIVER_FILES", &none).env_remove("PIXGEO_DEVICE");
            }
            let out = c.args(&all).output().expect("run pixgeo");
            let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
            let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
            assert!(out.status.success(), "{all:?}: {stderr}");
            let mut envelope = enveloped(&stdout, command);
            if key == "labels" {
                envelope["result"]["labels"] = std::fs::read(labels).unwrap().into();
            }
            (envelope, stderr)
        };
        let (default, _) = run(None, false);
        let (lavapipe, _) = run(Some("lavapipe"), false);
        let (cpu, _) = run(Some("cpu"), false);
        let (fallen, stderr) = run(None, true);
        for (name, other) in [
            ("lavapipe", &lavapipe),
            ("cpu", &cpu),
            ("no driver", &fallen),
        ] {
            assert_eq!(
                default["result"][key], other["result"][key],
                "{command}: {name} differs from the default"
            );
        }
        assert!(
            default["fallback"].is_null() && cpu["fallback"].is_null(),
            "{command}"
        );
        assert_eq!(fallen["device"], "cpu", "{command}");
        // Work the CPU does faster than a software rasterizer starts no
        // device, and has nothing to announce.
        if default["device"] == "cpu" {
            assert!(
                fallen["fallback"].is_null() && !stderr.contains("computing on the CPU"),
                "{command}: {stderr}"
            );
        } else {
            assert!(
                fallen["fallback"]
                    .as_str()
                    .is_some_and(|f| f.contains("no Vulkan driver"))
                    && stderr.contains("computing on the CPU"),
                "{command}: {stderr}"
            );
        }
    }
}
