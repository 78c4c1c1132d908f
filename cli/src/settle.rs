//! `pixgeo settle`: where a new site would win the largest Voronoi region.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::settle::{
        potential_areas, refine, PotentialAreas, Refined, SettleMethod, SettleOptions,
    },
    geometry::{metric::Metric, Frame},
};
use pixgeo_io::sites;
use serde_json::{json, Value};

use crate::{
    device::Backend,
    envelope,
    input::{Input, World},
    progress::Progress,
    write::{
        output::{check_distinct, check_extension},
        picture::PngStream,
        raster,
    },
};

/// Finds the settle point (thesis §3.10): the place where a new site, added to
/// the existing ones (a rival's stores, say), would own the largest Voronoi
/// region.
///
/// Every pixel t gets its potential area: the number of pixels nearer to t than
/// to any existing site. Turned around, each pixel p lies in the regions of all
/// candidates inside the disc around p whose radius is p's distance to its
/// nearest site, so counting how many discs cover each pixel gives the whole map.
/// `--method spans` (default) cuts every disc into spans along rows, columns and
/// diagonals, adds +1/-1 at their ends in a compute pass and sums along them;
/// `--method faithful` draws every disc and
/// counts with the stencil's wrap-around and blending, as the thesis did. Both
/// give the same counts. With the Euclidean metric the best pixels are then
/// refined to the exact region area of a real-valued position.
///
/// Examples:
///
///   pixgeo settle --random 20 --size 512 -o settle.png --json
///
///   pixgeo settle --sites rivals.csv --own mine.csv --bbox 0,0,10,10 --size 800 --area area.npy
///
///   pixgeo settle --random 18 --metric lp:0.5 --size 400 -o l05.png
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// The existing sites (--sites or --random) and the picture.
    #[command(flatten)]
    input: Input,

    /// The user's own stores (thesis §3.10.3): pixels already nearest to one of
    /// them do not count, since a new store cannot win them from a rival.
    #[arg(long, value_name = "FILE")]
    own: Option<PathBuf>,

    /// Distance function: `l2`, `l1`, `linf` or `lp:P` (any P > 0; the disc is
    /// the metric's ball). The exact refinement is Euclidean only. Default:
    /// l2; under a geographic --crs, where the settle point is not computed
    /// on the Earth, give it to measure degrees on the plane.
    #[arg(long, value_parser = pixgeo_io::sites::parse_metric)]
    metric: Option<Metric>,

    /// How the discs are counted (on a Vulkan device): `spans`, +1/-1 at
    /// every disc row's ends and prefix sums along the rows (§3.12.3), or
    /// `faithful`, every disc drawn and counted by stencil wrap-around and
    /// blending (Fig. 3.49).
    #[arg(long, default_value = "spans", value_parser = crate::input::named::<SettleMethod>)]
    method: SettleMethod,

    /// Write a PNG: brightness is the potential area, existing sites green, own
    /// stores blue, the settle point circled in red.
    #[arg(short = 'o', long = "output", value_name = "PICTURE.png")]
    output: Option<PathBuf>,

    /// Write the potential-area map as .npy (uint32, H×W, pixels) or as a
    /// GeoTIFF (.tif).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    area: Option<PathBuf>,

    /// Best pixels the exact refinement starts from (Euclidean metric; 0 turns
    /// it off).
    #[arg(long, default_value_t = 8, value_name = "K")]
    refine_from: usize,

    /// Print the answer as one JSON object.
    #[arg(long)]
    json: bool,

    /// Where to compute: `cpu` runs the thesis's CPU variant (§3.12.3); `auto`,
    /// `gpu`, `lavapipe`, an index or part of a name picks a Vulkan device
    /// (default: PIXGEO_DEVICE, else a GPU if present, else lavapipe; without any
    /// Vulkan driver, the CPU).
    #[arg(long)]
    device: Option<String>,
}

pub fn run(args: Args) -> Result<()> {
    if let Some(path) = &args.area {
        raster::check_name(path, "potential-area maps")?;
    }
    if let Some(path) = &args.output {
        check_extension(path, "png", "pictures")?;
    }
    check_distinct([
        ("--area", args.area.as_deref()),
        ("-o", args.output.as_deref()),
    ])?;
    args.input.check_world_file()?;
    let (world, rivals) = args.input.world_and_sites()?;
    let metric = match (args.metric, world.is_geographic()) {
        (None, true) => bail!(
            "the settle point is computed on the plane, not on the Earth: under EPSG:{} give \
             --metric l2 (or another) to measure degrees on the longitude-latitude plane",
            world.epsg.unwrap_or_default()
        ),
        (Some(m), true) => {
            world.warn_if_geographic(&format!(
                "--metric {m} measures the market areas in square degrees,"
            ));
            m
        }
        (m, false) => m.unwrap_or(Metric::L2),
    };
    let metric = world.metric(metric);
    let frame = world.frame;
    let own: Vec<DVec2> = match &args.own {
        Some(path) => sites::read_sites(path)?,
        None => Vec::new(),
    };
    let own: Vec<DVec2> = own.into_iter().map(|p| world.to_user(p)).collect();
    let method = args.method;
    let chosen = crate::device::choose(args.device.as_deref(), crate::device::need(false))?;
    let backend = chosen.backend();
    let progress = match backend {
        Backend::Device(_) => Progress::new(
            &format!("counting discs ({method:?})").to_lowercase(),
            args.json,
        ),
        Backend::Cpu => Progress::working("counting spans", args.json),
    };
    let options = SettleOptions::new(frame)
        .metric(metric)
        .method(method)
        .control(progress.control());
    let map = potential_areas(&backend, &rivals, &own, &options)?;
    drop(progress);
    let refined = if metric == Metric::L2 && args.refine_from > 0 {
        Some(refine(
            &rivals,
            &own,
            &frame,
            &map.leaders(args.refine_from),
        )?)
    } else {
        None
    };

    if let Some(path) = &args.area {
        let size = [frame.width, frame.height, 1];
        raster::write(path, size, &map.area, Some(&world.georeference()))?;
    }
    if let Some(path) = &args.output {
        write_picture(path, &map, &frame, &rivals, &own)?;
    }
    crate::wrote([args.area.as_deref(), args.output.as_deref()]);
    args.input.write_world_file(&world, (0, 0))?;
    let summary = summary(&map, &world, refined.as_ref(), (&args, &metric));
    if args.json {
        envelope::print_world("settle", backend.name(), &world, &summary)?;
    } else {
        print_summary(&summary);
    }
    Ok(())
}

fn pixel_of(map: &PotentialAreas, k: usize) -> [u32; 2] {
    [
        (k % map.width as usize) as u32,
        (k / map.width as usize) as u32,
    ]
}

fn summary(
    map: &PotentialAreas,
    world: &World,
    refined: Option<&Refined>,
    (args, metric): (&Args, &Metric),
) -> Value {
    let frame = &world.frame;
    let world = |p: DVec2| world.to_user(frame.to_world(p)).to_array();
    let pixel_area = 1.0 / (frame.scale * frame.scale);
    let best = pixel_of(map, map.best[0]);
    let best_point = DVec2::new(best[0] as f64, best[1] as f64);
    json!({
        "method": if map.stats.device == "cpu" {
            "spans (cpu)".to_string()
        } else {
            format!("{:?}", args.method).to_lowercase()
        },
        "metric": metric.to_string(),
        "settle": {
            "pixel": best,
            "point": world(best_point),
            "area_pixels": map.best_area,
            "area": map.best_area as f64 * pixel_area,
        },
        "ties": map.best.len(),
        "tied_pixels": map.best.iter().take(64).map(|&k| pixel_of(map, k)).collect::<Vec<_>>(),
        "refined": refined.map(|r| json!({
            "point": world(DVec2::from_array(r.position)),
            "area": r.area * pixel_area,
            "area_pixels": r.area,
            "start_pixel": r.start_pixel,
            "start_area_pixels": r.start_area,
        })),
        "stats": map.stats,
    })
}

fn print_summary(s: &Value) {
    let settle = &s["settle"];
    outln!(
        "settle point: pixel {} = {} wins {} pixels (area {:.6})",
        settle["pixel"],
        settle["point"],
        settle["area_pixels"],
        settle["area"]
    );
    if s["ties"].as_u64().unwrap_or(0) > 1 {
        outln!("{} pixels tie for the largest potential area", s["ties"]);
    }
    if let Some(r) = s["refined"].as_object() {
        outln!(
            "refined: {} wins an exact area of {:.6} ({:.3} square pixels; {:.3} at pixel {})",
            r["point"],
            r["area"],
            r["area_pixels"],
            r["start_area_pixels"],
            r["start_pixel"]
        );
    }
    let stats = &s["stats"];
    note!(
        "{} on {}: radii {:.1} ms, counting {:.1} ms, readback {:.1} ms",
        s["method"].as_str().unwrap_or_default(),
        stats["device"].as_str().unwrap_or_default(),
        stats["radii_ms"].as_f64().unwrap_or(0.0),
        stats["count_ms"].as_f64().unwrap_or(0.0),
        stats["readback_ms"].as_f64().unwrap_or(0.0)
    );
}

/// The potential area as brightness (thesis Fig. 3.46), with the sites on top.
fn write_picture(
    path: &std::path::Path,
    map: &PotentialAreas,
    frame: &Frame,
    rivals: &[DVec2],
    own: &[DVec2],
) -> Result<()> {
    let (w, h) = (map.width as usize, map.height as usize);
    let top = map.best_area.max(1) as f64;
    let mut rgb: Vec<u8> = map
        .area
        .iter()
        .flat_map(|&a| {
            // A warm ramp: black, red, orange, pale yellow.
            let v = a as f64 / top;
            [
                (255.0 * (1.6 * v).min(1.0)) as u8,
                (255.0 * (1.6 * v - 0.45).clamp(0.0, 1.0)) as u8,
                (255.0 * (2.0 * v - 1.2).clamp(0.0, 0.8)) as u8,
            ]
        })
        .collect();
    let mut paint = |p: DVec2, radius: f64, ring: bool, colour: [u8; 3]| {
        let r = radius.ceil() as i64 + 1;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (p.x.round() as i64 + dx, p.y.round() as i64 + dy);
                if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
                    continue;
                }
                let d = ((x as f64 - p.x).powi(2) + (y as f64 - p.y).powi(2)).sqrt();
                let hit = if ring {
                    (d - radius).abs() < 0.9
                } else {
                    d <= radius
                };
                if hit {
                    let k = 3 * (y as usize * w + x as usize);
                    rgb[k..k + 3].copy_from_slice(&colour);
                }
            }
        }
    };
    let dot = (w.max(h) as f64 / 300.0).max(1.5);
    for &s in rivals {
        paint(frame.to_pixel(s), dot, false, [40, 220, 90]);
    }
    for &s in own {
        paint(frame.to_pixel(s), dot, false, [60, 140, 255]);
    }
    for &k in map.best.iter().take(16) {
        let p = pixel_of(map, k);
        paint(
            DVec2::new(p[0] as f64, p[1] as f64),
            3.0 * dot,
            true,
            [255, 30, 30],
        );
    }
    let mut png = PngStream::create(path, map.width, map.height)?;
    png.write(&rgb)?;
    png.finish()?;
    Ok(())
}
