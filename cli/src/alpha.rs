//! `pixgeo alpha`: the α-hull of a point set (thesis ch. 6).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::algorithms::alpha_hull::{self, class, AlphaHull, AlphaMethod, AlphaOptions};

use crate::{
    device::VulkanDevice,
    envelope,
    input::Input,
    progress::Progress,
    write::{
        output::{check_distinct, check_extension},
        picture::PngStream,
        raster,
    },
};

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
/// Without --bbox the picture is fitted to where the hull can be.
///
/// Example:
///
///   pixgeo alpha --sites towns.csv --alpha -0.05 -o hull.png --hull hull.npy
///   pixgeo alpha --sites towns.csv --alpha -0.05 --bbox 0,0,100,100 --crs EPSG:32633 --hull hull.tif
///   pixgeo alpha --sites towns.csv --alpha 0.01 --method pixels --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// α: negative for the union of empty discs of radius -1/α, positive for
    /// the intersection of discs of radius 1/α, 0 for the convex hull.
    #[arg(long, allow_negative_numbers = true)]
    alpha: f64,
    /// How to compute a hull for α > 0: `hull`, circles through consecutive
    /// points of the convex hull (§6.4.1), or `pixels`, two intersections of
    /// discs by counting, nothing but pixels (§6.4.2).
    #[arg(long, default_value = "hull", value_parser = crate::input::named::<AlphaMethod>)]
    method: AlphaMethod,
    /// Write a PNG like the thesis's Figs. 6.1–6.3: the hull dark red, empty
    /// discs' centres yellow, what their discs erased light blue, sites blue.
    #[arg(short = 'o', long = "output", value_name = "PNG")]
    output: Option<PathBuf>,
    /// Write the hull as a uint8 raster [height, width], 1 inside and 0
    /// outside: `.npy`, or `.tif` placed by --bbox and --crs.
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    hull: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    device: VulkanDevice,
}

pub fn run(args: Args) -> Result<()> {
    if let Some(path) = &args.hull {
        raster::check_name(path, "--hull")?;
    }
    if let Some(path) = &args.output {
        check_extension(path, "png", "pictures")?;
    }
    check_distinct([
        ("--hull", args.hull.as_deref()),
        ("-o", args.output.as_deref()),
    ])?;
    args.input.check_world_file()?;
    // Refused before the sites are read: --size WxH needs --bbox.
    let fitted = (!args.input.has_bbox())
        .then(|| args.input.fitted_side())
        .transpose()?;
    let (world, points) = args.input.world_and_sites()?;
    world.warn_if_geographic("the discs' radius 1/α is in degrees,");
    let machine = args.device.machine()?;
    let (alpha, method) = (args.alpha, args.method);
    let working = Progress::working("alpha", args.json);
    let options = AlphaOptions::new(alpha).method(method);
    let options = match fitted {
        Some(side) => options.side(side),
        None => options.frame(world.frame),
    };
    let hull = alpha_hull::alpha_hull(&machine, &points, &options)?;
    drop(working);
    let world = args.input.world_of(hull.frame);
    if args.json {
        envelope::print_world("alpha", machine.device_name(), &world, &hull)?;
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
    if let Some(path) = &args.hull {
        raster::write(path, [w, h, 1], &hull.mask(), Some(&world.georeference()))?;
    }
    if let Some(path) = &args.output {
        let mut png = PngStream::create(path, w, h)?;
        png.write(&picture(&hull, &points))?;
        png.finish()?;
    }
    crate::wrote([args.hull.as_deref(), args.output.as_deref()]);
    args.input.write_world_file(&world, (0, 0))
}

/// A picture (RGB rows) like the thesis's Figs. 6.1–6.3: the hull dark red, the
/// empty discs' centres light yellow, what the discs erased light blue, the
/// sites as blue dots.
fn picture(hull: &AlphaHull, sites: &[DVec2]) -> Vec<u8> {
    let (w, h) = (hull.width as usize, hull.height as usize);
    let mut rgb: Vec<u8> = hull
        .pixels
        .iter()
        .flat_map(|&c| match c {
            class::INSIDE => [150, 20, 30],
            class::CENTRE => [255, 236, 150],
            class::DISC => [196, 216, 255],
            _ => [255, 255, 255],
        })
        .collect();
    for s in sites {
        let p = hull.frame.to_pixel(*s).round();
        for dj in -1..=1 {
            for di in -1..=1 {
                let (i, j) = (p.x as i64 + di, p.y as i64 + dj);
                if i >= 0 && j >= 0 && (i as usize) < w && (j as usize) < h {
                    let k = 3 * (j as usize * w + i as usize);
                    rgb[k..k + 3].copy_from_slice(&[20, 60, 220]);
                }
            }
        }
    }
    rgb
}
