//! `pixgeo lloyd`: centroidal Voronoi tessellations and stippling.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::lloyd::{check_density, lloyd, Lloyd, LloydOptions},
    geometry::Frame,
};
use pixgeo_io::mask::read_density;
use serde_json::json;

use crate::{
    envelope,
    input::{Input, World},
    progress::Progress,
    text::Real,
    write::{
        npy,
        output::{check_distinct, check_extensions, extension_among, write_text},
        picture::PngStream,
        raster,
    },
};

/// Moves the sites by Lloyd's iterations to a centroidal Voronoi
/// tessellation: each iteration draws the exact Voronoi diagram on the
/// picture, sums every region's pixels (weighted by --density) and moves
/// each site to its region's centroid. The centroids are exact for the
/// digital regions: whole-number sums, rounded once to the nearest double.
/// With a density (a picture, dark is dense) the points stipple it, as
/// Secord's weighted Voronoi stippling does.
///
/// Examples:
///
///   pixgeo lloyd --random 500 --size 512 --points cvt.csv -o cvt.png --json
///
///   pixgeo lloyd --random 4000 --density portrait.png --size 600x800 --iterations 80 -o stipple.svg
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// The starting sites (--sites or --random) and the picture.
    #[command(flatten)]
    input: Input,

    /// Iterations at most.
    #[arg(long, default_value_t = 50, value_name = "K")]
    iterations: u32,

    /// Stop once no site moves farther than this (world units; default a
    /// hundredth of a pixel).
    #[arg(long, value_name = "DISTANCE")]
    tolerance: Option<f64>,

    /// The density, one value per pixel of the picture (its size must be
    /// --size's): `.npy` (a 2-D array of values, finite and not negative) or
    /// `.png` (dark is dense: 255 minus the grey level). --random then draws
    /// the starting points from it. Default: uniform.
    #[arg(long, value_name = "FILE.npy|FILE.png")]
    density: Option<PathBuf>,

    /// Write the final sites: `.csv` (x,y) or `.npy` (n×2 float64), in input
    /// order.
    #[arg(long, value_name = "FILE.csv|FILE.npy")]
    points: Option<PathBuf>,

    /// Write every pixel's nearest final site: `.npy` (uint32, H×W) or
    /// GeoTIFF (`.tif`).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    labels: Option<PathBuf>,

    /// Write a stippling picture: `.png` (black dots on white) or `.svg`.
    #[arg(short = 'o', long = "output", value_name = "PICTURE.png|PICTURE.svg")]
    output: Option<PathBuf>,

    /// Print the answer as one JSON object.
    #[arg(long)]
    json: bool,

    /// Where to compute: `cpu` runs the thesis's CPU pixel algorithms (§3.12);
    /// `auto`, `gpu`, `lavapipe`, an index or part of a name picks a Vulkan
    /// device (default: PIXGEO_DEVICE, else a GPU if present, else lavapipe;
    /// without any Vulkan driver, the CPU).
    #[arg(long)]
    device: Option<String>,
}

pub fn run(args: Args) -> Result<()> {
    if let Some(path) = &args.points {
        check_extensions(path, &["csv", "npy"], "points")?;
    }
    if let Some(path) = &args.labels {
        raster::check_name(path, "label rasters")?;
    }
    if let Some(path) = &args.output {
        check_extensions(path, &["png", "svg"], "stippling pictures")?;
    }
    check_distinct([
        ("--points", args.points.as_deref()),
        ("--labels", args.labels.as_deref()),
        ("-o", args.output.as_deref()),
    ])?;
    args.input.check_world_file()?;
    let (world, mut sites) = args.input.world_and_sites()?;
    if world.is_geographic() {
        world.warn_if_geographic("Lloyd's centroids are taken");
    }
    let frame = world.frame;
    let density = match &args.density {
        Some(path) => {
            let raster = read_density(path)?;
            if (raster.width, raster.height) != (frame.width as u64, frame.height as u64) {
                bail!(
                    "{} is {}x{} pixels, the picture {}x{}: give --size {}x{}",
                    path.display(),
                    raster.width,
                    raster.height,
                    frame.width,
                    frame.height,
                    raster.width,
                    raster.height
                );
            }
            Some(raster.values)
        }
        None => None,
    };
    if let (Some(values), Some((n, seed))) = (&density, args.input.random()) {
        check_density(values)?;
        sites = drawn_from(values, &frame, n, seed)?;
    }
    let mut options = LloydOptions::new(frame).iterations(args.iterations);
    if let Some(t) = args.tolerance {
        options = options.tolerance(t);
    }
    let small = frame.len() as u64 <= crate::device::CPU_FASTER_PIXELS;
    let chosen = crate::device::choose(args.device.as_deref(), crate::device::need(small))?;
    let backend = chosen.backend();
    let started = std::time::Instant::now();
    let progress = Progress::new("lloyd: iterations", args.json);
    let options = options.control(progress.control());
    let answer = lloyd(&backend, &sites, density.as_deref(), &options)?;
    drop(progress);
    let compute_ms = started.elapsed().as_secs_f64() * 1e3;
    let user: Vec<DVec2> = answer.sites.iter().map(|&p| world.to_user(p)).collect();
    if let Some(path) = &args.points {
        write_points(path, &user)?;
    }
    if let Some(path) = &args.labels {
        let size = [frame.width, frame.height, 1];
        raster::write(path, size, &answer.labels, Some(&world.georeference()))?;
    }
    if let Some(path) = &args.output {
        write_picture(path, &frame, &answer.sites)?;
    }
    crate::wrote([
        args.points.as_deref(),
        args.labels.as_deref(),
        args.output.as_deref(),
    ]);
    args.input.write_world_file(&world, (0, 0))?;
    report(
        &args,
        &world,
        &answer,
        options.tolerance,
        compute_ms,
        backend.name(),
    )
}

fn report(
    args: &Args,
    world: &World,
    answer: &Lloyd,
    tolerance: f64,
    compute_ms: f64,
    device: &str,
) -> Result<()> {
    let moves: Vec<f64> = answer.steps.iter().map(|s| s.largest_move).collect();
    if args.json {
        let summary = json!({
            "sites": answer.sites.len(),
            "iterations": answer.steps.len(),
            "converged": answer.converged,
            "tolerance": tolerance,
            "largest_move": moves,
            "energy": answer.steps.iter().map(|s| s.energy).collect::<Vec<_>>(),
            "final_energy": answer.energy,
            "idle": answer.idle,
            "stats": { "compute_ms": compute_ms },
        });
        envelope::print_world("lloyd", device, world, &summary)?;
    } else {
        let last = moves.last().copied().unwrap_or(0.0);
        outln!(
            "{} sites, {} iterations ({}): last largest move {}, energy {}; {} sites own no weight",
            answer.sites.len(),
            answer.steps.len(),
            if answer.converged {
                "converged"
            } else {
                "not converged"
            },
            Real(last),
            Real(answer.energy),
            answer.idle
        );
    }
    Ok(())
}

/// `n` points drawn from the density (as Secord starts stippling): a pixel
/// with probability proportional to its value, then a uniform place in it.
fn drawn_from(density: &[f64], frame: &Frame, n: usize, seed: u64) -> Result<Vec<DVec2>> {
    use rand::{Rng, SeedableRng};
    let mut total = 0.0;
    let cumulative: Vec<f64> = density
        .iter()
        .map(|&v| {
            total += v;
            total
        })
        .collect();
    if !(total > 0.0 && total.is_finite()) {
        bail!("the density is zero everywhere: no points can be drawn from it");
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let width = frame.width as usize;
    Ok((0..n)
        .map(|_| {
            let t = rng.gen_range(0.0..total);
            let k = cumulative
                .partition_point(|&c| c <= t)
                .min(cumulative.len() - 1);
            let pixel = DVec2::new((k % width) as f64, (k / width) as f64);
            let jitter = DVec2::new(rng.gen_range(-0.5..0.5), rng.gen_range(-0.5..0.5));
            frame.to_world(pixel + jitter)
        })
        .collect())
}

fn write_points(path: &Path, points: &[DVec2]) -> Result<()> {
    if extension_among(path, &["npy"]).is_some() {
        let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
        npy::write(path, &[points.len() as u64, 2], &flat)?;
    } else {
        write_text(path, "csv", "points", |out| {
            writeln!(out, "x,y")?;
            for p in points {
                writeln!(out, "{},{}", Real(p.x), Real(p.y))?;
            }
            Ok(())
        })?;
    }
    Ok(())
}

/// Black dots on white, one per site, sized to the picture.
fn write_picture(path: &Path, frame: &Frame, sites: &[DVec2]) -> Result<()> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let radius = (((w * h) as f64 / sites.len() as f64).sqrt() * 0.18).clamp(0.6, 8.0);
    if extension_among(path, &["svg"]).is_some() {
        return Ok(write_text(path, "svg", "stippling pictures", |out| {
            writeln!(
                out,
                r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w} {h}" width="{w}" height="{h}">"#
            )?;
            writeln!(out, r#"<rect width="{w}" height="{h}" fill="white"/>"#)?;
            for s in sites {
                // Pixel (i, j) spans [i, i + 1) in the picture's coordinates.
                let p = frame.to_pixel(*s) + 0.5;
                writeln!(
                    out,
                    r#"<circle cx="{:.3}" cy="{:.3}" r="{radius:.2}"/>"#,
                    p.x, p.y
                )?;
            }
            writeln!(out, "</svg>")
        })?);
    }
    let mut grey = vec![255u8; w * h];
    let r = radius.ceil() as i64;
    for s in sites {
        let p = frame.to_pixel(*s);
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (p.x.round() as i64 + dx, p.y.round() as i64 + dy);
                let inside = x >= 0 && y >= 0 && x < w as i64 && y < h as i64;
                if inside && (x as f64 - p.x).hypot(y as f64 - p.y) <= radius {
                    grey[y as usize * w + x as usize] = 0;
                }
            }
        }
    }
    let rgb: Vec<u8> = grey.iter().flat_map(|&g| [g, g, g]).collect();
    let mut png = PngStream::create(path, frame.width, frame.height)?;
    png.write(&rgb)?;
    png.finish()?;
    Ok(())
}
