//! `pixgeo triangle` and `pixgeo quadrangle`: the smallest or largest triangle
//! and quadrangle with vertices among the sites (thesis ch. 7).

use anyhow::Result;
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::algorithms::area::{self, AreaAnswer, AreaOptions, AreaSearch, Decided, Extreme};

use crate::{device::Backend, envelope, input::Points, progress::Progress, text::Real};

/// The smallest (or, with --max, largest) triangle with three sites as
/// vertices. A saddle roof over every pair of sites, its height the area of
/// the triangle with the pair (thesis §7.3.2), all drawn in one pass with the
/// depth test; each site's pixel keeps its smallest triangle. The roofs reach
/// only as far as an area bound (§7.3.3), and the largest triangle draws only
/// the convex hull's roofs. The sites the pixels propose are then searched
/// exactly, so the area printed is exact.
///
/// Example:
///
///   pixgeo triangle --sites towns.csv
///   pixgeo triangle --sites towns.csv --max --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct TriangleArgs {
    #[command(flatten)]
    common: Common,
}

/// The smallest (or, with --max, largest) quadrangle with four sites as
/// vertices: a diagonal with one vertex strictly on each side (§7.3.4). Every
/// pair's roof keeps, per side, its nearest (farthest) site, in one pass; the
/// pairs the pixels propose are then searched exactly.
///
/// Example:
///
///   pixgeo quadrangle --sites towns.csv --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct QuadrangleArgs {
    #[command(flatten)]
    common: Common,
}

#[derive(ClapArgs)]
struct Common {
    #[command(flatten)]
    points: Points,
    /// The largest area instead of the smallest.
    #[arg(long)]
    max: bool,
    /// The roofs' picture side in pixels along the longer axis; Vulkan devices
    /// only. Its default is the one not 1024: 8 √n, from 64 to 1024, since
    /// each of the n² roofs covers the picture. Sites that share a pixel are
    /// searched on the CPU; the answer is exact either way.
    #[arg(long, value_name = "PIXELS", value_parser = crate::input::parse_side)]
    size: Option<u32>,
    /// Print the answer as JSON.
    #[arg(long)]
    json: bool,
    /// Where to compute: `cpu` runs the rotational sweep, exact in O(n² log n)
    /// however closely the sites crowd; auto, lavapipe, gpu, an index or part of
    /// a name draw the thesis's roofs on that Vulkan device, which cost far more
    /// (docs/benchmarks.md). Default: PIXGEO_DEVICE, else cpu.
    #[arg(long)]
    device: Option<String>,
}

impl Common {
    fn extreme(&self) -> Extreme {
        if self.max {
            Extreme::Largest
        } else {
            Extreme::Smallest
        }
    }
}

pub fn triangle(args: TriangleArgs) -> Result<()> {
    solve(&args.common, area::extremal_triangle, "triangle")
}

pub fn quadrangle(args: QuadrangleArgs) -> Result<()> {
    solve(&args.common, area::extremal_quadrangle, "quadrangle")
}

fn solve(c: &Common, search: AreaSearch, what: &str) -> Result<()> {
    let points = c.points.read()?;
    let device = c
        .device
        .clone()
        .or_else(|| std::env::var("PIXGEO_DEVICE").ok())
        .unwrap_or_else(|| "cpu".into());
    let chosen = crate::device::choose(Some(&device), crate::device::need(false))?;
    let backend = chosen.backend();
    let (step, device) = match &backend {
        Backend::Device(machine) => ("roofs of site pairs", machine.device_name()),
        Backend::Cpu => ("sweep over site pairs", "cpu (rotational sweep)"),
    };
    let progress = Progress::new(&format!("{what}: {step}"), c.json);
    let options = AreaOptions::new(c.extreme())
        .side(c.size)
        .control(progress.control());
    let answer = search(&backend, &points, &options)?;
    drop(progress);
    if c.json {
        return envelope::print(what, device, answer.frame.as_ref(), &answer);
    }
    report(&answer, &points, what)
}

fn report(answer: &AreaAnswer, points: &[DVec2], what: &str) -> Result<()> {
    let which = match answer.extreme {
        Extreme::Smallest => "smallest",
        Extreme::Largest => "largest",
    };
    outln!("{which} {what}: area {}", Real(answer.area));
    for &i in &answer.sites {
        let p = points[i as usize];
        outln!("  site {i}: ({}, {})", Real(p.x), Real(p.y));
    }
    if answer.decided_by == Decided::Pixels {
        outln!(
            "  {} roofs on {}x{} pixels proposed area {:.6e}; {} searched exactly",
            answer.roofs,
            answer.width,
            answer.height,
            answer.pixel_area.unwrap_or(f64::NAN),
            answer.checked
        );
    } else if answer.decided_by == Decided::Sweep {
        outln!(
            "  the rotational sweep met {} lines through two or more sites",
            answer.checked
        );
    } else {
        outln!("  decided by {}", answer.decided_by);
    }
    Ok(())
}
