//! `pixgeo transform`: masks from PNG and `.npy`, SciPy's layout, medial axes.

use super::*;

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
    write_npy(&empty, &[2, 2], &[0.0f64; 4]);
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
        (vec!["--distance", "d.png"], "name the file *.npy or *.tif"),
        (
            vec!["--medial-axis", "a.tiff.txt"],
            "name the file *.npy or *.tif",
        ),
        (vec!["--json", "--crs", "4326"], "EPSG:N"),
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
    write_npy(&bar, &[9, 20], &border);
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
    write_npy(&cube, &[2, 2, 2], &[1u8; 8]);
    let (ok, _, stderr) = pixgeo(&["transform", "--mask", cube.to_str().unwrap(), "--json"]);
    assert!(!ok && stderr.contains("2-D array"), "{stderr}");
}
