//! `pixgeo voronoi`: the Voronoi diagram of point sites, and of weighted sites,
//! segments, circles and arcs.
//!
//! One command holds every diagram's route, with the checks that refuse options
//! a route does not take: points here, `sites.rs` for shapes, `levels.rs` for
//! the k nearest, order-k and furthest, `seeds.rs` for flooding's seeds,
//! `great_circle.rs` for distances on the Earth under a geographic system.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::{
        higher_order::{self, KNearestOptions},
        voronoi::{voronoi_bands, Accuracy, Band, Method as LabelMethod, Speedup, VoronoiOptions},
    },
    geometry::{
        metric::Metric,
        site::{Shape, Site},
    },
    machine::PixelRect,
};
use serde_json::json;

use crate::{
    cells,
    device::Backend,
    envelope,
    input::{Input, World},
    progress::Progress,
    write::{
        output::{check_distinct, check_extension, check_extensions, extension_among},
        picture::{self, PngStream},
        raster::{self, RasterStream},
    },
};

mod great_circle;
mod levels;
mod power;
mod seeds;
mod sites;

use levels::*;
use seeds::*;
use sites::*;

/// Computes the Voronoi diagram of point sites: which site is nearest to every
/// pixel, and how far it is.
///
/// Each site gets a cone whose height is the distance to the site; drawn with a
/// depth test, the lowest cone wins each pixel. Pixel (i, j) is centred at world
/// point (i, j) unless --bbox maps another rectangle onto the picture; row 0 is
/// the top row of the PNG.
///
/// Examples:
///
///   pixgeo voronoi --random 2000 --seed 1 --size 1024 -o voronoi.png
///
///   pixgeo voronoi --sites shops.csv --bbox 0,0,10,7.5 --size 800 --labels l.npy --distance d.npy --json
///
///   pixgeo voronoi --random 500 --mode fan:12 --no-speedup -o fan.png
///
/// Higher-order diagrams (thesis §3.7): --degree K gives every pixel its K
/// nearest sites in order, --order K its set of K nearest, --furthest its
/// furthest site.
///
///   pixgeo voronoi --random 300 --degree 3 -o third.png --each-level --labels knn.npy
///
///   pixgeo voronoi --random 40 --order 2 -o order2.png
///
///   pixgeo voronoi --random 40 --furthest -o furthest.png
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    #[command(flatten)]
    input: Input,

    /// Distance function (thesis §3.6): `l2` (Euclidean), `l1`, `linf`, or
    /// `lp:P` for any P > 0 (P < 1 gives star-shaped, non-convex balls), or
    /// `polygon:FILE`: the unit ball is the polygon in FILE (vertices as a site
    /// file around the kernel point at the origin, or JSON `{"vertices": [...],
    /// "kernel": [x, y]}`), star-shaped around its kernel (§3.6.5). Every metric
    /// works in both modes (fans over the thesis's polygonal chains), for every
    /// kind of diagram, and with --device cpu; --ties and --peel take the L_p
    /// metrics. Circles and arcs under a polygon take fan mode or --device cpu
    /// (exact); under L_p with p < 1 their fans' bound grows with the reach.
    /// `great-circle`: distances on the Earth in metres, x and y longitude and
    /// latitude in degrees; the default under a geographic --crs (or a GeoJSON
    /// file's), where the others measure degrees on the plane, with a warning.
    /// Great circles run on the CPU without a GPU, else on the device as a
    /// filter, to the same answer. Default: l2.
    #[arg(long = "metric", value_name = "METRIC", value_parser = parse_metric_choice)]
    metric_choice: Option<MetricChoice>,

    /// The metric of the plane, from --metric once the world is known.
    #[arg(skip = Metric::L2)]
    metric: Metric,

    /// Accuracy: `exact` writes the exact distance per pixel (labels are nearest
    /// sites); `fan` draws triangle fans sized for a distance error of --epsilon
    /// pixels; `fan:T` draws every cone with T triangles (thesis §3.3).
    #[arg(long, default_value = "exact", value_parser = crate::input::named::<Accuracy>)]
    mode: Accuracy,

    /// Distance error bound in pixels for `--mode fan` (default 1).
    #[arg(long)]
    epsilon: Option<f64>,

    /// How far cones reach: `local` (a radius per site from its neighbourhood),
    /// `quadtree` (thesis §3.5: one radius from the quadtree, retried while minmax
    /// finds uncovered pixels), or `none` (picture-wide cones). Default: local.
    #[arg(long, value_parser = crate::input::named::<Speedup>)]
    speedup: Option<Speedup>,

    /// Same as `--speedup none`.
    #[arg(long, conflicts_with = "speedup")]
    no_speedup: bool,

    /// Write a picture: one colour per region, sites as dots. `.png` draws the
    /// pixels; `.svg` draws the cells as vector art (those of --cells).
    #[arg(short = 'o', long = "output", value_name = "PICTURE.png|PICTURE.svg")]
    output: Option<PathBuf>,

    /// Write the cells as GeoJSON: a FeatureCollection with a feature per
    /// region, its site (or sites) in `properties`, in the world's
    /// coordinates. The Euclidean diagram of points has exact cells, clipped
    /// to the frame, from the exact Delaunay triangulation (on a Vulkan
    /// device); every other diagram's cells are traced from its label raster,
    /// along pixel edges, within half a pixel (`accuracy` says which).
    #[arg(long, value_name = "FILE.geojson")]
    cells: Option<PathBuf>,

    /// Draw distance contours on the picture every STEP world units: the cones'
    /// lower envelope seen from above.
    #[arg(long, value_name = "STEP")]
    contours: Option<f64>,

    /// Write the label map as .npy (uint32, H×W; 4294967295 = no site) or as
    /// a GeoTIFF (.tif), placed by --bbox and --crs. --degree and --order
    /// write H×W×K, a band per level.
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    labels: Option<PathBuf>,

    /// Write the distance map as .npy or .tif (float32, H×W, world units).
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    distance: Option<PathBuf>,

    /// Count the sites at the smallest distance of every pixel (thesis §3.6.4:
    /// under L1 and L∞ whole areas are equidistant to two sites) and write the
    /// counts as .npy or .tif (uint32, H×W); the picture shades pixels with
    /// more than one nearest site. Exact mode.
    #[arg(long, value_name = "FILE.npy|FILE.tif")]
    ties: Option<PathBuf>,

    /// Print a JSON summary (timings, cone footprints and radii, tiles, passes,
    /// device).
    #[arg(long)]
    json: bool,

    /// Largest tile side in pixels. Pictures larger than a tile (or than the
    /// device's largest image) are rendered tile by tile and written band by band,
    /// so the whole picture is never held in memory (weighted and extended sites
    /// are tiled too, their arrays assembled on the host).
    #[arg(long, value_name = "PIXELS")]
    max_tile: Option<u32>,

    /// Compute only this window of the picture: X0,Y0,W,H in pixels, counted
    /// as the outputs' rows and columns (row 0 first: the top of a north-up
    /// raster). Its pixels are the whole diagram's there, bit for bit, ties
    /// included, so windows computed apart (on other machines) tile into the
    /// whole; outputs are W x H. Ordinary diagrams of points on a Vulkan device.
    #[arg(long, value_name = "X0,Y0,W,H", value_parser = parse_window)]
    window: Option<PixelRect>,

    /// Where to compute: `cpu` runs the thesis's CPU pixel algorithms (§3.12,
    /// exact, no Vulkan needed); `auto`, `gpu`, `lavapipe`, an index or part of a
    /// name picks a Vulkan device (default: PIXGEO_DEVICE, else a GPU if present,
    /// else lavapipe; without any Vulkan driver, the CPU).
    #[arg(long)]
    device: Option<String>,

    /// The K nearest sites of every pixel: the degree 1..K diagrams at once, equal
    /// distances counted with their multiplicity. --labels and --distance become
    /// H×W×K arrays (level 1 first); the picture shows level K.
    #[arg(long, value_name = "K", conflicts_with_all = ["order", "furthest"])]
    degree: Option<u32>,

    /// The order-K diagram: every pixel's set of K nearest sites. --labels holds
    /// each set's ids in ascending order (H×W×K), --distance the K distances in
    /// increasing order (H×W×K); the picture has one colour per set.
    #[arg(long, value_name = "K", conflicts_with = "furthest")]
    order: Option<u32>,

    /// The furthest-site diagram: every pixel's furthest site (drawn from the
    /// convex hull's sites only).
    #[arg(long)]
    furthest: bool,

    /// With --degree: also write one picture per level, PICTURE-1.png to
    /// PICTURE-K.png beside -o.
    #[arg(long, requires = "degree")]
    each_level: bool,

    /// With --degree or --order: compute the levels the thesis's way (§3.7), by
    /// peeling the cones level by level against the previous level's depth and
    /// site (one cone pass a level; equally far sites peeled in the order of their
    /// ids), instead of pixgeo's one pass over screen tiles. Same distances, and
    /// every level names a different site.
    #[arg(long)]
    peel: bool,

    /// How the label map is made: `auto` (the default: `grid` for exact
    /// Euclidean diagrams without a GPU, `cones` otherwise), `cones` (the
    /// lower envelope drawn on the device), `grid` (a search of a grid of the
    /// sites on the CPU, proven like the cones: the same labels bit for bit),
    /// `flood` (the digital Voronoi diagram by flooding of Cao, Edelsbrunner
    /// and Tan: every region connected, the dual a triangulation) or `jfa`
    /// (jump flooding: fast, a few pixels wrong). `flood` and `jfa` work on the
    /// sites' pixels, which must be distinct and inside the picture.
    #[arg(long, value_enum, default_value = "auto")]
    method: Method,

    /// `power`: the sites carry power weights `w` (the CSV column `w`, the
    /// JSON key `"w"`, the GeoJSON property `w`, an .npy's third column) and
    /// the diagram is their power (Laguerre) diagram: each pixel to the site
    /// of least `|p − s|² − w`, exactly, by a walk over their regular
    /// triangulation on the CPU. --distance writes the powers (float64);
    /// --json lists the hidden sites, whose cells are empty.
    #[arg(long, value_enum)]
    weights: Option<crate::input::Weights>,
}

/// What --metric names: a metric of the plane, or great circles on the Earth.
#[derive(Clone, Debug)]
enum MetricChoice {
    Plane(Metric),
    GreatCircle,
}

fn parse_metric_choice(text: &str) -> Result<MetricChoice, String> {
    match text {
        "great-circle" | "great_circle" => Ok(MetricChoice::GreatCircle),
        _ => pixgeo_io::sites::parse_metric(text).map(MetricChoice::Plane),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Method {
    Auto,
    Cones,
    Grid,
    Flood,
    Jfa,
}

impl Method {
    /// Whether the diagram is the lower envelope of the sites' distances
    /// (drawn, or found by the grid), not flooded from their pixels.
    fn is_envelope(self) -> bool {
        !matches!(self, Method::Flood | Method::Jfa)
    }

    /// The library's way to an ordinary diagram's labels.
    fn labels(self) -> LabelMethod {
        match self {
            Method::Cones => LabelMethod::Cones,
            Method::Grid => LabelMethod::Grid,
            _ => LabelMethod::Auto,
        }
    }
}

fn parse_window(s: &str) -> Result<PixelRect, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}`: a window is X0,Y0,W,H in whole pixels"))?;
    match v[..] {
        [x, y, width, height] => Ok(PixelRect {
            x,
            y,
            width,
            height,
        }),
        _ => Err(format!("`{s}`: a window is four numbers, X0,Y0,W,H")),
    }
}

/// Refuses --window where this run computes the whole picture.
fn refuse_window(args: &Args, what: &str) -> Result<()> {
    if args.window.is_some() {
        return Err(crate::device::DrawnOnly(format!("--window takes the ordinary diagram of points on a Vulkan device; {what} is computed whole")).into());
    }
    Ok(())
}

pub fn run(mut args: Args) -> Result<()> {
    check_options(&args)?;
    if args.weights.is_some() {
        let (world, samples) = args.input.world_and_samples("w")?;
        power::diagram(&args, &world, samples)?;
        return finish(&args, &world);
    }
    let (world, general) = args.input.world_and_general_sites()?;
    let geographic = world.is_geographic();
    match (args.metric_choice.clone(), geographic) {
        (Some(MetricChoice::GreatCircle), _) | (None, true) => {
            great_circle::diagram(&args, &world, general)?
        }
        (choice, _) => {
            let metric = match choice {
                Some(MetricChoice::Plane(m)) => m,
                _ => Metric::L2,
            };
            if geographic {
                note!(
                    "warning: EPSG:{} is geographic: --metric {metric} measures degrees on the \
                     longitude-latitude plane, not distances on the Earth (without --metric, \
                     pixgeo measures great circles in metres)",
                    world.epsg.unwrap_or_default()
                );
            }
            args.metric = world.metric(metric);
            diagram(&args, &world, general)?
        }
    }
    finish(&args, &world)
}

/// Writes the world file beside the rasters and names what was written.
fn finish(args: &Args, world: &World) -> Result<()> {
    let corner = args.window.map_or((0, 0), |w| (w.x, w.y));
    args.input.write_world_file(world, corner)?;
    // Options a diagram would not write are refused up front: each given was written.
    crate::wrote(
        [
            &args.output,
            &args.labels,
            &args.distance,
            &args.ties,
            &args.cells,
        ]
        .map(|p| p.as_deref()),
    );
    Ok(())
}

fn diagram(args: &Args, world: &World, general: Vec<Site>) -> Result<()> {
    let frame = world.frame;
    let arrays: Vec<&std::path::Path> = [&args.labels, &args.distance, &args.ties]
        .into_iter()
        .filter_map(|p| p.as_deref())
        .collect();
    crate::input::check_room(&arrays, frame.width, frame.height)?;
    if general.iter().any(|s| !s.is_plain_point()) {
        return general_sites(args, &general, world);
    }
    let sites: Vec<DVec2> = general
        .iter()
        .map(|s| match s.shape {
            Shape::Point(p) => p,
            _ => unreachable!("plain points"),
        })
        .collect();
    let (accuracy, speedup) = (args.accuracy(), args.speedup());
    if !args.method.is_envelope() {
        return seed_pixels(args, &sites, world);
    }
    let kind = match (args.degree, args.order, args.furthest) {
        (Some(k), _, _) => Kind::Degree(k),
        (_, Some(k), _) => Kind::Order(k),
        (_, _, true) => Kind::Furthest,
        _ => Kind::Ordinary,
    };
    if args.method == Method::Grid && kind != Kind::Ordinary {
        bail!("--method grid finds the labels of ordinary diagrams; drop --degree, --order and --furthest");
    }
    // Ordinary diagrams of points come out bit for bit the same from every
    // route; their exact vector cells come from the device's path. Without
    // a GPU, exact Euclidean labels take the grid at any size, and other
    // diagrams the CPU's pixel algorithms on small pictures.
    let vectors = args.vectors();
    let options = VoronoiOptions::exact(frame)
        .method(args.method.labels())
        .metric(args.metric)
        .accuracy(accuracy)
        .speedup(speedup)
        .distances(args.distance.is_some() || args.contours.is_some())
        .ties(args.ties.is_some())
        .max_tile(args.max_tile)
        .window(args.window);
    let grid_alone = kind == Kind::Ordinary && !vectors.any() && options.on_cpu_alone();
    let small = kind == Kind::Ordinary
        && args.window.is_none()
        && !vectors.any()
        && args.method == Method::Auto
        && frame.width as u64 * frame.height as u64 <= crate::device::CPU_FASTER_PIXELS;
    // The CPU's furthest sites beat lavapipe's envelope at every size
    // measured (`docs/benchmarks.md`).
    let chosen = args.backend(small || grid_alone || kind == Kind::Furthest)?;
    let backend = chosen.backend();
    if let Kind::Degree(k) | Kind::Order(k) = kind {
        // Sites at one place are one site to a pixel's nearest.
        let distinct: std::collections::HashSet<[u64; 2]> = sites
            .iter()
            .map(|p| [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits()])
            .collect();
        if k as usize > distinct.len() {
            let flag = if matches!(kind, Kind::Order(_)) {
                "order"
            } else {
                "degree"
            };
            bail!(
                "--{flag} {k} asks for {k} nearest sites, but there are only {} distinct sites",
                distinct.len()
            );
        }
    }
    let streamed = match &backend {
        Backend::Device(_) => kind == Kind::Ordinary,
        Backend::Cpu => grid_alone,
    };
    if !streamed {
        return whole_picture(args, &backend, &sites, world, accuracy, speedup, kind);
    }
    let window = options.window_rect()?;

    // Outputs are streamed band by band as the tiles come in.
    let geo = world.georeference_from(window.x, window.y);
    let (w, h) = (window.width, window.height);
    let mut labels = args
        .labels
        .as_deref()
        .map(|p| RasterStream::<u32>::create(p, w, h, 1, Some(&geo)))
        .transpose()?;
    let mut distances = args
        .distance
        .as_deref()
        .map(|p| RasterStream::<f32>::create(p, w, h, 1, Some(&geo)))
        .transpose()?;
    let mut ties = args
        .ties
        .as_deref()
        .map(|p| RasterStream::<u32>::create(p, w, h, 1, Some(&geo)))
        .transpose()?;
    let mut png = args
        .png()
        .map(|p| PngStream::create(p, window.width, window.height))
        .transpose()?;
    // Cells traced from the labels need them all.
    let traced = args.vectors().any() && args.metric != Metric::L2;
    let mut all_labels = Vec::new();
    let corner = DVec2::new(window.x as f64, window.y as f64);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p) - corner).collect();
    // Distances come in world units; contours are drawn in those units too.
    let contour_step = args.contours.map(|s| s as f32);
    // A tiled picture shows its progress, band by band.
    let progress = Progress::new("voronoi: rows of tiles", args.json);
    let options = options.control(progress.control());
    let mut sink = |band: Band| {
        if let Some(out) = labels.as_mut() {
            out.write(&band.labels)?;
        }
        if traced {
            all_labels.extend_from_slice(&band.labels);
        }
        if let Some(out) = distances.as_mut() {
            out.write(&band.distances)?;
        }
        if let Some(out) = ties.as_mut() {
            out.write(&band.ties)?;
        }
        if let Some(out) = png.as_mut() {
            let contours = contour_step.map(|step| picture::Contours {
                distances: &band.distances,
                step,
                line: (1.0 / frame.scale) as f32,
            });
            let rows = band.y0 - window.y;
            let mut rgb = picture::label_rows(&band.labels, window.width, rows, &pixels, contours);
            // Areas of equidistant points (Figs. 3.32, 3.33): darker, hatched.
            for (k, (px, count)) in rgb.chunks_exact_mut(3).zip(&band.ties).enumerate() {
                let (i, j) = (k % window.width as usize, k / window.width as usize);
                if *count > 1 {
                    let dim = if (i + j) % 4 < 2 { 0.35 } else { 0.6 };
                    px.iter_mut().for_each(|v| *v = (*v as f32 * dim) as u8);
                }
            }
            out.write(&rgb)?;
        }
        Ok(())
    };
    let stats = voronoi_bands(&backend, &sites, &options, &mut sink)?;
    drop(progress);
    labels.map(RasterStream::finish).transpose()?;
    distances.map(RasterStream::finish).transpose()?;
    ties.map(RasterStream::finish).transpose()?;
    png.map(PngStream::finish).transpose()?;
    let source = match traced {
        true => cells::Source::Traced {
            labels: &all_labels,
            describe: &cells::site,
        },
        false => cells::Source::Exact {
            backend: &backend,
            sites: &sites,
        },
    };
    cells::write(args.vectors(), world, source, &sites)?;

    let s = &stats;
    if args.json {
        let summary = json!({
            "metric": args.metric.to_string(),
            "mode": mode_name(args),
            "speedup": speedup,
            "stats": s,
        });
        envelope::print_world("voronoi", &s.device, world, &summary)?;
    } else if s.method == LabelMethod::Grid {
        note!(
            "{} sites, {}x{} pixels by a grid search on the CPU: {:.1} ms searching, {} label(s) \
             mended by the exact check",
            s.sites,
            frame.width,
            frame.height,
            s.render_ms,
            s.mended
        );
    } else {
        note!(
            "{} sites, {}x{} pixels on {}: {} cone(s), {} tile(s), {} pass(es), radius \
             {:.1}..{:.1}, {:.1} ms rendering",
            s.sites,
            frame.width,
            frame.height,
            s.device,
            s.cones,
            s.tiles,
            s.passes,
            s.radius_min,
            s.radius_max,
            s.render_ms
        );
    }
    Ok(())
}

/// Refuses options that contradict each other or that this run would ignore.
fn check_options(args: &Args) -> Result<()> {
    check_distinct(
        [
            ("-o", &args.output),
            ("--labels", &args.labels),
            ("--distance", &args.distance),
            ("--ties", &args.ties),
            ("--cells", &args.cells),
        ]
        .map(|(name, p)| (name, p.as_deref())),
    )?;
    args.input.check_world_file()?;
    if let Some(path) = &args.output {
        check_extensions(path, &["png", "svg"], "pictures")?;
    }
    if let Some(path) = &args.cells {
        check_extension(path, "geojson", "cells")?;
    }
    if args.vectors().any() && args.window.is_some() {
        bail!("--cells and -o *.svg draw the whole frame's cells; drop --window");
    }
    for (path, what) in [
        (&args.labels, "label maps"),
        (&args.distance, "distance maps"),
        (&args.ties, "tie counts"),
    ] {
        if let Some(path) = path {
            raster::check_name(path, what)?;
        }
    }
    if let Some(step) = args.contours {
        if !(step > 0.0 && step.is_finite()) {
            bail!("--contours needs a positive step, not {step}");
        }
        if args.png().is_none() {
            bail!("--contours draws on the picture: give -o PICTURE.png");
        }
    }
    if args.each_level && args.png().is_none() {
        bail!("--each-level writes pictures beside -o: give -o PICTURE.png");
    }
    if args.peel && args.degree.is_none() && args.order.is_none() {
        bail!("--peel computes the levels of --degree or --order");
    }
    if let Some(epsilon) = args.epsilon {
        if !(epsilon > 0.0 && epsilon.is_finite()) {
            bail!("--epsilon needs a positive distance in pixels, not {epsilon}");
        }
        if !matches!(
            args.mode,
            Accuracy::Fan {
                triangles: None,
                ..
            }
        ) {
            bail!("--epsilon sizes the fans of --mode fan (fan:T fixes their triangles instead)");
        }
    }
    Ok(())
}

impl Args {
    fn accuracy(&self) -> Accuracy {
        match self.mode {
            Accuracy::Fan { triangles, .. } => Accuracy::Fan {
                epsilon: self.epsilon.unwrap_or(1.0),
                triangles,
            },
            exact => exact,
        }
    }

    /// Where to compute; the CPU pixel algorithms refuse the cones' options.
    /// `small`: work the CPU algorithms do faster than a software rasterizer,
    /// with the same answer, unless the cones' options were given.
    fn backend(&self, small: bool) -> Result<pixgeo::Chosen> {
        let small = small && self.refuse_cone_options("").is_ok();
        let chosen = crate::device::choose(self.device.as_deref(), crate::device::need(small))?;
        if chosen.machine.is_none() {
            self.refuse_cone_options("the exact CPU pixel algorithm")?;
        }
        Ok(chosen)
    }

    fn speedup(&self) -> Speedup {
        if self.no_speedup {
            Speedup::None
        } else {
            self.speedup.unwrap_or(Speedup::Local)
        }
    }

    /// The PNG picture, if -o names one.
    fn png(&self) -> Option<&std::path::Path> {
        let path = self.output.as_deref()?;
        extension_among(path, &["svg"]).is_none().then_some(path)
    }

    /// The vector outputs: --cells and an SVG picture.
    fn vectors(&self) -> cells::Outputs<'_> {
        cells::Outputs {
            geojson: self.cells.as_deref(),
            svg: self
                .output
                .as_deref()
                .filter(|p| extension_among(p, &["svg"]).is_some()),
            json: self.json,
            sources: self.input.sources(),
        }
    }

    /// Refuses the options that shape cones on a path that draws none: the
    /// CPU pixel algorithms and flooding.
    fn refuse_cone_options(&self, path: &str) -> Result<()> {
        let given = [
            ("--mode fan", self.mode != Accuracy::Exact),
            ("--speedup", self.speedup.is_some() || self.no_speedup),
            ("--max-tile", self.max_tile.is_some()),
            ("--ties", self.ties.is_some()),
        ];
        match given.iter().find(|(_, set)| *set) {
            Some((name, _)) => Err(crate::device::DrawnOnly(format!(
                "{name} shapes the cones of a Vulkan device; {path} draws none"
            ))
            .into()),
            None => Ok(()),
        }
    }
}

/// The accuracy mode as the JSON summary names it.
fn mode_name(args: &Args) -> String {
    match args.mode {
        Accuracy::Exact => "exact".to_string(),
        Accuracy::Fan {
            triangles: None, ..
        } => format!("fan (epsilon {})", args.epsilon.unwrap_or(1.0)),
        Accuracy::Fan {
            triangles: Some(t), ..
        } => format!("fan:{t}"),
    }
}
