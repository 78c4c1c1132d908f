//! `pixgeo gallery`: one picture per capability, with its caption and the command
//! that makes it, and an `index.html` to look at them.

use std::{fmt::Write as _, path::PathBuf};

use anyhow::{Context, Result};
use clap::{Args as ClapArgs, CommandFactory, Parser};
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::{device::needs_a_device, Cli, Command};

/// Renders the gallery: one picture per capability pixgeo has, each the output of
/// a `pixgeo` command shown beneath it, and an index.html that shows them all.
///
/// Example: pixgeo gallery gallery/ && xdg-open gallery/index.html
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Directory to write the pictures, their site files and index.html into.
    dir: PathBuf,

    /// Where each picture's command computes: auto, cpu, lavapipe, gpu, an
    /// index, or part of a device name (default: PIXGEO_DEVICE). Pictures
    /// that only a Vulkan device draws are skipped where there is none, and
    /// listed.
    #[arg(long = "device")]
    device: Option<String>,
}

struct Entry {
    /// The `pixgeo` subcommand.
    command: &'static str,
    picture: &'static str,
    title: &'static str,
    caption: &'static str,
    /// The file the command reads, written by the gallery: name and text.
    sites: Option<(&'static str, String)>,
    args: &'static [&'static str],
}

fn entries() -> Vec<Entry> {
    let mut rng = ChaCha8Rng::seed_from_u64(2003);
    let quarter: Vec<DVec2> = (0..900)
        .map(|_| DVec2::new(rng.gen_range(0.0..640.0), rng.gen_range(0.0..640.0)))
        .filter(|p| p.x < 320.0 || p.y < 320.0)
        .collect();
    let mut scattered: Vec<DVec2> = (0..5)
        .flat_map(|_| {
            let c = DVec2::new(rng.gen_range(-0.5..4.5), rng.gen_range(-0.5..3.5));
            let spread = rng.gen_range(0.05..0.4);
            (0..40)
                .map(|_| {
                    c + DVec2::new(
                        rng.gen_range(-spread..spread),
                        rng.gen_range(-spread..spread),
                    )
                })
                .collect::<Vec<_>>()
        })
        .collect();
    scattered.extend([
        DVec2::new(-1.0, 1.5),
        DVec2::new(5.0, -0.5),
        DVec2::new(2.0, 4.2),
    ]);
    // Its own generator, so that the other entries' sites stay as they were.
    let mut town_rng = ChaCha8Rng::seed_from_u64(4);
    let towns: Vec<DVec2> = (0..60)
        .map(|_| {
            DVec2::new(
                town_rng.gen_range(0.0..100.0),
                town_rng.gen_range(0.0..100.0),
            )
        })
        .collect();
    // A crescent of points for the alpha hulls: bays that empty discs can enter.
    let mut shape_rng = ChaCha8Rng::seed_from_u64(6);
    let shape: Vec<DVec2> = (0..80)
        .map(|_| {
            let a: f64 = shape_rng.gen_range(0.3..5.6);
            let r = shape_rng.gen_range(28.0..45.0);
            DVec2::new(50.0 + r * a.cos(), 50.0 + r * a.sin())
        })
        .collect();
    vec![
        Entry {
            command: "voronoi",
            picture: "voronoi.png",
            title: "The Voronoi diagram",
            caption: "1000 random sites, one cone per site, the lowest cone wins each pixel \
                      (thesis §3.2, Fig. 3.1). Exact cones: every pixel gets a nearest site.",
            sites: None,
            args: &["--random", "1000", "--seed", "1", "--size", "640"],
        },
        Entry {
            command: "voronoi",
            picture: "envelope.png",
            title: "The lower envelope of the cones",
            caption: "Distance contours every 6 pixels: seen from above, each region is its \
                      cone's rings, cut where a lower cone takes over (thesis Fig. 3.3).",
            sites: None,
            args: &[
                "--random",
                "80",
                "--seed",
                "4",
                "--size",
                "640",
                "--contours",
                "6",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "fan.png",
            title: "Cones as triangle fans",
            caption: "The same sites with every cone a fan of 6 triangles: the distances are \
                      off by at most 16 %, and the bisectors bend into arcs (thesis §3.3-3.4, \
                      Figs. 3.6-3.8). --mode fan chooses T per cone for an error of ε pixels.",
            sites: None,
            args: &[
                "--random",
                "80",
                "--seed",
                "4",
                "--size",
                "640",
                "--contours",
                "6",
                "--mode",
                "fan:6",
                "--no-speedup",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "quarter.png",
            title: "The quadtree's worst case",
            caption: "One quarter of the picture holds no site (thesis §3.5). The cones next to \
                      it must reach far; per-site radii keep all the others short.",
            sites: Some(("quarter.csv", csv(&quarter))),
            args: &[
                "--sites",
                "quarter.csv",
                "--size",
                "640",
                "--contours",
                "12",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "world.png",
            title: "World coordinates, clusters and sites outside",
            caption: "Clustered sites in world coordinates mapped with --bbox, three of them \
                      outside the picture: their cones still reach in.",
            sites: Some(("world.csv", csv(&scattered))),
            args: &[
                "--sites",
                "world.csv",
                "--bbox",
                "0,0,4,3",
                "--size",
                "640",
                "--contours",
                "0.05",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "tiled.png",
            title: "Tiles",
            caption: "A 1800x450 picture drawn in tiles of 256 pixels, each tile with only the \
                      cones that reach it, streamed to the PNG band by band. Tiling never \
                      changes a pixel.",
            sites: None,
            args: &[
                "--random",
                "2500",
                "--seed",
                "9",
                "--size",
                "1800x450",
                "--max-tile",
                "256",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "l05.png",
            title: "The L0.5 distance",
            caption: "The same 30 sites under L<sub>0.5</sub>: its balls are concave stars, so \
                      regions grow arms and may fall apart (thesis Fig. 3.26). Exact mode \
                      evaluates the metric per pixel; contours every 25 units.",
            sites: None,
            args: &[
                "--random",
                "30",
                "--seed",
                "2",
                "--size",
                "400",
                "--metric",
                "lp:0.5",
                "--contours",
                "25",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "l1.png",
            title: "The L1 distance",
            caption: "Manhattan distance: diamond-shaped cones, bisectors of horizontal, \
                      vertical and diagonal pieces (thesis Fig. 3.27).",
            sites: None,
            args: &[
                "--random",
                "30",
                "--seed",
                "2",
                "--size",
                "400",
                "--metric",
                "l1",
                "--contours",
                "25",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "l6.png",
            title: "The L6 distance",
            caption: "Nearly square balls: the diagram approaches that of L<sub>∞</sub> \
                      (thesis Fig. 3.29).",
            sites: None,
            args: &[
                "--random",
                "30",
                "--seed",
                "2",
                "--size",
                "400",
                "--metric",
                "lp:6",
                "--contours",
                "25",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "ties.png",
            title: "Areas of equidistant points",
            caption: "Under L<sub>1</sub> two sites on a diagonal have whole quadrants of \
                      points equally far from both, hatched here: a second pass with the \
                      depth test EQUAL counts the sites at each pixel's lowest depth \
                      (thesis §3.6.4, Fig. 3.32). --ties writes the counts.",
            sites: Some((
                "diagonal.csv",
                csv(&[DVec2::new(100.0, 100.0), DVec2::new(200.0, 200.0)]),
            )),
            args: &[
                "--sites",
                "diagonal.csv",
                "--size",
                "300",
                "--metric",
                "l1",
                "--ties",
                "ties.npy",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "second.png",
            title: "The second-nearest diagram",
            caption: "Every pixel coloured by its second-nearest site: the degree-2 diagram \
                      of thesis Fig. 3.34, whose regions fall apart into pieces. --degree K \
                      computes levels 1 to K at once.",
            sites: None,
            args: &[
                "--random", "40", "--seed", "4", "--size", "512", "--degree", "2",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "order3.png",
            title: "The order-3 diagram",
            caption: "One colour per set of three nearest sites (thesis §3.7): unlike the \
                      degree-3 diagram, every region is connected.",
            sites: None,
            args: &[
                "--random", "40", "--seed", "4", "--size", "512", "--order", "3",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "furthest.png",
            title: "The furthest-site diagram",
            caption: "Every pixel coloured by its furthest site, with distance contours: the \
                      cones turned upside down in one pass, drawn only for the convex hull's \
                      sites (thesis §3.7.1).",
            sites: None,
            args: &[
                "--random",
                "40",
                "--seed",
                "4",
                "--size",
                "512",
                "--furthest",
                "--contours",
                "40",
            ],
        },
        Entry {
            command: "voronoi",
            picture: "weighted.png",
            title: "Multiplicatively weighted points",
            caption: "Each site's distance divided by its weight m: heavier sites have                       flatter cones and win regions bounded by circles around the                       lighter ones, which may lie inside them (thesis §3.8, Fig. 3.38).",
            sites: Some(("weighted.json", weighted_sites(&mut rng))),
            args: &["--sites", "weighted.json", "--size", "640", "--contours", "40"],
        },
        Entry {
            command: "voronoi",
            picture: "mixed.png",
            title: "Points, segments, circles and arcs",
            caption: "Segments as roofs with half-cones at their ends, circles as straw                       huts, arcs as sliced huts with their end cones, all in one diagram                       (thesis §3.9, Fig. 3.45); contours every 12 pixels.",
            sites: Some(("mixed.json", mixed_sites(&mut rng))),
            args: &["--sites", "mixed.json", "--size", "640", "--contours", "12"],
        },
        Entry {
            command: "voronoi",
            picture: "polygon.png",
            title: "A polygonal distance",
            caption: "The unit ball is a four-pointed star around its kernel point: the                       polygon is the cone's base, so the fan over it is exact                       (thesis §3.6.5).",
            sites: Some((
                "star.json",
                "{\"vertices\": [[3, 0], [0.5, 0.5], [0, 2], [-0.5, 0.5], [-3, 0], \
                 [-0.5, -0.5], [0, -2], [0.5, -0.5]], \"kernel\": [0, 0]}\n"
                    .into(),
            )),
            args: &[
                "--random",
                "60",
                "--seed",
                "4",
                "--size",
                "640",
                "--metric",
                "polygon:star.json",
            ],
        },
        Entry {
            command: "enclose",
            picture: "enclose.png",
            title: "Smallest enclosing homothet",
            caption: "The lowest pixel of the upper envelope of cones on the reflected                       kite is the centre (yellow) of the smallest kite holding every                       site (red), refined exactly; regions coloured by their furthest                       site (thesis ch. 4, Fig. 4.1).",
            sites: Some(("towns.csv", csv(&towns))),
            args: &["--sites", "towns.csv", "--polygon", "kite.csv", "--size", "640"],
        },
        Entry {
            command: "empty",
            picture: "empty.png",
            title: "Largest empty circle inside a region with a hole",
            caption: "The highest pixel of the lower envelope inside the region (the                       hole darkened), with the region's edges as segment sites so that                       the whole circle stays inside (thesis ch. 5, §5.4.1).",
            sites: Some(("towns.csv", csv(&towns))),
            args: &[
                "--sites",
                "towns.csv",
                "--region",
                "county.json",
                "--inside",
                "--size",
                "640",
            ],
        },
        Entry {
            command: "alpha",
            picture: "alpha.png",
            title: "Alpha hull for a negative alpha",
            caption: "A rectangle at the depth of r = 1/|α| on the lower envelope marks                       the centres of empty discs (yellow); discs of radius r around                       their rim erase more (blue); what is left is the hull (red)                       (thesis §6.3, Figs. 6.1 and 6.3).",
            sites: Some(("shape.csv", csv(&shape))),
            args: &["--sites", "shape.csv", "--alpha", "-0.06", "--size", "640"],
        },
        Entry {
            command: "alpha",
            picture: "alpha_positive.png",
            title: "Alpha hull for a positive alpha",
            caption: "The intersection of every disc of radius 1/α that holds all                       sites: the circles through consecutive hull points that hold                       the others, counted with blending (thesis §6.4.1, Fig. 6.5).",
            sites: Some(("shape.csv", csv(&shape))),
            args: &["--sites", "shape.csv", "--alpha", "0.018", "--size", "640"],
        },
        Entry {
            command: "delaunay",
            picture: "delaunay.png",
            title: "Delaunay triangulation from a digital Voronoi diagram",
            caption: "Flooding colours the texture so that every region is connected,                       and its dual is a valid triangulation of the seeds (Cao,                       Edelsbrunner and Tan 2015, Fig. 3); the seeds then move to                       their true positions, the points that shared a pixel are                       inserted, and flips make it Delaunay.",
            sites: None,
            args: &["--random", "200", "--grid", "60", "--size", "640"],
        },
        Entry {
            command: "transform",
            picture: "transform.png",
            title: "Distance transform and the Voronoi diagram of obstacles",
            caption: "Every pixel of a raster takes its exact distance to the nearest \
                      obstacle pixel (darker farther, a band every tenth of the \
                      largest) and the colour of the obstacle it is nearest to: \
                      a pass down the columns, then the lower envelope of the \
                      columns' parabolas along each row (Meijster et al. 2000).",
            sites: None,
            args: &["--mask", "obstacles.png"],
        },
        Entry {
            command: "voronoi",
            picture: "north_up.png",
            title: "A north-up map",
            caption: "Europe's capitals by longitude and latitude: with --bbox the \
                      rasters and pictures are north-up, row 0 at the box's largest y, \
                      as GIS tools show them; --labels capitals.tif --crs EPSG:4326 \
                      would write the same labels as a GeoTIFF that they place (the \
                      distances here are in degrees, as on a plate carrée map).",
            sites: None,
            args: &["--sites", "capitals.csv", "--bbox", "-12,34,32,62", "--size", "640"],
        },
        Entry {
            command: "voronoi",
            picture: "cells.svg",
            title: "Vector cells",
            caption: "The exact Euclidean cells as polygons, clipped to the frame: each \
                      site's Delaunay neighbours give the bisectors that bound its cell. \
                      The same polygons go to cells.geojson for GIS tools and shapely; \
                      other metrics' cells are traced from the label raster.",
            sites: None,
            args: &["--random", "60", "--seed", "5", "--size", "640x480", "--cells", "cells.geojson"],
        },
        Entry {
            command: "transform",
            picture: "medial_axis.png",
            title: "Medial axis of the free space",
            caption: "The white pixels are the medial axis of the space between the \
                      obstacles, read off the exact feature transform: two neighbouring \
                      pixels whose nearest obstacle pixels lie far apart and seen under a \
                      wide angle straddle their bisector, and the nearer one is on the \
                      axis (Hesselink and Roerdink 2008). It is the roadmap that keeps \
                      farthest from every obstacle.",
            sites: None,
            args: &["--mask", "obstacles.png", "--medial-axis", "medial_axis.npy"],
        },
        Entry {
            command: "voronoi",
            picture: "power.png",
            title: "Power diagram with hidden sites",
            caption: "Thirty sites with power weights: each pixel goes to the site of \
                      least |p - s|² - w, exactly, by a walk over their regular \
                      triangulation. Heavy sites push their edges out; open rings mark \
                      hidden sites, whose cells are empty.",
            sites: Some(("power.csv", power_sites(&mut rng))),
            args: &["--sites", "power.csv", "--weights", "power", "--size", "400"],
        },
        Entry {
            command: "interpolate",
            picture: "natural_neighbor.png",
            title: "Natural-neighbour interpolation",
            caption: "Heights at 80 scattered samples (black), interpolated at every pixel \
                      by Sibson's natural neighbours: each pixel's weights are the areas a \
                      site there would steal from its neighbours' Voronoi regions, from the \
                      exact Delaunay triangulation, and each value is the double nearest \
                      the exact interpolant. White lies outside the samples' hull.",
            sites: Some((
                "heights.csv",
                include_str!("../../examples/data/heights.csv").into(),
            )),
            args: &["--sites", "heights.csv", "--bbox", "0,0,100,100", "--size", "400"],
        },
        Entry {
            command: "lloyd",
            picture: "stipple.png",
            title: "Weighted Voronoi stippling",
            caption: "A shaded sphere drawn by 3000 points, first drawn at random from \
                      the picture's darkness, then moved by Lloyd's iterations to their \
                      Voronoi regions' centroids weighted by it (Secord 2002): evenly \
                      spaced, denser where it is dark. Each iteration is an exact \
                      diagram and a sum per region; the centroids are exact for the \
                      digital regions.",
            sites: None,
            args: &[
                "--random", "3000", "--seed", "4", "--size", "400", "--density", "sphere.png",
                "--iterations", "40",
            ],
        },
    ]
}

/// A sphere lit from the upper left on a pale ground, as an 8-bit grey PNG:
/// the stippling entry's density (dark is dense).
fn sphere_png() -> Result<Vec<u8>> {
    let side = 400u32;
    let light = glam::DVec3::new(-0.5, -0.6, 0.62).normalize();
    let grey: Vec<u8> = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) as f64, (k / side) as f64);
            let (u, v) = ((x - 200.0) / 160.0, (y - 200.0) / 160.0);
            let r2 = u * u + v * v;
            if r2 > 1.0 {
                return 255;
            }
            let lit = glam::DVec3::new(u, v, (1.0 - r2).sqrt())
                .dot(light)
                .max(0.0);
            (10.0 + 235.0 * lit) as u8
        })
        .collect();
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, side, side);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&grey)?;
    writer.finish()?;
    Ok(bytes)
}

/// The files the entries read besides their sites: the homothets' units and
/// region, the transform's mask, and Europe's capitals (longitude, latitude).
const EXTRA_FILES: [(&str, &[u8]); 4] = [
    ("kite.csv", b"x,y\n1,0\n0,1.2\n-0.6,0\n0,-0.5\n"),
    (
        "county.json",
        b"[[[0, 0], [100, 0], [100, 100], [0, 100]], [[30, 30], [70, 30], [70, 70], [30, 70]]]\n",
    ),
    (
        "obstacles.png",
        include_bytes!("../../examples/data/obstacles.png"),
    ),
    ("capitals.csv", b"x,y\n-9.14,38.72\n-3.70,40.42\n2.35,48.86\n-0.13,51.51\n-6.26,53.35\n4.35,50.85\n4.90,52.37\n6.13,49.61\n7.45,46.95\n13.40,52.52\n12.57,55.68\n10.75,59.91\n18.07,59.33\n24.94,60.17\n24.75,59.44\n24.11,56.95\n25.28,54.69\n21.01,52.23\n14.42,50.08\n16.37,48.21\n17.11,48.15\n19.04,47.50\n14.51,46.06\n15.98,45.81\n12.50,41.90\n14.51,35.90\n18.41,43.86\n20.46,44.79\n19.26,42.44\n19.82,41.33\n21.43,42.00\n23.32,42.70\n23.73,37.98\n26.10,44.43\n28.86,47.01\n30.52,50.45\n27.56,53.90\n"),
];

/// Point sites as a CSV site file.
fn csv(sites: &[DVec2]) -> String {
    sites.iter().fold("x,y\n".into(), |mut s, p| {
        let _ = writeln!(s, "{},{}", p.x, p.y);
        s
    })
}

/// Fig. 3.45's kind of input: points, segments, circles and arcs in one file,
/// some weighted.
fn mixed_sites(rng: &mut ChaCha8Rng) -> String {
    let mut items = Vec::new();
    for k in 0..24 {
        let (x, y) = (rng.gen_range(20.0..620.0), rng.gen_range(20.0..620.0));
        let item = match k % 4 {
            0 => format!("{{\"point\": [{x:.1}, {y:.1}]}}"),
            1 => {
                let a: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
                let l = rng.gen_range(30.0..90.0);
                format!(
                    "{{\"segment\": [[{x:.1}, {y:.1}], [{:.1}, {:.1}]]}}",
                    x + l * a.cos(),
                    y + l * a.sin()
                )
            }
            2 => format!(
                "{{\"circle\": {{\"center\": [{x:.1}, {y:.1}], \"radius\": {:.1}}}}}",
                rng.gen_range(10.0..40.0)
            ),
            _ => {
                let start: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
                format!(
                    "{{\"arc\": {{\"center\": [{x:.1}, {y:.1}], \"radius\": {:.1}, \"start\": {start:.2}, \"end\": {:.2}}}}}",
                    rng.gen_range(15.0..45.0),
                    start + rng.gen_range(1.0..4.0)
                )
            }
        };
        items.push(item);
    }
    format!("{{\"sites\": [\n  {}\n]}}\n", items.join(",\n  "))
}

/// Fig. 3.38's kind of input: points with multiplicative weights.
/// Points in [0, 400]² with power weights up to a site spacing squared.
fn power_sites(rng: &mut ChaCha8Rng) -> String {
    (0..30).fold("x,y,w\n".into(), |mut s, _| {
        let _ = writeln!(
            s,
            "{:.1},{:.1},{:.0}",
            rng.gen_range(10.0..390.0),
            rng.gen_range(10.0..390.0),
            rng.gen_range(0.0..6000.0)
        );
        s
    })
}

fn weighted_sites(rng: &mut ChaCha8Rng) -> String {
    let items: Vec<String> = (0..30)
        .map(|_| {
            format!(
                "{{\"point\": [{:.1}, {:.1}], \"m\": {:.2}}}",
                rng.gen_range(0.0..640.0),
                rng.gen_range(0.0..640.0),
                rng.gen_range(0.5..3.0)
            )
        })
        .collect();
    format!("{{\"sites\": [\n  {}\n]}}\n", items.join(",\n  "))
}

/// Renders the gallery, running each entry's command through `run`, the
/// command line's own dispatch.
pub fn run(args: Args, run: impl Fn(Command) -> Result<()>) -> Result<()> {
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("creating {}", args.dir.display()))?;
    let mut html = String::from(
        "<!doctype html>\n<meta charset=\"utf-8\">\n<title>pixgeo gallery</title>\n<style>\n\
         body { font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; }\n\
         main { display: grid; grid-template-columns: repeat(auto-fill, minmax(420px, 1fr)); gap: 2em; }\n\
         img { width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }\n\
         code { display: block; background: #f4f4f4; padding: .5em; overflow-x: auto; font-size: 85%; }\n\
         </style>\n<h1>pixgeo gallery</h1>\n<p>Planar geometry computed by rendering. Each \
         picture is the output of the command beneath it, run in this directory.</p>\n<main>\n",
    );
    for (name, text) in EXTRA_FILES {
        std::fs::write(args.dir.join(name), text).with_context(|| format!("writing {name}"))?;
    }
    std::fs::write(args.dir.join("sphere.png"), sphere_png()?).context("writing sphere.png")?;
    let (mut skipped, mut failed) = (Vec::new(), None);
    for entry in entries() {
        if let Some((name, text)) = &entry.sites {
            std::fs::write(args.dir.join(name), text).with_context(|| format!("writing {name}"))?;
        }
        let mut argv: Vec<String> = vec!["pixgeo".into(), entry.command.into()];
        argv.extend(entry.args.iter().map(|a| a.to_string()));
        argv.extend(["-o".into(), entry.picture.into()]);
        let shown = argv.join(" ");
        // Run with file names relative to the gallery directory.
        let mut real: Vec<String> = argv
            .iter()
            .map(|a| {
                if let Some(file) = a.strip_prefix("polygon:") {
                    format!("polygon:{}", args.dir.join(file).display())
                } else if [".csv", ".json", ".png", ".npy", ".svg", ".geojson"]
                    .iter()
                    .any(|e| a.ends_with(e))
                {
                    args.dir.join(a).display().to_string()
                } else {
                    a.clone()
                }
            })
            .collect();
        // Only the commands that draw on a device take one.
        let takes_device = Cli::command()
            .find_subcommand(entry.command)
            .is_some_and(|c| c.get_arguments().any(|a| a.get_long() == Some("device")));
        if let (Some(d), true) = (&args.device, takes_device) {
            real.extend(["--device".into(), d.clone()]);
        }
        let cli = Cli::try_parse_from(&real).with_context(|| format!("gallery command {shown}"))?;
        match run(cli.command) {
            Ok(()) => {
                let _ = write!(
                    html,
                    "<figure>\n<img src=\"{}\" alt=\"{}\">\n<figcaption><b>{}.</b> {}<code>{}</code></figcaption>\n</figure>\n",
                    entry.picture, entry.title, entry.title, entry.caption, shown
                );
            }
            Err(e) if needs_a_device(&e) => {
                let _ = write!(
                    html,
                    "<figure>\n<figcaption><b>{}.</b> Not drawn here: {}<code>{}</code></figcaption>\n</figure>\n",
                    entry.title, escaped(&e.to_string()), shown
                );
                skipped.push(entry.title);
            }
            Err(e) => {
                failed = Some(e.context(format!("gallery command {shown}")));
                break;
            }
        }
    }
    html.push_str("</main>\n");
    let index = args.dir.join("index.html");
    std::fs::write(&index, html).with_context(|| format!("writing {}", index.display()))?;
    note!("wrote {}", index.display());
    if !skipped.is_empty() {
        note!(
            "note: {} pictures need a Vulkan device and were not drawn: {}",
            skipped.len(),
            skipped.join(", ")
        );
    }
    failed.map_or(Ok(()), Err)
}

/// `text` with HTML's special characters escaped.
fn escaped(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
