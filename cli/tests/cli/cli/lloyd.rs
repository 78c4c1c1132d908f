//! `pixgeo lloyd`: points, labels and pictures that load, energies that
//! never increase, a density that draws the points to its dark side, and
//! clear refusals.

use super::*;

fn points(path: &Path) -> Vec<[f64; 2]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let (x, y) = l.split_once(',').unwrap();
            [x.parse().unwrap(), y.parse().unwrap()]
        })
        .collect()
}

#[test]
fn lloyd_writes_its_outputs_and_its_energy_falls() {
    let (csv, labels, png, svg) = (
        temp("lloyd.csv"),
        temp("lloyd-labels.npy"),
        temp("lloyd.png"),
        temp("lloyd.svg"),
    );
    let (ok, stdout, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "60",
        "--bbox",
        "0,0,12,8",
        "--size",
        "96",
        "--iterations",
        "40",
        "--points",
        csv.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let result = answer(&stdout, "lloyd");
    let energy: Vec<f64> = result["energy"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_f64().unwrap())
        .collect();
    assert!(energy.len() >= 2);
    for pair in energy.windows(2) {
        assert!(pair[1] <= pair[0] * (1.0 + 1e-12), "{energy:?}");
    }
    // The points in the user's coordinates, inside the box.
    let p = points(&csv);
    assert_eq!(p.len(), 60);
    assert!(p
        .iter()
        .all(|[x, y]| (0.0..=12.0).contains(x) && (0.0..=8.0).contains(y)));
    let (shape, l) = npy::read::<u32>(&labels).unwrap();
    assert_eq!(shape, vec![64, 96]);
    assert!(l.iter().all(|&k| k < 60));
    let picture = image::open(&png).unwrap();
    assert_eq!((picture.width(), picture.height()), (96, 64));
    let (ok, _, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "30",
        "--size",
        "64",
        "--iterations",
        "3",
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches("<circle").count(), 30);
}

#[test]
fn a_density_draws_the_points_to_its_dark_side() {
    // Dark (density 255) on the left third, light (density 15) on the rest.
    let (w, h) = (90u32, 60u32);
    let density = temp("lloyd-density.png");
    let grey = image::GrayImage::from_fn(w, h, |x, _| image::Luma([if x < 30 { 0 } else { 240 }]));
    grey.save(&density).unwrap();
    let csv = temp("lloyd-dense.csv");
    let (ok, _, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "40",
        "--size",
        "90x60",
        "--density",
        density.to_str().unwrap(),
        "--iterations",
        "30",
        "--points",
        csv.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    // The same start without the density: the dark third keeps its third of
    // the points (14); with it, the iterations draw more there (18).
    let uniform = temp("lloyd-uniform.csv");
    let (ok, _, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "40",
        "--size",
        "90x60",
        "--iterations",
        "30",
        "--points",
        uniform.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let dark = |path: &Path| points(path).iter().filter(|[x, _]| *x < 30.0).count();
    assert!(
        dark(&csv) >= dark(&uniform) + 3,
        "{} against {}",
        dark(&csv),
        dark(&uniform)
    );
    let (ok, _, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "40",
        "--size",
        "64",
        "--density",
        density.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("give --size 90x60"), "{stderr}");
    let bad = temp("lloyd-negative.npy");
    write_npy(&bad, &[4, 4], &[-1.0f64; 16]);
    let (ok, _, stderr) = pixgeo(&[
        "lloyd",
        "--random",
        "4",
        "--size",
        "4",
        "--density",
        bad.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("not negative"), "{stderr}");
    let (ok, _, stderr) = pixgeo(&["lloyd", "--random", "4", "--points", "p.txt"]);
    assert!(!ok && stderr.contains(".csv"), "{stderr}");
}
