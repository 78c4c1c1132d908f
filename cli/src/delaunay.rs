//! `pixgeo delaunay`: the Delaunay triangulation of points from their digital
//! Voronoi diagram (Cao, Edelsbrunner and Tan 2015).

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::{
        delaunay::{self, Delaunay, DelaunayOptions, DigitalDiagram},
        power::regular_triangulation,
    },
    geometry::{power::Weighted, triangulation::check_delaunay},
    Need,
};

use crate::{
    device::DeviceArg,
    envelope,
    input::Points,
    progress::Progress,
    write::{
        output,
        picture::{site_color, PngStream},
        vector::{write_geojson, Feature},
    },
};

/// The Delaunay triangulation of points, from a digital Voronoi diagram.
///
/// The points' bounding box is laid over a texture (--grid pixels along its
/// longer side, about one pixel per point by default); one point per pixel
/// becomes a seed. Flooding colours the texture so that every region is
/// connected, and its dual is a valid triangulation of the seeds (Cao,
/// Edelsbrunner and Tan 2015). The seeds are then moved to their true
/// positions, the points that shared a pixel inserted, and edges flipped with
/// exact predicates until the triangulation is Delaunay for the real input.
/// Repeated points are reported and dropped.
///
/// Examples:
///
///   pixgeo delaunay --sites points.csv --triangle mesh   # mesh.node, mesh.ele
///   pixgeo delaunay --random 2000 -o fig3.png --check
///   pixgeo delaunay --sites points.csv --json > mesh.json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    #[command(flatten)]
    points: Points,
    /// Write the triangulation in Triangle's formats: PREFIX.node (every input
    /// point, numbered from 0) and PREFIX.ele (counter-clockwise triangles).
    #[arg(long, value_name = "PREFIX")]
    triangle: Option<PathBuf>,
    /// Write the triangles as GeoJSON: a FeatureCollection of Polygons, each
    /// with its three point indices (`vertices`, counter-clockwise) in
    /// `properties`.
    #[arg(long, value_name = "FILE.geojson")]
    geojson: Option<PathBuf>,
    /// The points' coordinate system (as `--crs` reads it), named in the
    /// GeoJSON's `crs` (none is written for EPSG:4326, GeoJSON's own).
    #[arg(long, value_name = "CRS", value_parser = crate::write::geotiff::parse_crs, requires = "geojson")]
    crs: Option<u16>,
    /// Print the mesh as JSON: points, triangles, duplicates, phase statistics.
    #[arg(long)]
    json: bool,
    /// Write a PNG: the digital Voronoi diagram with the triangulation over it
    /// (like the paper's Fig. 3).
    #[arg(short = 'o', long = "output", value_name = "PNG")]
    output: Option<PathBuf>,
    /// The PNG's longer side in pixels (default 1024; each texture pixel is
    /// drawn as a square block).
    #[arg(long, default_value_t = pixgeo::geometry::Frame::DEFAULT_SIDE, value_name = "PIXELS",
          value_parser = clap::value_parser!(u32).range(1..=16384))]
    size: u32,
    /// Texture pixels along the longer side of the bounding box (default: about
    /// √n, at least 64; the pixel side is rounded up to a 3-bit mantissa, so
    /// the texture can come out up to a fifth smaller). Any size gives the same triangulation; it changes
    /// how much is left to insertion and flips.
    #[arg(long, value_name = "PIXELS")]
    grid: Option<u32>,
    /// Check the digital triangulation (conditions I–III of a valid
    /// triangulation) and the result (orientation, half-edges, convex hull,
    /// area, empty circles); fail if the result is wrong.
    #[arg(long)]
    check: bool,
    /// `power`: the points carry power weights `w` (the CSV column `w`, the
    /// JSON key `"w"`, the GeoJSON property `w`, an .npy's third column):
    /// build their regular (weighted Delaunay) triangulation, the dual of
    /// their power diagram, exactly on the CPU. --json lists the hidden
    /// points, whose power cells are empty; --triangle writes the weights as
    /// the .node's attribute.
    #[arg(long, value_enum)]
    weights: Option<crate::input::Weights>,
    #[command(flatten)]
    device: DeviceArg,
}

pub fn run(args: Args) -> Result<()> {
    if args.weights.is_some() {
        return regular(&args);
    }
    if let Some(path) = &args.geojson {
        output::check_extension(path, "geojson", "triangles")?;
    }
    let points = args.points.read()?;
    // The flooding's own outputs (its grid, its picture, its conditions)
    // ask for the flooding; the triangles alone come faster by insertion
    // without a GPU.
    let flooding = args.grid.is_some() || args.output.is_some() || args.check;
    let need = match flooding {
        true => Need::DeviceIfAny,
        false => Need::CpuUnlessGpu,
    };
    let chosen = args.device.choose(need)?;
    let backend = chosen.backend();
    let progress = Progress::new("delaunay: flooding, duals, insertion, flips", args.json);
    let options = DelaunayOptions::default()
        .grid(args.grid)
        .check(args.check)
        .control(progress.control());
    let result = delaunay::delaunay(&backend, &points, &options)?;
    drop(progress);
    let problems = args
        .check
        .then(|| check_delaunay(&points, &result.triangles, &result.distinct()));
    if let Some(prefix) = &args.triangle {
        write_triangle_files(prefix, &points, None, &result.triangles)?;
    }
    if let Some(path) = &args.output {
        let (w, h, rgb) = picture(&result, &points, args.size);
        let mut png = PngStream::create(path, w, h)?;
        png.write(&rgb)?;
        png.finish()?;
    }
    if let Some(path) = &args.geojson {
        write_triangles_geojson(path, &points, &result.triangles, args.crs)?;
    }
    crate::wrote([args.output.as_deref(), args.geojson.as_deref()]);
    if args.json {
        let mesh = serde_json::json!({
            "points": points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
            "triangles": result.triangles,
            "duplicates": result.duplicates,
            "digital_validity": result.digital_validity,
            "check": problems,
            "stats": result.stats,
        });
        let texture = result.digital.as_ref().map(DigitalDiagram::frame);
        envelope::print("delaunay", backend.name(), texture.as_ref(), &mesh)?;
    } else {
        report(&result, points.len(), problems.as_deref());
    }
    if let Some(problems) = problems {
        if !problems.is_empty() {
            bail!("the triangulation failed its check: {problems:?}");
        }
    }
    Ok(())
}

fn report(result: &Delaunay, n: usize, problems: Option<&[String]>) {
    let s = &result.stats;
    let f = &s.flooding;
    outln!(
        "{n} points ({} repeated, dropped): {} Delaunay triangles",
        result.duplicates.len(),
        result.triangles.len()
    );
    if result.digital.is_none() {
        note!(
            "  inserted in Hilbert order on the CPU: {:.1} ms, {} flips",
            s.insert_ms,
            s.insertion_flips
        );
        return;
    }
    note!(
        "  grid {}x{} ({:?} per pixel): {} seeds, {} points shared a pixel",
        s.width,
        s.height,
        s.cell,
        s.seeds,
        s.points - s.seeds
    );
    note!(
        "  colouring {:.1} ms, repair {:.1} ms ({} debris pixels recoloured), dualization {:.1} ms ({} triangles)",
        f.colour_ms,
        f.debris_ms + f.repair_ms,
        f.recoloured,
        s.dualize_ms,
        s.digital_triangles
    );
    note!(
        "  shifting {:.1} ms ({} hull flips, {} seeds moved, {} taken out), insertion {:.1} ms ({} points, {} flips), flips {:.1} ms ({})",
        s.shift_ms,
        s.hull_flips,
        s.moved,
        s.taken_out,
        s.insert_ms,
        s.inserted,
        s.insertion_flips,
        s.flip_ms,
        s.delaunay_flips
    );
    if let Some(why) = &s.incremental {
        note!("  built by insertion alone: {why}");
    }
    if let Some(v) = &result.digital_validity {
        if v.is_valid() {
            outln!(
                "  digital triangulation valid: V {} E {} F {}, V - E + F = {}",
                v.vertices,
                v.edges,
                v.triangles,
                v.euler_characteristic
            );
        } else {
            outln!("  digital triangulation NOT valid: {:?}", v.problems);
        }
    }
    match problems {
        Some([]) => outln!("  check: counter-clockwise, half-edges paired, hull convex, areas add up, every edge locally Delaunay"),
        Some(p) => outln!("  check FAILED: {p:?}"),
        None => {}
    }
}

/// PREFIX.node and PREFIX.ele in Triangle's formats, numbered from 0.
/// The regular triangulation of weighted points.
fn regular(args: &Args) -> Result<()> {
    let refused = [
        (args.output.is_some(), "-o"),
        (args.grid.is_some(), "--grid"),
        (args.check, "--check"),
    ];
    if let Some((_, flag)) = refused.iter().find(|(given, _)| *given) {
        bail!("{flag} is not computed for regular triangulations: they give --triangle, --geojson and --json");
    }
    let samples = args.points.samples("w")?;
    let sites = Weighted::zip(&samples.points, &samples.values);
    let result = regular_triangulation(&sites)?;
    let points = &samples.points;
    if let Some(prefix) = &args.triangle {
        write_triangle_files(prefix, points, Some(&samples.values), &result.triangles)?;
    }
    if let Some(path) = &args.geojson {
        write_triangles_geojson(path, points, &result.triangles, args.crs)?;
    }
    crate::wrote([args.geojson.as_deref()]);
    if args.json {
        let mesh = serde_json::json!({
            "points": points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
            "weights": samples.values,
            "triangles": result.triangles,
            "duplicates": [],
            "hidden": result.hidden,
            "stats": {},
        });
        envelope::print("delaunay", "cpu", None, &mesh)?;
    } else {
        outln!(
            "{} points, {} triangles (regular); {} hidden points own no power cell",
            points.len(),
            result.triangles.len(),
            result.hidden.len()
        );
    }
    Ok(())
}

/// The triangles as GeoJSON Polygons, each with its `vertices`.
fn write_triangles_geojson(
    path: &std::path::Path,
    points: &[DVec2],
    triangles: &[[u32; 3]],
    crs: Option<u16>,
) -> Result<()> {
    let features = triangles.iter().map(|t| {
        let mut properties = serde_json::Map::new();
        properties.insert("vertices".into(), serde_json::json!(t));
        Feature {
            polygons: vec![vec![t.iter().map(|&v| points[v as usize]).collect()]],
            properties,
        }
    });
    write_geojson(path, features, crs)?;
    Ok(())
}

/// Triangle's `.node` (with the weights as the one attribute, if any) and
/// `.ele` files.
fn write_triangle_files(
    prefix: &std::path::Path,
    points: &[DVec2],
    weights: Option<&[f64]>,
    triangles: &[[u32; 3]],
) -> Result<()> {
    let path = |ext: &str| {
        let mut p = prefix.as_os_str().to_owned();
        p.push(ext);
        PathBuf::from(p)
    };
    let node = path(".node");
    output::write_text(&node, "node", "--triangle", |w| {
        writeln!(w, "{} 2 {} 0", points.len(), usize::from(weights.is_some()))?;
        for (i, p) in points.iter().enumerate() {
            match weights {
                Some(weights) => writeln!(w, "{i} {:?} {:?} {:?}", p.x, p.y, weights[i])?,
                None => writeln!(w, "{i} {:?} {:?}", p.x, p.y)?,
            }
        }
        Ok(())
    })?;
    let ele = path(".ele");
    output::write_text(&ele, "ele", "--triangle", |w| {
        writeln!(w, "{} 3 0", triangles.len())?;
        for (k, t) in triangles.iter().enumerate() {
            writeln!(w, "{k} {} {} {}", t[0], t[1], t[2])?;
        }
        Ok(())
    })?;
    crate::wrote([Some(node.as_path()), Some(ele.as_path())]);
    Ok(())
}

/// A texture without labels around `points`, `side` pixels along the
/// longer side, a twentieth of it spare all round.
fn blank_texture(points: &[DVec2], side: u32) -> DigitalDiagram {
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), &p| {
        (lo.min(p), hi.max(p))
    });
    let margin = (side / 20).max(1);
    let inner = side.saturating_sub(2 * margin).max(1);
    let cell = (hi - lo).max_element() / inner as f64;
    let extent = ((hi - lo) / cell).ceil();
    DigitalDiagram {
        width: extent.x as u32 + 2 * margin,
        height: extent.y as u32 + 2 * margin,
        origin: lo - DVec2::splat(margin as f64 * cell),
        cell,
        ..Default::default()
    }
}

/// A picture like Cao, Edelsbrunner and Tan's Fig. 3: the digital Voronoi
/// diagram (each pixel `zoom` pixels wide, `zoom` chosen so the longer side is
/// about `side`) with the Delaunay triangulation drawn over it in dark lines
/// and the points as dots. Returns width, height and RGB bytes.
fn picture(result: &Delaunay, points: &[DVec2], side: u32) -> (u32, u32, Vec<u8>) {
    let blank;
    let d = match &result.digital {
        Some(d) => d,
        None => {
            blank = blank_texture(points, side);
            &blank
        }
    };
    let zoom = (side / d.width.max(d.height)).max(1);
    let (w, h) = (d.width * zoom, d.height * zoom);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    for y in 0..h {
        for x in 0..w {
            let label = d.labels.get(((y / zoom) * d.width + x / zoom) as usize);
            // Without a digital diagram (on the CPU) the mesh is drawn on white.
            let colour = label.map_or([255; 3], |&l| site_color(l));
            let k = ((y * w + x) * 3) as usize;
            rgb[k..k + 3].copy_from_slice(&colour);
        }
    }
    // Pixel (i, j) of the texture covers [i, i + 1) x [j, j + 1) of the
    // picture's texture units, its centre at (i + 1/2, j + 1/2).
    let at = |p: DVec2| (d.to_pixels(p) + 0.5) * zoom as f64;
    let mut darken = |x: i64, y: i64, f: f32| {
        if x >= 0 && y >= 0 && x < w as i64 && y < h as i64 {
            let k = ((y as u32 * w + x as u32) * 3) as usize;
            for c in &mut rgb[k..k + 3] {
                *c = (*c as f32 * f) as u8;
            }
        }
    };
    let mut edges: Vec<(u32, u32)> = result
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |e| (t[e].min(t[(e + 1) % 3]), t[e].max(t[(e + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    for (a, b) in edges {
        let (p, q) = (at(points[a as usize]), at(points[b as usize]));
        let steps = (q - p).abs().max_element().ceil().max(1.0) as usize;
        for s in 0..=steps {
            let r = p + (q - p) * (s as f64 / steps as f64);
            darken(r.x.floor() as i64, r.y.floor() as i64, 0.25);
        }
    }
    // Every point as a dot about a quarter of a texture pixel across.
    let radius = (zoom as i64 / 4).max(1);
    for p in points {
        let r = at(*p);
        for dy in -radius..=radius {
            for dx in -radius..=radius {
                if dx * dx + dy * dy <= radius * radius {
                    darken(r.x.floor() as i64 + dx, r.y.floor() as i64 + dy, 0.0);
                }
            }
        }
    }
    (w, h, rgb)
}
