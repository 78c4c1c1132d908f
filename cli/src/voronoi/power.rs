//! The power (Laguerre) diagram of points with power weights, on the CPU
//! over their exact regular triangulation.

use anyhow::{bail, Result};
use glam::DVec2;
use pixgeo::{
    algorithms::{
        power::{power_diagram, PowerOptions},
        voronoi::Accuracy,
    },
    geometry::power::Weighted,
    memory::reserve_picture,
};
use pixgeo_io::samples::Samples;
use serde_json::json;

use super::{Args, Method};
use crate::{
    cells, envelope,
    input::World,
    progress::Progress,
    write::{
        picture::{site_color, PngStream},
        raster,
    },
};

/// Computes and writes the power diagram of weighted points.
pub(super) fn diagram(args: &Args, world: &World, samples: Samples) -> Result<()> {
    let other = [
        (args.degree.is_some(), "--degree"),
        (args.order.is_some(), "--order"),
        (args.furthest, "--furthest"),
        (args.contours.is_some(), "--contours"),
        (args.metric_choice.is_some(), "--metric"),
        (
            !matches!(args.method, Method::Auto | Method::Cones),
            "--method",
        ),
        (args.mode != Accuracy::Exact, "--mode"),
    ];
    if let Some((_, flag)) = other.iter().find(|(given, _)| *given) {
        bail!(
            "{flag} is not computed for power diagrams: they give --labels, --distance, \
             --ties, --cells, -o PNG or SVG, --window and --json"
        );
    }
    if args
        .device
        .as_deref()
        .is_some_and(|d| d != "cpu" && d != "auto")
    {
        note!("note: power diagrams are computed on the CPU, whatever --device names");
    }
    let sites = Weighted::zip(&samples.points, &samples.values);
    let frame = world.frame;
    let window = frame.window_rect(args.window)?;
    let (w, h) = (window.width, window.height);
    reserve_picture(w, h, 12, "a power diagram")?;
    let started = std::time::Instant::now();
    let progress = Progress::new("voronoi: power rows", args.json);
    let options = PowerOptions::new(frame)
        .window(Some(window))
        .control(progress.control());
    let answer = power_diagram(&sites, &options)?;
    drop(progress);
    let compute_ms = started.elapsed().as_secs_f64() * 1e3;
    let geo = world.georeference_from(window.x, window.y);
    if let Some(path) = &args.labels {
        raster::write(path, [w, h, 1], &answer.labels, Some(&geo))?;
    }
    if let Some(path) = &args.distance {
        raster::write(path, [w, h, 1], &answer.powers, Some(&geo))?;
    }
    if let Some(path) = &args.ties {
        raster::write(path, [w, h, 1], &answer.ties, Some(&geo))?;
    }
    if let Some(path) = args.png() {
        let mut rgb: Vec<u8> = answer.labels.iter().flat_map(|&l| site_color(l)).collect();
        // Each site a black dot; a hidden one an open ring.
        for (k, s) in sites.iter().enumerate() {
            let hidden = answer.regular.hidden.binary_search(&(k as u32)).is_ok();
            let p = frame.to_pixel(s.at).round() - DVec2::new(window.x as f64, window.y as f64);
            for (dx, dy) in (-3i64..=3).flat_map(|x| (-3i64..=3).map(move |y| (x, y))) {
                let r2 = dx * dx + dy * dy;
                let (x, y) = (p.x as i64 + dx, p.y as i64 + dy);
                let mark = if hidden {
                    (5..=9).contains(&r2)
                } else {
                    r2 <= 4
                };
                if mark && x >= 0 && y >= 0 && x < w as i64 && y < h as i64 {
                    let at = 3 * (y as usize * w as usize + x as usize);
                    rgb[at..at + 3].fill(0);
                }
            }
        }
        let mut png = PngStream::create(path, w, h)?;
        png.write(&rgb)?;
        png.finish()?;
    }
    let source = cells::Source::Power {
        regular: &answer.regular,
        sites: &sites,
    };
    let points: Vec<DVec2> = sites.iter().map(|s| s.at).collect();
    cells::write(args.vectors(), world, source, &points)?;
    if args.json {
        let summary = json!({
            "sites": sites.len(),
            "width": w,
            "height": h,
            "metric": "power",
            "hidden": answer.regular.hidden,
            "triangles": answer.regular.triangles.len(),
            "stats": { "compute_ms": compute_ms },
        });
        envelope::print_world("voronoi", "cpu", world, &summary)?;
    } else {
        outln!(
            "{} sites, {w}x{h} pixels: power diagram, labels exact; {} hidden sites own no cell",
            sites.len(),
            answer.regular.hidden.len()
        );
    }
    Ok(())
}
