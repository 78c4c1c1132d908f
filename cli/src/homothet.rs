//! `pixgeo enclose` and `pixgeo empty`: the smallest enclosing and the largest
//! empty homothet of a circle or a star-shaped polygon (thesis ch. 4 and 5).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::homothet::{
        self, EmptyOptions, EncloseOptions, Envelope, EnvelopeLabels, HomothetAnswer, PixelStage,
        Region, Unit,
    },
    Backend, Machine, Metric, Shape as SiteShape, Site,
};
use pixgeo_io::sites;
use serde_json::Value;

use crate::{
    device::VulkanDevice,
    envelope,
    input::Points,
    progress::Progress,
    text::{Real, Rounded},
    write::picture::{label_rows, PngStream},
};

/// The shape and the picture, shared by both commands.
#[derive(ClapArgs)]
pub struct Shape {
    #[command(flatten)]
    sites: Points,
    /// The homothets' shape: a polygon star-shaped around its kernel point (a
    /// point file of its vertices around the kernel at the origin, or JSON
    /// `{"vertices": [[x, y], ...], "kernel": [x, y]}`). Default: a circle.
    #[arg(long, value_name = "FILE", conflicts_with = "circle")]
    polygon: Option<PathBuf>,
    /// Circles (the default).
    #[arg(long)]
    circle: bool,
    /// Write a PNG of the envelope's regions with the homothet outlined in red
    /// and its centre in yellow (thesis Figs. 4.1, 5.1).
    #[arg(short = 'o', long = "output", value_name = "PNG")]
    output: Option<PathBuf>,
    /// Picture side in pixels along the longer axis (default 1024). A finer
    /// picture gives a closer candidate; the refined answer is exact either way.
    #[arg(long, value_name = "PIXELS", default_value_t = pixgeo::geometry::Frame::DEFAULT_SIDE, value_parser = crate::input::parse_side)]
    size: u32,
    /// Print the answer as JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    device: VulkanDevice,
}

impl Shape {
    /// Writes the picture if one was asked for.
    fn draw(
        &self,
        machine: &Machine,
        shapes: &[Site],
        answer: &HomothetAnswer,
        envelope: Envelope,
        region: &Region,
    ) -> Result<()> {
        let Some(path) = &self.output else {
            return Ok(());
        };
        let unit = self.unit()?;
        let view = homothet::envelope_labels(machine, shapes, unit, answer, envelope)?;
        let rgb = picture(&view, shapes, unit, answer, envelope, region);
        let mut png = PngStream::create(path, view.frame.width, view.frame.height)?;
        png.write(&rgb)?;
        png.finish()?;
        crate::wrote([Some(path.as_path())]);
        Ok(())
    }

    fn unit(&self) -> Result<Unit> {
        let Some(path) = &self.polygon else {
            return Ok(Unit::Circle);
        };
        let (vertices, kernel) = sites::read_polygon(path)?;
        match Metric::polygon(&vertices, kernel) {
            Ok(Metric::Polygon(g)) => Ok(Unit::Polygon(g)),
            Ok(_) => unreachable!("a polygon metric"),
            Err(e) => bail!("{}: {e}", path.display()),
        }
    }
}

/// The smallest homothet of a circle or polygon holding all sites (or at least
/// K points): the lowest pixel of the upper envelope of cones on the reflected
/// polygon (thesis §4.3), refined exactly (Welzl for circles; the vertices of the
/// candidate sites' distance pieces for polygons). Sites may also be segments,
/// circles and arcs (JSON, as for `pixgeo voronoi`), refined by a branch and
/// bound where no closed form decides.
///
/// Example:
///
///   pixgeo enclose --sites towns.csv --json
///   pixgeo enclose --sites towns.csv --polygon triangle.csv --at-least 10
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct EncloseArgs {
    #[command(flatten)]
    shape: Shape,
    /// Hold at least K sites (smallest k-enclosing homothet, thesis §4.4.1):
    /// 1 to 256, or all the sites (the default).
    #[arg(long, value_name = "K", value_parser = parse_k)]
    at_least: Option<usize>,
}

/// The largest homothet of a circle or polygon containing no site, its centre in
/// a region: the highest pixel of the lower envelope, the pixels outside the
/// region pushed to 0 through a stencil mask (thesis ch. 5), refined exactly.
/// Sites may be points, segments, circles and arcs with multiplicative weights
/// (JSON or weight columns, as for `pixgeo voronoi`): obstacles and weighted
/// facilities (§5.4.2–5.4.3).
///
/// Example:
///
///   pixgeo empty --sites towns.csv --region county.json --json
///   pixgeo empty --sites obstacles.json --region hall.json --inside
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct EmptyArgs {
    #[command(flatten)]
    shape: Shape,
    /// Where the centre may lie: JSON `[[[x, y], ...], ...]` (rings; holes are
    /// rings inside rings, even-odd), a GeoJSON Polygon or MultiPolygon (bare,
    /// or in a Feature or FeatureCollection), or a point file (one ring).
    /// Default: the sites' bounding box.
    #[arg(long, value_name = "FILE")]
    region: Option<PathBuf>,
    /// Keep the whole homothet inside the region: its boundary becomes segment
    /// sites (thesis §5.4.1).
    #[arg(long)]
    inside: bool,
    /// How the picture is made for circles among points: `auto` (the default)
    /// takes the exact distance transform of the sites snapped to their pixels
    /// where it applies, `cones` draws the lower envelope of cones as the
    /// thesis does, `transform` insists on the former. The refined answer is
    /// the same.
    #[arg(long, value_enum, default_value_t = StageChoice::Auto)]
    pixel_stage: StageChoice,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum StageChoice {
    Auto,
    Cones,
    Transform,
}

pub fn enclose(args: EncloseArgs) -> Result<()> {
    let shapes = args.shape.sites.read_general()?;
    let unit = args.shape.unit()?;
    let machine = args.shape.device.machine()?;
    let side = args.shape.size;
    let k = args.at_least.unwrap_or(0);
    let working = Progress::working("enclose", args.shape.json);
    let answer = homothet::enclose(
        &Backend::Device(&machine),
        &shapes,
        &EncloseOptions::new(unit).k(k).side(side),
    )?;
    drop(working);
    let json = args
        .shape
        .json
        .then_some(("enclose", machine.device_name()));
    report(&answer, json, "smallest enclosing")?;
    let envelope = Envelope::Enclosing { k };
    args.shape
        .draw(&machine, &shapes, &answer, envelope, &Region::default())
}

pub fn empty(args: EmptyArgs) -> Result<()> {
    let shapes = args.shape.sites.read_general()?;
    let unit = args.shape.unit()?;
    let region = match &args.region {
        None => Region::default(),
        Some(path) => read_region(path)?,
    };
    let machine = args.shape.device.machine()?;
    let side = args.shape.size;
    let stage = match args.pixel_stage {
        StageChoice::Auto => None,
        StageChoice::Cones => Some(PixelStage::Cones),
        StageChoice::Transform => Some(PixelStage::DistanceTransform),
    };
    let working = Progress::working("empty", args.shape.json);
    let answer = homothet::largest_empty(
        &machine,
        &shapes,
        &EmptyOptions::new(unit)
            .region(region.clone())
            .inside(args.inside)
            .side(side)
            .stage(stage),
    )?;
    drop(working);
    let json = args.shape.json.then_some(("empty", machine.device_name()));
    report(&answer, json, "largest empty")?;
    args.shape
        .draw(&machine, &shapes, &answer, Envelope::Empty, &region)
}

/// The rings of a GeoJSON Polygon or MultiPolygon, bare or in a Feature or
/// FeatureCollection (every polygon's rings, holes included: a point is in
/// the region inside an odd number of them), each without its closing point.
fn geojson_rings(value: &Value) -> Result<Value> {
    let kind = value["type"].as_str().unwrap_or("");
    let rings: Vec<Value> = match kind {
        "FeatureCollection" => {
            let features = value["features"]
                .as_array()
                .context("no \"features\" array")?;
            let mut all = Vec::new();
            for feature in features {
                if let Value::Array(r) = geojson_rings(feature)? {
                    all.extend(r);
                }
            }
            all
        }
        "Feature" => return geojson_rings(&value["geometry"]),
        "Polygon" => value["coordinates"].as_array().cloned().unwrap_or_default(),
        "MultiPolygon" => value["coordinates"]
            .as_array()
            .into_iter()
            .flatten()
            .flat_map(|p| p.as_array().cloned().unwrap_or_default())
            .collect(),
        other => bail!("a {other:?} is not a region: give a Polygon or MultiPolygon"),
    };
    let open = |ring: Value| match ring {
        Value::Array(mut points) => {
            if points.len() > 1 && points.first() == points.last() {
                points.pop();
            }
            Value::Array(points)
        }
        other => other,
    };
    Ok(Value::Array(rings.into_iter().map(open).collect()))
}

fn parse_k(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(k) if k >= 1 => Ok(k),
        _ => Err(format!("`{text}`: K counts the sites to hold, at least 1")),
    }
}

fn read_region(path: &Path) -> Result<Region> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let rings = match serde_json::from_str::<Value>(&text) {
        Ok(Value::Array(rings)) => Some(Value::Array(rings)),
        // GeoJSON polygons; GeoJSON points are a point file, one ring.
        Ok(v @ Value::Object(_)) if text.contains("Polygon\"") => Some(
            geojson_rings(&v).with_context(|| format!("{}: a GeoJSON region", path.display()))?,
        ),
        _ => None,
    };
    if let Some(Value::Array(rings)) = rings {
        let rings = rings
            .iter()
            .map(|ring| serde_json::from_value::<Vec<[f64; 2]>>(ring.clone()))
            .collect::<Result<Vec<_>, _>>()
            .with_context(|| format!("{}: rings are lists of [x, y]", path.display()))?;
        if rings.iter().all(|r| r.len() < 3) {
            bail!(
                "{}: the region needs a ring of at least three points (leave out --region for the sites' bounding box)",
                path.display()
            );
        }
        return Ok(Region {
            rings: rings
                .into_iter()
                .map(|r| r.into_iter().map(DVec2::from).collect())
                .collect(),
        });
    }
    Ok(Region {
        rings: vec![sites::read_sites(path)?],
    })
}

fn report(answer: &HomothetAnswer, json: Option<(&str, &str)>, what: &str) -> Result<()> {
    if let Some((command, device)) = json {
        return envelope::print(command, device, Some(&answer.frame), answer);
    }
    let e = &answer.exact;
    outln!(
        "{what} homothet: centre ({}, {}), scale {}",
        Real(e.centre[0]),
        Real(e.centre[1]),
        Real(e.scale)
    );
    outln!("  determined by sites {:?}", e.sites);
    if answer.tolerance > 0.0 {
        outln!(
            "  the optimum's scale is within {:.2e} of this one",
            answer.tolerance
        );
    }
    outln!(
        "  picture ({}x{}, {}): centre ({}, {}), scale {} (within {:.2e} of the exact one)",
        answer.width,
        answer.height,
        match answer.pixel_stage {
            PixelStage::Cones => "cones",
            PixelStage::DistanceTransform => "distance transform",
        },
        Rounded(answer.pixel.centre[0], 4),
        Rounded(answer.pixel.centre[1], 4),
        Rounded(answer.pixel.scale, 6),
        answer.pixel_bound
    );
    Ok(())
}

/// A picture (RGB rows) of the envelope behind `answer`, like the thesis's
/// Figs. 4.1 and 5.1: the regions coloured by their site, the point sites as
/// dots, the exact homothet's outline in red and its centre in yellow; for
/// `empty`, what lies outside the region darkened.
fn picture(
    view: &EnvelopeLabels,
    shapes: &[Site],
    unit: Unit,
    answer: &HomothetAnswer,
    envelope: Envelope,
    region: &Region,
) -> Vec<u8> {
    let frame = &view.frame;
    let (centre, scale) = (DVec2::from(answer.exact.centre), answer.exact.scale);
    let marks: Vec<DVec2> = shapes
        .iter()
        .filter_map(|s| match s.shape {
            SiteShape::Point(p) => Some(frame.to_pixel(p)),
            _ => None,
        })
        .collect();
    let mut rgb = label_rows(&view.labels, frame.width, 0, &marks, None);
    // A band about a pixel wide around the outline, in gauge units.
    let band = 0.8 / frame.scale * unit.lipschitz();
    let w = frame.width as usize;
    for (at, px) in rgb.chunks_exact_mut(3).enumerate() {
        let q = frame.to_world(DVec2::new((at % w) as f64, (at / w) as f64));
        if envelope == Envelope::Empty && !region.rings.is_empty() && !region.contains(q) {
            px.iter_mut().for_each(|v| *v = (*v as f32 * 0.35) as u8);
        }
        if (unit.gauge(q - centre) - scale).abs() <= band {
            px.copy_from_slice(&[220, 20, 30]);
        } else if q.distance(centre) * frame.scale <= 2.5 {
            px.copy_from_slice(&[255, 220, 0]);
        }
    }
    rgb
}
