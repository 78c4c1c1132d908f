//! Inputs at the edges of the doubles that once spun for minutes or gave
//! nothing with exit 0: sites scaled to 1e-300 and 1e300 with their box,
//! boxes and regions of 1e300, values near the largest double. Each answers
//! (as the unscaled input does) or is refused with a reason. A hang fails
//! after two minutes rather than holding the suite.

use std::{path::Path, process::Command};

use super::{answer, outcome, temp};

/// Runs pixgeo with `args` for at most two minutes: (success, stdout, stderr).
fn bounded(args: &[&str]) -> (bool, String, String) {
    outcome(
        Command::new("timeout")
            .arg("120")
            .arg(env!("CARGO_BIN_EXE_pixgeo"))
            .args(args),
    )
}

/// `interpolate --json` of the samples in `file` over `bbox` by `method`,
/// on 48 pixels: its result, after a successful run.
fn interpolated(file: &Path, bbox: &str, method: &str) -> serde_json::Value {
    let raster = temp(&format!("magnitudes-{method}.npy"));
    let (ok, out, err) = bounded(&[
        "interpolate",
        "--sites",
        file.to_str().unwrap(),
        "--value",
        "z",
        "--bbox",
        bbox,
        "--size",
        "48",
        "--method",
        method,
        "--raster",
        raster.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{} {method}: {err}", file.display());
    answer(&out, "interpolate")
}

/// 40 samples on [0, 100)², their values x + y, the coordinates times
/// `scale`, as CSV.
fn samples(scale: f64) -> String {
    let mut text = String::from("x,y,z\n");
    for k in 0..40u32 {
        let (x, y) = ((k * 37 % 97) as f64 + 0.3, (k * 61 % 89) as f64 + 0.7);
        text += &format!("{:?},{:?},{}\n", x * scale, y * scale, x + y);
    }
    text
}

#[test]
fn samples_at_1e_minus_300_and_1e300_interpolate_as_unscaled_ones() {
    let count = |scale: f64, method: &str| {
        let file = temp(&format!("magnitudes-{scale:e}.csv"));
        std::fs::write(&file, samples(scale)).unwrap();
        let bbox = format!("0,0,{:?},{:?}", 100.0 * scale, 100.0 * scale);
        interpolated(&file, &bbox, method)["with_value"]
            .as_u64()
            .unwrap()
    };
    for method in ["exact", "linear", "nearest", "discrete"] {
        let unscaled = count(1.0, method);
        assert!(unscaled > 1000, "{method}: {unscaled}");
        for scale in [1e-300, 1e300] {
            assert_eq!(count(scale, method), unscaled, "{scale:e} {method}");
        }
    }
}

#[test]
fn a_picture_outside_the_samples_hull_says_why_it_has_no_values() {
    let file = temp("magnitudes-tiny.csv");
    std::fs::write(&file, samples(1e-300)).unwrap();
    let raster = temp("magnitudes-nan.npy");
    let (ok, _, err) = bounded(&[
        "interpolate",
        "--sites",
        file.to_str().unwrap(),
        "--value",
        "z",
        "--size",
        "32",
        "--raster",
        raster.to_str().unwrap(),
    ]);
    assert!(
        ok && err.contains("every value is NaN: give a --bbox"),
        "{err}"
    );
}

#[test]
fn sites_at_1e_minus_300_move_and_get_cells() {
    let file = temp("magnitudes-sites.csv");
    let text: String = samples(1e-300)
        .lines()
        .skip(1)
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    std::fs::write(&file, text).unwrap();
    let (s, cells) = (file.to_str().unwrap(), temp("magnitudes-cells.geojson"));
    let bbox = "0,0,1e-298,1e-298";
    let (ok, _, err) = bounded(&["lloyd", "--sites", s, "--bbox", bbox, "--size", "64"]);
    assert!(ok, "lloyd: {err}");
    let (ok, _, err) = bounded(&[
        "voronoi",
        "--sites",
        s,
        "--bbox",
        bbox,
        "--size",
        "64",
        "--cells",
        cells.to_str().unwrap(),
    ]);
    assert!(ok, "cells: {err}");
}

#[test]
fn boxes_and_regions_of_1e300_answer() {
    let (ok, _, err) = bounded(&[
        "voronoi",
        "--random",
        "10",
        "--bbox",
        "0,0,1e308,1e308",
        "--size",
        "64",
    ]);
    assert!(ok, "voronoi: {err}");
    let (sites, region) = (temp("magnitudes-s3.csv"), temp("magnitudes-region.json"));
    std::fs::write(&sites, "0,0\n1,1\n5,3\n").unwrap();
    std::fs::write(
        &region,
        "[[[-1e300,-1e300],[1e300,-1e300],[1e300,1e300],[-1e300,1e300]]]",
    )
    .unwrap();
    let (ok, out, err) = bounded(&[
        "empty",
        "--sites",
        sites.to_str().unwrap(),
        "--region",
        region.to_str().unwrap(),
        "--inside",
        "--json",
    ]);
    assert!(ok, "empty: {err}");
    let centre = &answer(&out, "empty")["exact"]["centre"];
    let at = |k: usize| centre[k].as_f64().unwrap();
    assert!(at(0).abs() <= 1e300 && at(1).abs() <= 1e300, "{centre}");
}

#[test]
fn values_near_the_largest_double_interpolate() {
    let file = temp("magnitudes-values.csv");
    let mut text = String::from("x,y,z\n");
    for (k, line) in samples(1.0).lines().skip(1).take(10).enumerate() {
        let (xy, _) = line.rsplit_once(',').unwrap();
        text += &format!("{xy},{}\n", if k % 2 == 0 { -1.7e308 } else { 1.7e308 });
    }
    std::fs::write(&file, text).unwrap();
    for method in ["exact", "linear", "discrete"] {
        let result = interpolated(&file, "0,0,100,100", method);
        assert!(
            result["with_value"].as_u64().unwrap() > 0,
            "{method}: {result}"
        );
        let (lo, hi) = (
            result["min"].as_f64().unwrap(),
            result["max"].as_f64().unwrap(),
        );
        assert!(lo >= -1.7e308 && hi <= 1.7e308, "{method}: {lo} {hi}");
    }
}
