//! The Voronoi diagram on the Earth: under a geographic coordinate system
//! (or `--metric great-circle`) x is longitude and y latitude, and every
//! pixel's nearest site and distance are by great circle on the mean sphere,
//! in metres.

use anyhow::{bail, Result};
use glam::DVec2;
use pixgeo::{
    algorithms::{
        great_circle::{great_circle_grid, GreatCircleOptions, DISTANCE_ERROR, EARTH_RADIUS},
        voronoi::Accuracy,
    },
    geometry::site::{Shape, Site},
};
use serde_json::json;

use super::{Args, Method};
use crate::{
    device::Backend,
    envelope,
    input::World,
    progress::Progress,
    write::{
        picture::{site_color, PngStream},
        raster,
    },
};

/// Computes and writes the great-circle diagram of point sites.
pub(super) fn diagram(args: &Args, world: &World, general: Vec<Site>) -> Result<()> {
    let planar = [
        (args.ties.is_some(), "--ties"),
        (args.cells.is_some(), "--cells"),
        (args.degree.is_some(), "--degree"),
        (args.order.is_some(), "--order"),
        (args.furthest, "--furthest"),
        (args.window.is_some(), "--window"),
        (args.contours.is_some(), "--contours"),
        (
            !matches!(args.method, Method::Auto | Method::Cones),
            "--method",
        ),
        (args.mode != Accuracy::Exact, "--mode"),
        (args.png().is_none() && args.output.is_some(), "-o *.svg"),
    ];
    if let Some((_, flag)) = planar.iter().find(|(given, _)| *given) {
        bail!(
            "{flag} is not computed on the Earth: great-circle distances give --labels, \
             --distance, -o PNG and --json; give --metric l2 for a planar diagram in degrees"
        );
    }
    let [_, south, _, north] = world.bbox();
    if south < -90.0 || north > 90.0 {
        bail!(
            "the picture reaches latitudes {south} to {north}: under a geographic coordinate \
             system y is a latitude in [-90, 90]; give a --bbox within it"
        );
    }
    // Sites and pixel centres in the user's longitude and latitude.
    let sites: Vec<DVec2> = general
        .iter()
        .enumerate()
        .map(|(i, s)| match s.shape {
            Shape::Point(p) if s.is_plain_point() => Ok(world.to_user(p)),
            _ => bail!("site {i}: great-circle distances take unweighted points"),
        })
        .collect::<Result<_>>()?;
    let frame = world.frame;
    frame.reserve(32, "a great-circle diagram")?;
    let (w, h) = (frame.width, frame.height);
    // Pixel centres: longitudes by column, latitudes by row.
    let centre = |i: u32, j: u32| world.to_user(frame.to_world(DVec2::new(i as f64, j as f64)));
    let lons: Vec<f64> = (0..w).map(|i| centre(i, 0).x).collect();
    let lats: Vec<f64> = (0..h).map(|j| centre(0, j).y).collect();
    // Without a GPU the k-d tree on the CPU is faster than the filter on a
    // software rasterizer (`docs/benchmarks.md`).
    let chosen = crate::device::choose(args.device.as_deref(), crate::device::need(true))?;
    let backend = chosen.backend();
    let started = std::time::Instant::now();
    let progress = Progress::new("voronoi: great circles", args.json);
    let options = GreatCircleOptions::default().control(progress.control());
    let answer = great_circle_grid(&backend, &sites, &lons, &lats, &options)?;
    drop(progress);
    let device = match &backend {
        Backend::Device(machine) => machine.device_name(),
        Backend::Cpu => "cpu",
    };
    let compute_ms = started.elapsed().as_secs_f64() * 1e3;
    let geo = world.georeference();
    if let Some(path) = &args.labels {
        raster::write(path, [w, h, 1], &answer.labels, Some(&geo))?;
    }
    if let Some(path) = &args.distance {
        let metres: Vec<f32> = answer.distances.iter().map(|&d| d as f32).collect();
        raster::write(path, [w, h, 1], &metres, Some(&geo))?;
    }
    if let Some(path) = args.png() {
        let rgb: Vec<u8> = answer.labels.iter().flat_map(|&l| site_color(l)).collect();
        let mut png = PngStream::create(path, w, h)?;
        png.write(&rgb)?;
        png.finish()?;
    }
    let largest = answer.distances.iter().copied().fold(0.0, f64::max);
    if args.json {
        let summary = json!({
            "sites": sites.len(),
            "width": w,
            "height": h,
            "metric": "great-circle",
            "sphere_radius_m": EARTH_RADIUS,
            "distance_error_m": DISTANCE_ERROR,
            "equidistant": answer.equidistant,
            "decided_on_host": answer.decided_on_host,
            "largest_distance_m": largest,
            "stats": { "compute_ms": compute_ms },
        });
        envelope::print_world("voronoi", device, world, &summary)?;
    } else {
        outln!(
            "{} sites, {w}x{h} pixels: great-circle distances on the sphere of the Earth's \
             mean radius ({EARTH_RADIUS} m), within {DISTANCE_ERROR:.1e} m; largest {largest:.3} m; \
             labels proven, {} pixels equidistant to two sites or more (the lower index)",
            sites.len(),
            answer.equidistant
        );
    }
    Ok(())
}
