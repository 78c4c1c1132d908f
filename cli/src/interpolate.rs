//! `pixgeo interpolate`: scattered values onto a raster, by natural
//! neighbours (exact or rendered), linearly or from the nearest sample.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::interpolate::{interpolate, InterpolateOptions, Interpolation, Method},
    geometry::Frame,
};
use serde_json::json;

use crate::{
    device::DeviceArg,
    envelope,
    input::{named, Input},
    progress::Progress,
    text::Real,
    write::{
        output::{check_distinct, check_extension},
        picture::{ramp, PngStream},
        raster::{self, RasterStream},
    },
};

/// Interpolates the values of scattered samples at every pixel centre.
/// `exact` (the default) is Sibson's natural-neighbour interpolant: each
/// pixel's weights are the areas a new site there steals from its natural
/// neighbours' Voronoi regions, from the exact Delaunay triangulation, and
/// each value is the double nearest the exact interpolant. `discrete` is the
/// rendered discrete Sibson interpolant (Park et al. 2006), `linear` the
/// barycentric one in the exact Delaunay triangle (as SciPy's griddata) and
/// `nearest` the nearest sample's value. Outside the samples' convex hull
/// `exact`, `discrete` and `linear` give NaN (nodata in a GeoTIFF).
///
/// Samples: `.csv` (a header naming x, y and --value's column, or three
/// columns x,y,value), `.json` ([[x, y, value], ...]), `.geojson` (Points
/// whose property --value holds the value, or their third coordinate) or
/// `.npy` (n×3).
///
/// Examples:
///
///   pixgeo interpolate --sites examples/data/heights.csv --value z --size 256 --raster h.npy -o h.png
///
///   pixgeo interpolate --sites examples/data/heights.csv --value z --method linear --bbox 0,0,100,100 --size 512 --raster h.tif --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// The samples (--sites FILE) and the raster's picture.
    #[command(flatten)]
    input: Input,

    /// The column (CSV), key (JSON) or property (GeoJSON) holding the values.
    #[arg(long, default_value = "z", value_name = "NAME")]
    value: String,

    /// `exact`, `discrete`, `linear` or `nearest`.
    #[arg(long, default_value = "exact", value_parser = named::<Method>)]
    method: Method,

    /// Write the interpolated raster: `.npy` (float64, H×W, NaN where no
    /// value) or GeoTIFF (`.tif`, float64, nodata NaN).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    raster: Option<PathBuf>,

    /// Draw a PNG: the values in colour (low dark blue, high yellow), white
    /// where none, the samples as black dots.
    #[arg(short = 'o', long = "output", value_name = "PICTURE.png")]
    output: Option<PathBuf>,

    /// Print the answer as one JSON object.
    #[arg(long)]
    json: bool,

    #[command(flatten)]
    device: DeviceArg,
}

pub fn run(args: Args) -> Result<()> {
    if let Some(path) = &args.raster {
        raster::check_name(path, "interpolated rasters")?;
    }
    if let Some(path) = &args.output {
        check_extension(path, "png", "pictures")?;
    }
    check_distinct([
        ("--raster", args.raster.as_deref()),
        ("-o", args.output.as_deref()),
    ])?;
    args.input.check_world_file()?;
    let (world, samples) = args.input.world_and_samples(&args.value)?;
    world.warn_if_geographic("the natural neighbours' areas and the triangles are taken");
    let frame = world.frame;
    let chosen = args.device.choose(args.method.need())?;
    let backend = chosen.backend();
    let started = std::time::Instant::now();
    let progress = Progress::new("interpolate: rows", args.json);
    let options = InterpolateOptions::new(frame, args.method).control(progress.control());
    let answer = interpolate(&backend, &samples.points, &samples.values, &options)?;
    drop(progress);
    let compute_ms = started.elapsed().as_secs_f64() * 1e3;
    let (w, h) = (frame.width, frame.height);
    if let Some(path) = &args.raster {
        let mut stream =
            RasterStream::create(path, w, h, 1, Some(&world.georeference()))?.with_nodata("nan");
        stream.write(&answer.values)?;
        stream.finish()?;
    }
    if let Some(path) = &args.output {
        write_picture(path, &frame, &answer.values, &samples.points)?;
    }
    crate::wrote([args.raster.as_deref(), args.output.as_deref()]);
    args.input.write_world_file(&world, (0, 0))?;
    let summary = Summary::of(&answer);
    if summary.with_value == 0 {
        note!(
            "note: no pixel centre lies inside the samples' convex hull, so every value is NaN: \
             give a --bbox over the samples (they span {})",
            span(&samples.points, args.input.y_up())
        );
    }
    if args.json {
        let result = json!({
            "method": format!("{:?}", args.method).to_lowercase(),
            "samples": samples.points.len(),
            "pixels": answer.values.len(),
            "with_value": summary.with_value,
            "min": summary.min,
            "max": summary.max,
            "decided_exactly": answer.decided_exactly,
            "stats": { "compute_ms": compute_ms },
        });
        envelope::print_world("interpolate", backend.name(), &world, &result)?;
    } else {
        outln!(
            "{} samples onto {w}x{h} pixels ({:?}): {} with a value, from {} to {}",
            samples.points.len(),
            args.method,
            summary.with_value,
            summary.min.map_or("-".into(), |v| Real(v).to_string()),
            summary.max.map_or("-".into(), |v| Real(v).to_string()),
        );
    }
    Ok(())
}

/// The samples' bounding box as `XMIN,YMIN,XMAX,YMAX`, in the user's y.
fn span(points: &[DVec2], y_up: bool) -> String {
    let lo = points
        .iter()
        .copied()
        .reduce(DVec2::min)
        .unwrap_or_default();
    let hi = points
        .iter()
        .copied()
        .reduce(DVec2::max)
        .unwrap_or_default();
    let (y0, y1) = if y_up { (-hi.y, -lo.y) } else { (lo.y, hi.y) };
    format!("{:?},{:?},{:?},{:?}", lo.x, y0, hi.x, y1)
}

/// The pixels with a value and their range.
struct Summary {
    with_value: usize,
    min: Option<f64>,
    max: Option<f64>,
}

impl Summary {
    fn of(answer: &Interpolation) -> Self {
        let valued = answer.values.iter().copied().filter(|v| !v.is_nan());
        Self {
            with_value: valued.clone().count(),
            min: valued.clone().reduce(f64::min),
            max: valued.reduce(f64::max),
        }
    }
}

/// The values in colour, white where none, the samples as black dots.
fn write_picture(
    path: &std::path::Path,
    frame: &Frame,
    values: &[f64],
    samples: &[DVec2],
) -> Result<()> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let valued = values.iter().copied().filter(|v| !v.is_nan());
    let (lo, hi) = valued.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let mut rgb: Vec<u8> = values
        .iter()
        .flat_map(|&v| match v.is_nan() {
            true => [255; 3],
            false if hi > lo => ramp((v - lo) / (hi - lo)),
            false => ramp(0.5),
        })
        .collect();
    // Dots of about a 250th of the picture's side.
    let r = (w.max(h) as i64 / 250).max(1);
    for p in samples {
        let p = frame.to_pixel(*p).round();
        for (dx, dy) in (-r..=r).flat_map(|dx| (-r..=r).map(move |dy| (dx, dy))) {
            let (x, y) = (p.x as i64 + dx, p.y as i64 + dy);
            if dx * dx + dy * dy <= r * r && x >= 0 && y >= 0 && x < w as i64 && y < h as i64 {
                let k = 3 * (y as usize * w + x as usize);
                rgb[k..k + 3].fill(0);
            }
        }
    }
    let mut png = PngStream::create(path, frame.width, frame.height)?;
    png.write(&rgb)?;
    png.finish()?;
    Ok(())
}
