//! Work the process cannot hold is refused before it allocates: under an
//! address-space limit, exit 1 with the size it needs, outputs untouched, where
//! an allocation failure would abort (SIGABRT) or the driver crash.

use super::*;

/// Runs pixgeo with `args` under `ulimit -v` of 1.5 GB, a sentinel in place
/// of `output`; returns stderr after checking the exit and the sentinel.
fn refused_under_limit(args: &[&str], output: &Path) -> String {
    std::fs::write(output, "sentinel").unwrap();
    let out = Command::new("bash")
        .arg("-c")
        .arg("ulimit -v 1500000 && exec \"$@\"")
        .arg("pixgeo")
        .arg(env!("CARGO_BIN_EXE_pixgeo"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run pixgeo");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(
        stderr.contains("needs about") && stderr.contains("more than this process can have"),
        "{args:?}: {stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(output).unwrap(),
        "sentinel",
        "{args:?}"
    );
    stderr
}

#[test]
fn work_larger_than_the_process_may_hold_is_refused_with_its_size() {
    let out = temp("memory-out.npy");
    let o = out.to_str().unwrap();
    let png = temp("memory-out.png");
    let p = png.to_str().unwrap();
    let stderr = refused_under_limit(&["voronoi", "--random", "20000000", "--labels", o], &out);
    assert!(stderr.contains("20000000 sites"), "{stderr}");
    // The CPU's pixel algorithm holds the whole picture (the grid streams
    // Euclidean labels band by band, and needs no such room).
    let big_cpu = [
        "voronoi", "--random", "100", "--size", "16384", "--device", "cpu", "--metric", "l1",
        "--labels", o,
    ];
    refused_under_limit(&big_cpu, &out);
    let trace = temp("memory-trace.json");
    let t = trace.to_str().unwrap();
    let diameter = [
        "diameter", "--random", "100", "--size", "16384", "--trace", t,
    ];
    refused_under_limit(&diameter, &trace);
    let alpha = [
        "alpha", "--alpha", "-0.1", "--random", "100", "--size", "16384", "-o", p,
    ];
    let stderr = refused_under_limit(&alpha, &png);
    assert!(stderr.contains("an α-hull of "), "{stderr}");
    // A 12000² mask: 144 MB of pixels, 5.8 GB to transform.
    let mask = temp("memory-mask.png");
    image::GrayImage::new(12000, 12000).save(&mask).unwrap();
    let transform = [
        "transform",
        "--mask",
        mask.to_str().unwrap(),
        "--distance",
        o,
    ];
    let stderr = refused_under_limit(&transform, &out);
    assert!(stderr.contains("distance transform"), "{stderr}");
    // The same as .npy: its values as doubles, before the transform.
    let npy = temp("memory-mask.npy");
    write_npy(&npy, &[12000, 12000], &vec![false; 12000 * 12000]);
    let transform = [
        "transform",
        "--mask",
        npy.to_str().unwrap(),
        "--distance",
        o,
    ];
    let stderr = refused_under_limit(&transform, &out);
    assert!(stderr.contains("144000000 values"), "{stderr}");
    std::fs::remove_file(&npy).unwrap();
    let samples = temp("memory-samples.csv");
    std::fs::write(&samples, "x,y,z\n10,10,1\n100,20,2\n50,90,3\n").unwrap();
    let s = samples.to_str().unwrap();
    for method in ["exact", "nearest", "discrete"] {
        let interpolate = [
            "interpolate",
            "--sites",
            s,
            "--size",
            "16384",
            "--method",
            method,
            "--raster",
            o,
        ];
        let stderr = refused_under_limit(&interpolate, &out);
        assert!(stderr.contains("an interpolated raster"), "{stderr}");
    }
}
