//! `pixgeo hausdorff`, `pixgeo diameter`, `pixgeo maxdist`: distances between point
//! sets read off Voronoi pictures (thesis §3.11), refined to exact answers.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args as ClapArgs;
use glam::DVec2;
use pixgeo::{
    algorithms::distances::{self, Answer, Method},
    geometry::check_sites,
    machine::Machine,
    Need,
};
use pixgeo_io::sites;
use serde_json::{json, Value};

use crate::{device::DeviceArg, envelope, input::Points, progress::Progress, text::Real};

/// Options every distance command shares.
#[derive(ClapArgs)]
pub struct Common {
    /// Picture side in pixels along the longer axis (default 1024). A coarser
    /// picture only means more points are checked exactly; the answer stays exact.
    #[arg(long, value_name = "PIXELS", default_value_t = pixgeo::geometry::Frame::DEFAULT_SIDE, value_parser = crate::input::parse_side)]
    size: u32,

    /// Print the answer as JSON.
    #[arg(long)]
    json: bool,

    #[command(flatten)]
    device: DeviceArg,
}

impl Common {
    /// The machine of the commands drawn on a device alone.
    fn machine(&self) -> Result<Machine> {
        crate::device::machine_on(self.device.name.as_deref())
    }
}

/// The Hausdorff distance between a red and a blue point set: for each direction,
/// the point farthest from its nearest point of the other set, and the larger of
/// the two (thesis §3.11.1).
///
/// The Voronoi diagram of one set is drawn; each point of the other set reads
/// its candidate nearest point off its pixel. Points whose pixel bounds cannot rule
/// them out are checked exactly, so the answer is exact. On a software
/// rasterizer a grid of the other set proposes the partners instead, faster
/// (--method).
///
/// Example:
///
///   pixgeo hausdorff --red a.csv --blue b.csv --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct HausdorffArgs {
    /// How partners are proposed before the exact check: `pixels` (the
    /// thesis's Voronoi picture), `grid` (a bucket grid on the CPU, with an
    /// early exit), or `auto`, the faster on the device (grid on lavapipe,
    /// pixels on a GPU). The answer is the same.
    #[arg(long, value_enum, default_value = "auto")]
    method: MethodChoice,
    /// The red points: a point file (`.csv`, `.json`, `.geojson`, `.npy`), like
    /// --sites of voronoi.
    #[arg(long, value_name = "FILE")]
    red: PathBuf,
    /// The blue points.
    #[arg(long, value_name = "FILE")]
    blue: PathBuf,
    #[command(flatten)]
    common: Common,
}

/// The diameter of a point set: the two points farthest apart, read off the
/// furthest-site diagram (thesis §3.11.2), checked exactly.
///
/// Example:
///
///   pixgeo diameter --sites points.csv
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct DiameterArgs {
    #[command(flatten)]
    points: Points,
    #[command(flatten)]
    common: Common,
}

/// The maximum distance between a red and a blue point set: the red and blue
/// points farthest apart, read off the blue set's furthest-site diagram (thesis
/// §3.11.3), checked exactly.
///
/// Example:
///
///   pixgeo maxdist --red a.csv --blue b.csv --json
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct MaxDistArgs {
    /// The red points.
    #[arg(long, value_name = "FILE")]
    red: PathBuf,
    /// The blue points.
    #[arg(long, value_name = "FILE")]
    blue: PathBuf,
    #[command(flatten)]
    common: Common,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodChoice {
    Auto,
    Pixels,
    Grid,
}

/// The `what` points, checked here so that an error names them as the user did.
fn read(path: &std::path::Path, what: &str) -> Result<Vec<DVec2>> {
    let points = sites::read_sites(path).with_context(|| format!("reading the {what} points"))?;
    check_sites(&points).with_context(|| format!("the {what} points"))?;
    Ok(points)
}

/// An answer as JSON: the pair with its indices and coordinates.
fn answer_json(answer: &Answer, from: &[DVec2], to: &[DVec2], names: [&str; 2]) -> Value {
    let point = |set: &[DVec2], i: u32| {
        let p = set[i as usize];
        json!({ "index": i, "point": [p.x, p.y] })
    };
    json!({
        "distance": answer.pair.distance,
        names[0]: point(from, answer.pair.from),
        names[1]: point(to, answer.pair.to),
        "method": answer.method,
        "picture_distance": answer.picture_pair.distance,
        "checked_exactly": answer.checked,
        "picture": (answer.method == Method::Pixels).then_some([answer.width, answer.height]),
    })
}

fn describe(answer: &Answer, from: &[DVec2], to: &[DVec2], names: [&str; 2]) -> String {
    let (a, b) = (from[answer.pair.from as usize], to[answer.pair.to as usize]);
    format!(
        "{} between {} {} ({}, {}) and {} {} ({}, {}); {} point(s) checked exactly, {}",
        Real(answer.pair.distance),
        names[0],
        answer.pair.from,
        Real(a.x),
        Real(a.y),
        names[1],
        answer.pair.to,
        Real(b.x),
        Real(b.y),
        answer.checked,
        match answer.method {
            Method::Pixels => format!("on a {}x{} picture", answer.width, answer.height),
            Method::Grid => "proposed by a grid".into(),
        }
    )
}

pub fn hausdorff(args: HausdorffArgs) -> Result<()> {
    let red = read(&args.red, "red")?;
    let blue = read(&args.blue, "blue")?;
    let need = match args.method {
        MethodChoice::Pixels => Need::Drawing("hausdorff --method pixels"),
        _ => Need::CpuUnlessGpu,
    };
    let chosen = args.common.device.choose(need)?;
    let backend = chosen.backend();
    let working = Progress::working("hausdorff", args.common.json);
    let method = match args.method {
        MethodChoice::Auto => Method::for_backend(&backend),
        MethodChoice::Pixels => Method::Pixels,
        MethodChoice::Grid => Method::Grid,
    };
    let options = distances::HausdorffOptions::default()
        .method(Some(method))
        .side(Some(args.common.size));
    let h = distances::hausdorff(&backend, &red, &blue, &options)?;
    drop(working);
    if args.common.json {
        let summary = json!({
            "hausdorff": h.distance,
            "red_to_blue": answer_json(&h.a_to_b, &red, &blue, ["red", "blue"]),
            "blue_to_red": answer_json(&h.b_to_a, &blue, &red, ["blue", "red"]),
        });
        // A grid draws no picture.
        let frame = (method == Method::Pixels).then_some(&h.a_to_b.frame);
        envelope::print("hausdorff", backend.name(), frame, &summary)?;
    } else {
        outln!("Hausdorff distance {}", Real(h.distance));
        outln!(
            "red to blue: {}",
            describe(&h.a_to_b, &red, &blue, ["red", "blue"])
        );
        outln!(
            "blue to red: {}",
            describe(&h.b_to_a, &blue, &red, ["blue", "red"])
        );
    }
    Ok(())
}

pub fn diameter(args: DiameterArgs) -> Result<()> {
    let points = args.points.read()?;
    let machine = args.common.machine()?;
    let working = Progress::working("diameter", args.common.json);
    let d = distances::diameter(&machine, &points, Some(args.common.size))?;
    drop(working);
    let names = Names {
        json: ["first", "second"],
        text: ["point", "point"],
    };
    print_answer(
        &args.common,
        &machine,
        ["diameter", "diameter"],
        &d,
        [&points, &points],
        names,
    )
}

pub fn maxdist(args: MaxDistArgs) -> Result<()> {
    let red = read(&args.red, "red")?;
    let blue = read(&args.blue, "blue")?;
    let machine = args.common.machine()?;
    let working = Progress::working("maxdist", args.common.json);
    let d = distances::max_distance(&machine, &red, &blue, Some(args.common.size))?;
    drop(working);
    let names = Names {
        json: ["red", "blue"],
        text: ["red", "blue"],
    };
    print_answer(
        &args.common,
        &machine,
        ["maxdist", "maximum distance"],
        &d,
        [&red, &blue],
        names,
    )
}

/// What the two points of an answer are called in JSON and in a line of text.
struct Names {
    json: [&'static str; 2],
    text: [&'static str; 2],
}

/// Prints one answering pair: as JSON with the device, or as a line.
fn print_answer(
    common: &Common,
    machine: &Machine,
    [command, what]: [&str; 2],
    answer: &Answer,
    sets: [&[DVec2]; 2],
    names: Names,
) -> Result<()> {
    if common.json {
        let summary = answer_json(answer, sets[0], sets[1], names.json);
        envelope::print(
            command,
            machine.device_name(),
            Some(&answer.frame),
            &summary,
        )?;
    } else {
        outln!("{what} {}", describe(answer, sets[0], sets[1], names.text));
    }
    Ok(())
}
