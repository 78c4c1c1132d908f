//! `pixgeo alpha`: the α-hull of a point set (thesis ch. 6).

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args as ClapArgs, ValueEnum};
use pixgeo::{
    algorithms::alpha_hull::{self, AlphaMethod},
    io::{npy, picture::PngStream},
};

use crate::{device::machine_on, envelope, input::Points};

#[derive(Clone, Copy, ValueEnum)]
enum Method {
    /// Circles through consecutive points of the convex hull (§6.4.1).
    Hull,
    /// Two intersections of discs by counting, nothing but pixels (§6.4.2).
    Pixels,
}

/// The α-hull of a point set (Edelsbrunner, Kirkpatrick and Seidel; thesis
/// ch. 6): for α > 0 what every disc of radius 1/α holding all sites holds; for
/// α < 0 what the empty discs of radius -1/α leave; for α = 0 the convex hull.
///
/// α < 0 takes the lower envelope of the sites' cones: a rectangle at depth
/// -1/α marks the centres of empty discs and discs around their rim erase the
/// rest. Pixels within -1/α of the picture border can be overestimated (discs
/// centred beyond the border are not drawn); the picture reaches that far
/// beyond the sites where it can, and the report counts what is left.
/// α > 0 needs 1/α at least the smallest enclosing circle's radius.
///
/// Example:
///
///   pixgeo alpha --sites towns.csv --alpha -0.05 -o hull.png --mask hull.npy
///   pixgeo alpha --sites towns.csv --alpha 0.01 --method pixels --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    #[command(flatten)]
    points: Points,
    /// α: negative for the union of empty discs of radius -1/α, positive for
    /// the intersection of discs of radius 1/α, 0 for the convex hull.
    #[arg(long, allow_negative_numbers = true)]
    alpha: f64,
    /// How to compute a hull for α > 0.
    #[arg(long, value_enum, default_value = "hull")]
    method: Method,
    /// Write a PNG like the thesis's Figs. 6.1–6.3: the hull dark red, empty
    /// discs' centres yellow, what their discs erased light blue, sites blue.
    #[arg(short = 'o', long = "output", value_name = "PNG")]
    output: Option<PathBuf>,
    /// Write the hull as a NumPy uint8 array [height, width]: 1 inside, 0 outside.
    #[arg(long, value_name = "NPY")]
    mask: Option<PathBuf>,
    /// Picture side in pixels along the longer axis (default 1024).
    #[arg(long, value_name = "PIXELS", default_value_t = pixgeo::geometry::Frame::DEFAULT_SIDE, value_parser = crate::input::parse_side)]
    size: u32,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Vulkan device: auto, lavapipe, gpu, an index, or part of a name (default:
    /// PIXGEO_DEVICE); this command has no CPU algorithm, so `cpu` is refused.
    #[arg(long)]
    device: Option<String>,
}

pub fn run(args: Args) -> Result<()> {
    let points = args.points.read()?;
    let machine = machine_on(args.device.as_deref())?;
    let method = match args.method {
        Method::Hull => AlphaMethod::Hull,
        Method::Pixels => AlphaMethod::Pixels,
    };
    let side = args.size;
    let hull = alpha_hull::alpha_hull(&machine, &points, args.alpha, method, side)?;
    if args.json {
        envelope::print("alpha", machine.device_name(), Some(&hull.frame), &hull)?;
    } else {
        let radius = hull
            .radius
            .map_or("the convex hull".to_string(), |r| format!("radius {r}"));
        outln!(
            "alpha {} ({radius}, method {}): {} of {}x{} pixels inside, {} discs drawn",
            hull.alpha,
            hull.method,
            hull.inside,
            hull.width,
            hull.height,
            hull.discs
        );
        if !hull.boundary_sites.is_empty() {
            outln!("  boundary sites {:?}", hull.boundary_sites);
        }
        if hull.alpha < 0.0 {
            outln!(
                "  {} inside pixels lie within {} of the picture border, where the hull may be overestimated",
                hull.uncertain, hull.border_band
            );
        }
    }
    let (w, h) = (hull.width, hull.height);
    if let Some(path) = &args.mask {
        npy::write(path, &[h as u64, w as u64], &hull.mask())?;
    }
    if let Some(path) = &args.output {
        let mut png = PngStream::create(path, w, h)?;
        png.write(&alpha_hull::picture(&hull, &points))?;
        png.finish()?;
    }
    crate::wrote([args.mask.as_deref(), args.output.as_deref()]);
    Ok(())
}
