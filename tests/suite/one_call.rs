//! The one-call functions on a machine without a Vulkan driver: those with
//! a CPU algorithm answer, as their oracles do, without loading Vulkan.

use std::process::Command;

use glam::DVec2;
use pixgeo::geometry::{metric::Metric, Frame};
use pixgeo_reference::exact::exact_k_nearest;

/// Runs [`answers_on_the_cpu`] in a child process whose Vulkan loader finds
/// no driver.
#[test]
fn one_call_functions_answer_without_a_vulkan_driver() {
    let dir = std::env::temp_dir().join(format!("pixgeo-no-driver-{}", std::process::id()));
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "one_call::answers_on_the_cpu", "--ignored"])
        .env("VK_DRIVER_FILES", dir.join("none.json"))
        .env_remove("PIXGEO_DEVICE")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("1 passed"),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
#[ignore = "run without a driver by one_call_functions_answer_without_a_vulkan_driver"]
fn answers_on_the_cpu() {
    let sites: Vec<DVec2> = (0..25)
        .map(|k| DVec2::new((k % 5) as f64 * 3.0 + 0.5, (k / 5) as f64 * 2.0 + 1.0))
        .collect();
    let frame = Frame::pixels(16, 12).unwrap();
    let (nearest, _) = exact_k_nearest(&sites, &frame, Metric::L2, 1);
    assert_eq!(pixgeo::voronoi(&sites, 16, 12).unwrap().labels, nearest);
    let (two, _) = exact_k_nearest(&sites, &frame, Metric::L2, 2);
    assert_eq!(pixgeo::k_nearest(&sites, 16, 12, 2).unwrap().labels, two);
    assert_eq!(
        pixgeo::furthest(&sites, 16, 12).unwrap().labels.len(),
        16 * 12
    );
    // A 5 x 5 lattice: two triangles a square.
    assert_eq!(pixgeo::delaunay(&sites).unwrap().triangles.len(), 32);
    let h = pixgeo::hausdorff(&sites[..3], &sites[20..]).unwrap();
    assert_eq!(h.distance, 10.0);
    assert!(pixgeo::settle(&sites, 16, 12).is_ok());
}
