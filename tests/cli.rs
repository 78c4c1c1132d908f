//! The command line: outputs that load, and clear errors with a non-zero exit.

use std::{path::PathBuf, process::Command};

use pixgeo::io::npy;

fn pixgeo(args: &[&str]) -> (bool, String, String) {
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

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pixgeo-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
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
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["width"], 64);
    assert_eq!(summary["stats"]["sites"], 3);
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
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        (summary["width"].clone(), summary["height"].clone()),
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
            (vec!["--sites".into(), s(&empty)], "empty"),
            (vec!["--sites".into(), s(&nan)], "non-finite"),
            (vec!["--sites".into(), s(&bad)], "site 1"),
            (
                vec!["--sites".into(), "/nonexistent/sites.csv".into()],
                "No such file",
            ),
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
    assert!(pictures.len() >= 5, "{index}");
    for p in pictures {
        let img = image::open(dir.join(p)).unwrap_or_else(|e| panic!("{p}: {e}"));
        assert!(img.width() >= 256, "{p}");
    }
    assert!(index.contains("<code>pixgeo voronoi"), "commands shown");
}
