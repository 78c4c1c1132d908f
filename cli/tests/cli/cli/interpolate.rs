//! `pixgeo interpolate`: every sample format and method, rasters that load
//! (NaN outside the hull, the GeoTIFF's nodata NaN), a plane reproduced
//! exactly, and clear refusals.

use super::*;

/// Samples of the plane 2x + 3y + 1 at whole points, the picture's corners
/// among them, so that every pixel centre (whole points too) has a value.
fn plane_samples() -> Vec<[f64; 3]> {
    let mut samples = vec![[0.0, 0.0], [31.0, 0.0], [0.0, 23.0], [31.0, 23.0]];
    samples.extend((0..20).map(|k| [((k * 7) % 29 + 1) as f64, ((k * 5) % 21 + 1) as f64]));
    samples
        .iter()
        .map(|&[x, y]| [x, y, 2.0 * x + 3.0 * y + 1.0])
        .collect()
}

#[test]
fn interpolate_reads_every_format_and_reproduces_a_plane() {
    let samples = plane_samples();
    let csv = temp("interpolate-plane.csv");
    let text: String = samples
        .iter()
        .map(|s| format!("{},{},{}\n", s[1], s[0], s[2]))
        .collect();
    std::fs::write(&csv, format!("y,x,height\n{text}")).unwrap();
    let geojson = temp("interpolate-plane.geojson");
    let features: Vec<String> = samples
        .iter()
        .map(|s| {
            format!(
                r#"{{"type": "Feature", "properties": {{"height": {}}}, "geometry": {{"type": "Point", "coordinates": [{}, {}]}}}}"#,
                s[2], s[0], s[1]
            )
        })
        .collect();
    std::fs::write(
        &geojson,
        format!(
            r#"{{"type": "FeatureCollection", "features": [{}]}}"#,
            features.join(",")
        ),
    )
    .unwrap();
    let npy_samples = temp("interpolate-plane.npy");
    let flat: Vec<f64> = samples.iter().flatten().copied().collect();
    write_npy(&npy_samples, &[samples.len() as u64, 3], &flat);
    for (file, method) in [
        (&csv, "exact"),
        (&geojson, "linear"),
        (&npy_samples, "exact"),
        (&csv, "discrete"),
        (&csv, "nearest"),
    ] {
        let raster = temp(&format!("interpolate-{method}.npy"));
        let (ok, stdout, stderr) = pixgeo(&[
            "interpolate",
            "--sites",
            file.to_str().unwrap(),
            "--value",
            "height",
            "--method",
            method,
            "--size",
            "32x24",
            "--raster",
            raster.to_str().unwrap(),
            "--json",
        ]);
        assert!(ok, "{method}: {stderr}");
        let result = answer(&stdout, "interpolate");
        assert_eq!(result["method"], method);
        assert_eq!(result["with_value"], 32 * 24);
        let (shape, values) = npy::read::<f64>(&raster).unwrap();
        assert_eq!(shape, vec![24, 32]);
        let mut error = 0.0;
        for (k, v) in values.iter().enumerate() {
            let want = 2.0 * (k % 32) as f64 + 3.0 * (k / 32) as f64 + 1.0;
            match method {
                // Sibson's and the linear interpolants reproduce a plane,
                // and the exact value is a whole number.
                "exact" | "linear" => assert_eq!(*v, want, "{method}, pixel {k}"),
                "discrete" if (8..24).contains(&(k % 32)) && (6..18).contains(&(k / 32)) => {
                    error += (v - want).abs() / 192.0
                }
                "discrete" => {}
                _ => assert!(samples.iter().any(|s| s[2] == *v)),
            }
        }
        // A pixel's rise is 2 to 3; the discrete errs most along the hull
        // (here the frame), least in the middle.
        eprintln!("discrete: mean error {error} in the middle");
        assert!(error < 1.5, "discrete: mean error {error} in the middle");
    }
}

#[test]
fn interpolate_leaves_nan_outside_the_hull_and_marks_it_nodata() {
    let (tif, png) = (temp("interpolate.tif"), temp("interpolate.png"));
    let (ok, stdout, stderr) = pixgeo(&[
        "interpolate",
        "--sites",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/data/heights.csv"),
        "--bbox",
        "0,0,100,100",
        "--size",
        "100",
        "--raster",
        tif.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("80 samples onto 100x100 pixels"),
        "{stdout}"
    );
    let bytes = std::fs::read(&tif).unwrap();
    // GDAL_NODATA, tag 42113, holds "nan".
    assert!(bytes.windows(4).any(|w| w == b"nan\0"));
    let picture = image::open(&png).unwrap().to_rgb8();
    assert_eq!(picture.dimensions(), (100, 100));
    // The picture's corner lies outside the samples' hull: white.
    assert_eq!(picture.get_pixel(0, 0).0, [255, 255, 255]);
}

#[test]
fn interpolate_refuses_clearly() {
    let heights = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/data/heights.csv");
    let cases: [(&[&str], &str); 4] = [
        (&["--sites", heights, "--value", "t"], "no column `t`"),
        (
            &["--sites", heights, "--method", "cubic"],
            "unknown interpolation method",
        ),
        (&["--random", "10"], "--sites FILE"),
        (&["--sites", heights, "--raster", "out.png"], "out.png"),
    ];
    for (args, message) in cases {
        let mut all = vec!["interpolate"];
        all.extend_from_slice(args);
        let (ok, _, stderr) = pixgeo(&all);
        assert!(!ok && stderr.contains(message), "{args:?}: {stderr}");
    }
}
