//! `pixgeo voronoi`: pictures and arrays, weights and shapes, windows, levels,
//! the CPU algorithms, flooding's seeds, and sites past memory.

use super::*;

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
    // The device's name is read in any case.
    for (flags, out) in [
        (["--device", "CPU"], &cpu_labels),
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
    // Without Vulkan, the grid gives the same window.
    let out = temp("w-cpu.npy");
    let (ok, _, stderr) = pixgeo(&[
        "voronoi",
        "--sites",
        s,
        "--size",
        "64x48",
        "--window",
        "0,0,25,48",
        "--device",
        "cpu",
        "--labels",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (_, cpu): (Vec<u64>, Vec<u32>) = npy::read(&out).unwrap();
    assert_eq!(cpu, halves[0].1);
    let (ok, _, stderr) = pixgeo(&[
        "voronoi", "--sites", s, "--size", "64x48", "--window", "0,0,8,8", "--device", "cpu",
        "--metric", "l1",
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
fn levels_beyond_the_distinct_sites_are_refused_by_name() {
    let sites = temp("three.csv");
    // Three sites, two of them at one place.
    std::fs::write(&sites, "x,y\n3,4\n3,4\n20,30\n").unwrap();
    let s = sites.to_str().unwrap();
    for flag in ["--order", "--degree"] {
        let (ok, _, stderr) = pixgeo(&["voronoi", "--sites", s, "--size", "32", flag, "3"]);
        assert!(
            !ok && stderr.contains(&format!(
                "{flag} 3 asks for 3 nearest sites, but there are only 2 distinct sites"
            )),
            "{flag}: {stderr}"
        );
        let (ok, _, stderr) =
            pixgeo(&["voronoi", "--sites", s, "--size", "32", flag, "2", "--json"]);
        assert!(ok, "{flag} 2: {stderr}");
    }
}

#[test]
fn labels_are_exact_for_the_doubles_given() {
    // Two sites mirrored about the centre of pixel (5, 0), the second one ulp
    // nearer to it: float32 sites tie there and give the first; the exact
    // nearest is the second, on the device and on the CPU alike.
    let sites = temp("mirrored.csv");
    std::fs::write(&sites, "x,y\n5.3,0\n4.700000000000001,0\n").unwrap();
    let s = sites.to_str().unwrap();
    for device in ["lavapipe", "cpu"] {
        let labels = temp(&format!("mirrored_{device}.npy"));
        let l = labels.to_str().unwrap();
        let (ok, _, stderr) = pixgeo(&[
            "voronoi", "--sites", s, "--size", "12x4", "--device", device, "--labels", l,
        ]);
        assert!(ok, "{stderr}");
        let map: Vec<u32> = npyz::NpyFile::new(std::fs::File::open(&labels).unwrap())
            .unwrap()
            .into_vec()
            .unwrap();
        assert_eq!(map[5], 1, "{device}");
    }
}
