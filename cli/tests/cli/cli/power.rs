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
        "--cells",
        "c.geojson",
    ]);
    assert!(!ok && stderr.contains("--cells"), "{stderr}");
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
