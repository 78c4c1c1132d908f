//! The settle point (thesis §3.10): where a new site would win the largest
//! Voronoi region.
//!
//! For a candidate pixel t, its *potential area* is the number of pixels p with
//! `dist(t, p) < dist(p, s_p)`, s_p the site nearest to p. Turned around, pixel p
//! adds one to every candidate inside its disc C(p) of radius `dist(p, s_p)`
//! (thesis's correctness argument: `p ∈ zone(t) ⟺ t ∈ C(p)`). Counting, for
//! every pixel, the discs that cover it gives the whole potential-area map at
//! once.
//!
//! Two methods count the same discs with the same membership test
//! (`in_disc` in `glsl/settle.glsl`), so their maps are identical:
//! - [`SettleMethod::Faithful`]: the thesis's GPU method. Every disc is drawn;
//!   the stencil counts covering discs with wrap-around and every 256th one adds
//!   1/255 to a colour channel by blending (Fig. 3.49). After 255 wraps per
//!   channel the next channel counts; after four the picture is read back.
//! - [`SettleMethod::Spans`]: the idea of §3.12.3 on the device. A span adds +1
//!   where it starts and -1 after it ends, and prefix sums along it yield the
//!   counts: work per disc grows with its radius, not its area. Each invocation
//!   of the compute pass cuts one disc into a core and caps, spans along rows,
//!   columns and diagonals (`glsl/settle_spans.comp`), and adds their ends with
//!   atomics to seven difference pictures; a second kernel sums them.
//!
//! Disc radii are float32 thresholds for the strict comparison `key <
//! radius` of the float32 keys of integer offsets. For L1, L2 and L∞ those
//! keys are integers, so each radius lies just above the largest integer
//! key strictly inside the exact disc (decided from the user's
//! doubles, `Certifier::disc_radius_f32`): the maps of those metrics are
//! exact below keys of 2^24 (L2: distances of 4096 pixels). Other metrics
//! take their float key rounded up.
//!
//! Pixels that already belong to one of the user's own stores ("successful
//! stores", §3.10.3) get radius 0 and add nothing.

use super::ms;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    backend::drawn_only,
    error::{Error, Result},
    geometry::{
        cell,
        frame::{check_sites, first_of_each, Checked},
        metric::Metric,
        Frame,
    },
    machine::{
        shaders, Blend, ChannelMask, Clear, ClearColor, ColorUpdate, Compare, ComputeProgram,
        DepthTest, Draw, DrawParams, Format, Fragments, GraphicsProgram, Machine, PixelRect,
        RasterState, StencilOp, StencilTest, Target, Topology, MAX_GROUPS,
    },
    Backend, Control,
};

use super::certify::Certifier;
use super::voronoi::{voronoi_checked, VoronoiOptions};

mod cpu;
mod device;
mod refine;

use cpu::potential_areas_cpu;
use device::{count_faithful, count_spans, Push};
pub use refine::{refine, Refined};

/// How the discs are counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum SettleMethod {
    /// Spans and prefix sums (§3.12.3) in a compute pass: the default.
    Spans,
    /// The thesis's discs counted by stencil wrap-around and blending (Fig. 3.49).
    Faithful,
}

/// What to compute, and the work's progress (on a device) and cancellation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SettleOptions {
    pub frame: Frame,
    pub metric: Metric,
    pub method: SettleMethod,
    pub control: Control,
}

impl SettleOptions {
    /// Euclidean, counted by row spans, on `frame`.
    pub fn new(frame: Frame) -> Self {
        Self {
            frame,
            metric: Metric::L2,
            method: SettleMethod::Spans,
            control: Control::new(),
        }
    }

    pub fn frame(self, frame: Frame) -> Self {
        Self { frame, ..self }
    }

    pub fn metric(self, metric: Metric) -> Self {
        Self { metric, ..self }
    }

    pub fn method(self, method: SettleMethod) -> Self {
        Self { method, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

impl Default for SettleOptions {
    /// On 1024 x 1024 pixels.
    fn default() -> Self {
        Self::new(Frame::pixels(1024, 1024).expect("a valid picture"))
    }
}

/// How the map was made.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct SettleStats {
    pub device: String,
    pub rivals: usize,
    pub own: usize,
    /// Pixels whose disc counts (not in an own store's region).
    pub discs: usize,
    /// Milliseconds: nearest sites and disc radii; counting; reading back.
    pub radii_ms: f64,
    pub count_ms: f64,
    pub readback_ms: f64,
    /// Pictures read back by the faithful method (thesis: five at 1024²).
    pub readbacks: u32,
}

/// The potential-area map and its maximum.
#[derive(Clone, Debug)]
pub struct PotentialAreas {
    pub width: u32,
    pub height: u32,
    /// The picture: [`Frame::to_world`] maps its pixels to world points.
    pub frame: Frame,
    /// Pixels a new site at each pixel would win, row-major.
    pub area: Vec<u32>,
    /// The largest potential area.
    pub best_area: u32,
    /// Every pixel (row-major index) with the largest potential area, ascending.
    pub best: Vec<usize>,
    pub stats: SettleStats,
}

impl PotentialAreas {
    fn new(frame: &Frame, area: Vec<u32>, stats: SettleStats) -> Self {
        let best_area = area.par_iter().copied().max().unwrap_or(0);
        let best = area
            .par_iter()
            .enumerate()
            .filter(|(_, &a)| a == best_area)
            .map(|(k, _)| k)
            .collect();
        Self {
            width: frame.width,
            height: frame.height,
            frame: *frame,
            area,
            best_area,
            best,
            stats,
        }
    }

    /// Up to `count` pixels in order of decreasing potential area (ties by index).
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a picture whose room was reserved where it was placed"
    )]
    pub fn leaders(&self, count: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.area.len()).collect();
        let count = count.min(order.len());
        if count == 0 {
            return Vec::new();
        }
        let by_area = |a: &usize, b: &usize| self.area[*b].cmp(&self.area[*a]).then(a.cmp(b));
        order.select_nth_unstable_by(count - 1, by_area);
        order.truncate(count);
        order.sort_unstable_by(by_area);
        order
    }
}

/// Checks the inputs every method shares.
fn check(rivals: &[DVec2], own: &[DVec2], frame: &Frame, metric: Metric) -> Result<()> {
    frame.check()?;
    if let Metric::Polygon(_) = metric {
        // A star-shaped disc's rows need not be single spans.
        return Err(Error::unsupported_option(
            "the settle point takes the L_p metrics; polygonal distances are not counted yet"
                .into(),
        ));
    }
    check_sites(rivals).map_err(|e| e.about("rival sites"))?;
    if !own.is_empty() {
        check_sites(own).map_err(|e| e.about("own sites"))?;
    }
    Ok(())
}

/// Each pixel's disc radius as the shaders compare it: the positions
/// strictly nearer to the pixel than its nearest rival (given the nearest
/// site ids of both sets; sites in world coordinates), exactly where the keys
/// of integer offsets are integers (see the module notes), or 0 where an own
/// store is at least as near, decided exactly.
fn disc_radius_keys(
    frame: &Frame,
    metric: Metric,
    rivals: &[DVec2],
    rival_labels: &[u32],
    own: &[DVec2],
    own_labels: Option<&[u32]>,
) -> Result<Vec<f32>> {
    let rival_sites = Certifier::new(rivals, frame, metric)?;
    let own_sites = own_labels
        .map(|labels| Certifier::new(own, frame, metric).map(|c| (c, labels)))
        .transpose()?;
    let w = frame.width as usize;
    // Sites far outside the picture give discs that cover it whole.
    let covering = rival_sites.covering_radius();
    Ok((0..frame.len())
        .into_par_iter()
        .map(|k| {
            let pixel = [(k % w) as i64, (k / w) as i64];
            let owned = own_sites.as_ref().is_some_and(|(sites, labels)| {
                sites.no_farther(labels[k], &rival_sites, rival_labels[k], pixel)
            });
            match owned {
                true => 0.0,
                false => rival_sites
                    .disc_radius_f32(&rival_sites.disc(pixel, rival_labels[k]))
                    .min(covering),
            }
        })
        .collect())
}

/// Each position of `points` once, in their first order: the areas depend on
/// where sites are, not on how many stand at one place, and every repeat
/// would be a candidate at every pixel's check.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn distinct(points: &[DVec2]) -> Vec<DVec2> {
    first_of_each(points)
        .iter()
        .map(|&i| points[i as usize])
        .collect()
}

/// The potential-area map of a new site among `rivals`, not counting pixels that
/// `own` stores already hold (world coordinates): on a device by the method
/// the options name, on the CPU by row spans ([`SettleMethod::Faithful`]
/// draws, so it needs a device); the same counts on every route.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::settle::{potential_areas, SettleOptions}, geometry::Frame};
///
/// let rivals = [DVec2::new(5.0, 5.0), DVec2::new(58.0, 42.0)];
/// let options = SettleOptions::new(Frame::pixels(64, 48)?);
/// let map = potential_areas(&pixgeo::Backend::Cpu, &rivals, &[], &options)?;
/// assert!(map.best_area > 0 && map.area.len() == 64 * 48);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn potential_areas(
    backend: &Backend,
    rivals: &[DVec2],
    own: &[DVec2],
    options: &SettleOptions,
) -> Result<PotentialAreas> {
    let progress = &mut |done, total| options.control.report(done, total);
    options.control.run(|| match (backend, options.method) {
        (Backend::Device(machine), _) => drawn(machine, rivals, own, options, progress),
        (Backend::Cpu, SettleMethod::Spans) => {
            potential_areas_cpu(rivals, own, &options.frame, options.metric)
        }
        (Backend::Cpu, SettleMethod::Faithful) => {
            Err(drawn_only("the faithful method's disc count"))
        }
    })
}

/// [`potential_areas`] on a device.
fn drawn(
    machine: &Machine,
    rivals: &[DVec2],
    own: &[DVec2],
    options: &SettleOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<PotentialAreas> {
    let frame = options.frame;
    check(rivals, own, &frame, options.metric)?;
    let (rivals, own) = (&distinct(rivals)[..], &distinct(own)[..]);
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::PictureTooLarge {
            width: frame.width,
            height: frame.height,
            limit: side,
        });
    }
    // Each of the span counting's difference pictures is one storage buffer.
    let bytes = 4 * frame.len() as u64;
    if options.method == SettleMethod::Spans && bytes > machine.max_storage_buffer_bytes() {
        return Err(Error::out_of_range(format!(
            "span counting needs {} MB per picture of {}x{} counts; the device allows {} MB \
             per buffer (use a smaller picture)",
            bytes >> 20,
            frame.width,
            frame.height,
            machine.max_storage_buffer_bytes() >> 20
        )));
    }
    let start = Instant::now();
    let diagram_options = VoronoiOptions {
        metric: options.metric,
        distances: false,
        ..VoronoiOptions::exact(frame)
    };
    // The distinct sites of the sets checked above.
    let labels = |sites| {
        voronoi_checked(
            &Backend::Device(machine),
            Checked::derived(sites),
            &diagram_options,
        )
    };
    let rival_labels = labels(rivals)?.labels;
    let own_labels = if own.is_empty() {
        None
    } else {
        Some(labels(own)?.labels)
    };
    let keys = disc_radius_keys(
        &frame,
        options.metric,
        rivals,
        &rival_labels,
        own,
        own_labels.as_deref(),
    )?;
    let mut stats = SettleStats {
        device: machine.device_name().to_string(),
        rivals: rivals.len(),
        own: own.len(),
        discs: keys.iter().filter(|&&k| k > 0.0).count(),
        radii_ms: ms(start),
        ..Default::default()
    };
    let mut radii = machine.storage_buffer(4 * frame.len() as u64)?;
    radii.write(&keys);
    let push = Push {
        frame,
        code: Certifier::shader_code(options.metric),
    };
    let area = match options.method {
        SettleMethod::Spans => count_spans(machine, &radii, push, &mut stats, progress)?,
        SettleMethod::Faithful => count_faithful(machine, &radii, push, &mut stats, progress)?,
    };
    Ok(PotentialAreas::new(&frame, area, stats))
}
