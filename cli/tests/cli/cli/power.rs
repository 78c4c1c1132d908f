//! `--weights power`: power diagrams from `voronoi` and regular
//! triangulations from `delaunay`, a hidden site reported and owning no
//! pixel, outputs that load, and refusals.

use super::*;

/// Three heavy sites and a light one inside their triangle that they hide.
const SITES: &str = "x,y,w\n10,10,2560\n90,10,2560\n50,82,2560\n50,34,0\n";

#[test]
fn voronoi_draws_power_diagrams_and_names_hidden_sites() {
    let sites = temp("power.csv");
    std::fs::write(&sites, SITES).unwrap();
    let (labels, powers, png) = (
        temp("power-labels.npy"),
        temp("power.npy"),
        temp("power.png"),
    );
    let (ok, stdout, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--weights",
        "power",
        "--size",
        "100",
        "--labels",
        labels.to_str().unwrap(),
        "--distance",
        powers.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let result = answer(&stdout, "voronoi");
    assert_eq!(result["metric"], "power");
    assert_eq!(result["hidden"], serde_json::json!([3]));
    let (shape, l) = npy::read::<u32>(&labels).unwrap();
    assert_eq!(shape, vec![100, 100]);
    assert!(l.iter().all(|&k| k < 3));
    let (_, p) = npy::read::<f64>(&powers).unwrap();
    // Pixel (10, 10) is the first site's own point: power -2560.
    assert_eq!(l[10 * 100 + 10], 0);
    assert_eq!(p[10 * 100 + 10], -2560.0);
    assert!(image::open(&png).is_ok());
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        sites.to_str().unwrap(),
        "--weights",
        "power",
        "--order",
        "2",
    ]);
    assert!(!ok && stderr.contains("--order"), "{stderr}");
}

#[test]
fn power_cells_and_windows() {
    let sites = temp("power-cells.csv");
    std::fs::write(&sites, SITES).unwrap();
    let (cells, svg, window) = (
        temp("power-cells.geojson"),
        temp("power-cells.svg"),
        temp("power-window.npy"),
    );
    let run = |extra: &[&str]| {
        let mut argv = vec![
            "voronoi",
            "--sites",
            sites.to_str().unwrap(),
            "--weights",
            "power",
            "--bbox",
            "0,0,100,100",
            "--size",
            "100",
        ];
        argv.extend_from_slice(extra);
        pixgeo(&argv)
    };
    let (ok, _, stderr) = run(&[
        "--cells",
        cells.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cells).unwrap()).unwrap();
    let features = geojson["features"].as_array().unwrap();
    assert_eq!(features.len(), 4);
    // The heavy three share the square; the hidden fourth has no cell.
    let area: f64 = features
        .iter()
        .map(|f| f["properties"]["area"].as_f64().unwrap())
        .sum();
    assert!((area - 1e4).abs() < 1e-6, "{area}");
    assert_eq!(features[3]["properties"]["hidden"], true);
    assert_eq!(features[3]["properties"]["area"], 0.0);
    assert_eq!(features[0]["properties"]["weight"], 2560.0);
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    // A window is the whole diagram's pixels.
    let whole = temp("power-whole.npy");
    let (ok, _, stderr) = run(&["--labels", whole.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = run(&[
        "--window",
        "20,30,50,40",
        "--labels",
        window.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, all) = npy::read::<u32>(&whole).unwrap();
    let (shape, part) = npy::read::<u32>(&window).unwrap();
    assert_eq!(shape, vec![40, 50]);
    for (k, &l) in part.iter().enumerate() {
        assert_eq!(l, all[(30 + k / 50) * 100 + 20 + k % 50], "pixel {k}");
    }
    let (ok, _, stderr) = run(&[
        "--window",
        "20,30,50,40",
        "--cells",
        cells.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("--window"), "{stderr}");
}

#[test]
fn delaunay_builds_regular_triangulations() {
    let sites = temp("regular.csv");
    std::fs::write(&sites, SITES).unwrap();
    let prefix = temp("regular");
    let (ok, stdout, stderr) = pixgeo(&[
        "delaunay",
        "--sites",
        sites.to_str().unwrap(),
        "--weights",
        "power",
        "--triangle",
        prefix.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let result = answer(&stdout, "delaunay");
    assert_eq!(result["hidden"], serde_json::json!([3]));
    assert_eq!(result["triangles"], serde_json::json!([[1, 2, 0]]));
    let node = std::fs::read_to_string(prefix.with_extension("node")).unwrap();
    assert!(node.starts_with("4 2 1 0\n0 10.0 10.0 2560.0\n"), "{node}");
    let (ok, _, stderr) = pixgeo(&["delaunay", "--random", "10", "--weights", "power"]);
    assert!(!ok && stderr.contains("--sites FILE"), "{stderr}");
}
