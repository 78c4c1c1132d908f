//! `pixgeo enclose` and `pixgeo empty`: the smallest enclosing and the largest
//! empty homothet of a circle or a star-shaped polygon (thesis ch. 4 and 5).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::homothet::{self, HomothetAnswer, Region, Unit, DEFAULT_SIDE},
    geometry::metric::Metric,
    io::sites,
};
use serde_json::Value;

use crate::distances::Common;

/// The shape and the picture, shared by both commands.
#[derive(ClapArgs)]
pub struct Shape {
    /// The points: CSV `x,y` per line or JSON.
    #[arg(long, value_name = "FILE")]
    sites: PathBuf,
    /// The homothets' shape: a polygon star-shaped around its kernel point (a
    /// point file of its vertices around the kernel at the origin, or JSON
    /// `{"vertices": [[x, y], ...], "kernel": [x, y]}`). Default: a circle.
    #[arg(long, value_name = "FILE", conflicts_with = "circle")]
    polygon: Option<PathBuf>,
    /// Circles (the default).
    #[arg(long)]
    circle: bool,
    #[command(flatten)]
    common: Common,
}

impl Shape {
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
/// K of them): the lowest pixel of the upper envelope of cones on the reflected
/// polygon (thesis §4.3), refined exactly (Welzl for circles; the vertices of the
/// candidate sites' distance pieces for polygons).
///
/// Example:
///
///   pixgeo enclose --sites towns.csv --json
///   pixgeo enclose --sites towns.csv --polygon triangle.csv --k 10
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct EncloseArgs {
    #[command(flatten)]
    shape: Shape,
    /// Hold at least K sites (smallest k-enclosing homothet, thesis §4.4.1).
    #[arg(long, value_name = "K")]
    k: Option<usize>,
}

/// The largest homothet of a circle or polygon containing no site, its centre in
/// a region: the highest pixel of the lower envelope, the pixels outside the
/// region pushed to 0 through a stencil mask (thesis ch. 5), refined exactly.
///
/// Example:
///
///   pixgeo empty --sites towns.csv --region county.json --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct EmptyArgs {
    #[command(flatten)]
    shape: Shape,
    /// Where the centre may lie: JSON `[[[x, y], ...], ...]` (rings; holes are
    /// rings inside rings, even-odd) or a point file (one ring). Default: the
    /// sites' bounding box.
    #[arg(long, value_name = "FILE")]
    region: Option<PathBuf>,
}

pub fn enclose(args: EncloseArgs) -> Result<()> {
    let points = sites::read_sites(&args.shape.sites)?;
    let unit = args.shape.unit()?;
    let machine = args.shape.common.machine()?;
    let side = args.shape.common.size.unwrap_or(DEFAULT_SIDE);
    let answer = homothet::enclose(&machine, &points, unit, args.k.unwrap_or(0), side)?;
    report(&answer, args.shape.common.json, "smallest enclosing")
}

pub fn empty(args: EmptyArgs) -> Result<()> {
    let points = sites::read_sites(&args.shape.sites)?;
    let unit = args.shape.unit()?;
    let region = match &args.region {
        None => Region::default(),
        Some(path) => read_region(path)?,
    };
    let machine = args.shape.common.machine()?;
    let side = args.shape.common.size.unwrap_or(DEFAULT_SIDE);
    let answer = homothet::largest_empty(&machine, &points, unit, &region, side)?;
    report(&answer, args.shape.common.json, "largest empty")
}

fn read_region(path: &Path) -> Result<Region> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    if let Ok(Value::Array(rings)) = serde_json::from_str::<Value>(&text) {
        let rings = rings
            .iter()
            .map(|ring| serde_json::from_value::<Vec<[f64; 2]>>(ring.clone()))
            .collect::<Result<Vec<_>, _>>()
            .with_context(|| format!("{}: rings are lists of [x, y]", path.display()))?;
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

fn report(answer: &HomothetAnswer, json: bool, what: &str) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(answer)?);
        return Ok(());
    }
    let e = &answer.exact;
    println!(
        "{what} homothet: centre ({}, {}), scale {}",
        e.centre[0], e.centre[1], e.scale
    );
    println!("  determined by sites {:?}", e.sites);
    println!(
        "  picture ({}x{}): centre ({:.4}, {:.4}), scale {:.6} (within {:.2e} of the exact one)",
        answer.width,
        answer.height,
        answer.pixel.centre[0],
        answer.pixel.centre[1],
        answer.pixel.scale,
        answer.pixel_bound
    );
    Ok(())
}
