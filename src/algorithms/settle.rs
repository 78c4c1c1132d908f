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
//! Disc radii are metric keys rounded up to the next float32: for L1, L2 and L∞
//! the keys of integer offsets are exact integers, so the strict comparison
//! `key < radius` gives the same answer as the exact comparison with the
//! float64 radius. The maps of those metrics therefore equal the definition
//! evaluated in float64.
//!
//! Pixels that already belong to one of the user's own stores ("successful
//! stores", §3.10.3) get radius 0 and add nothing.
//!
//! The file is long because both methods live here, with the programs they
//! declare, beside the disc radii and the answer they share.

use super::ms;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::{cell, frame::check_sites, metric::Metric, Frame},
    machine::{
        shaders, Blend, ChannelMask, Clear, ClearColor, ColorUpdate, Compare, ComputeProgram,
        DepthTest, Draw, DrawParams, Format, Fragments, GraphicsProgram, Machine, PixelRect,
        RasterState, StencilOp, StencilTest, Target, Topology, MAX_GROUPS,
    },
};

use super::voronoi::{voronoi, VoronoiOptions};

/// Push constants of the settle programs (`glsl/settle.glsl`): `[width,
/// height, metric kind, p, first, count, channel]`.
type SettleWords = [u32; 7];

/// The settle point's discs (thesis §3.10.3): one square per source pixel,
/// instanced without vertex buffers; the fragment shader keeps the disc and
/// reads each pixel's radius from the bound storage buffer. Its fragment
/// builds follow the distance function's kind.
static SETTLE_DISC: GraphicsProgram = GraphicsProgram::new(
    "SettleDisc",
    shaders::SETTLE_DISC_VERT,
    Fragments::ByVariant(&shaders::SETTLE_DISC_FRAG),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<SettleWords>(),
);

/// The span counting: every disc's parts into seven difference pictures of
/// `i32` in buffers 1 to 7, one invocation per source pixel, by the distance
/// function's kind.
static SETTLE_SPANS: [ComputeProgram; 4] = {
    const fn spans(name: &'static str, shader: crate::machine::Shader) -> ComputeProgram {
        ComputeProgram::new(name, shader, std::mem::size_of::<SettleWords>())
    }
    [
        spans("SettleSpans(L2)", shaders::SETTLE_SPANS_COMP[0]),
        spans("SettleSpans(L1)", shaders::SETTLE_SPANS_COMP[1]),
        spans("SettleSpans(LInf)", shaders::SETTLE_SPANS_COMP[2]),
        spans("SettleSpans(Lp)", shaders::SETTLE_SPANS_COMP[3]),
    ]
};

/// The counts from those difference pictures, into the first (push `[width,
/// height, phase]`, one invocation per column, per diagonal, per antidiagonal
/// and per row in phases 0 to 3).
static SETTLE_SUMS: ComputeProgram = ComputeProgram::new(
    "SettleSums",
    shaders::SETTLE_SUMS_COMP,
    std::mem::size_of::<[u32; 3]>(),
);

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

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SettleOptions {
    pub frame: Frame,
    pub metric: Metric,
    pub method: SettleMethod,
}

impl SettleOptions {
    /// Euclidean, counted by row spans, on `frame`.
    pub fn new(frame: Frame) -> Self {
        Self {
            frame,
            metric: Metric::L2,
            method: SettleMethod::Spans,
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
        return Err(Error::InvalidInput(
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

/// Each pixel's disc radius key: the key of its nearest rival, or 0 where an own
/// store is at least as near (given the nearest site ids of both sets; sites in
/// pixel coordinates). Rounded up to float32 (see the module notes).
fn disc_radius_keys(
    frame: &Frame,
    metric: Metric,
    rivals: &[DVec2],
    rival_labels: &[u32],
    own: &[DVec2],
    own_labels: Option<&[u32]>,
) -> Vec<f32> {
    let w = frame.width as usize;
    let key = |sites: &[DVec2], label: u32, k: usize| -> f64 {
        let p = DVec2::new((k % w) as f64, (k / w) as f64);
        sites
            .get(label as usize)
            .map_or(f64::INFINITY, |s| metric.key(*s - p))
    };
    (0..frame.len())
        .into_par_iter()
        .map(|k| {
            let rival = key(rivals, rival_labels[k], k);
            let owned = own_labels.is_some_and(|labels| key(own, labels[k], k) <= rival);
            if owned {
                0.0
            } else {
                round_up_f32(rival)
            }
        })
        .collect()
}

/// The smallest float32 at least `x`.
fn round_up_f32(x: f64) -> f32 {
    let f = x as f32;
    // For finite positive f the next float up has the next bit pattern.
    if (f as f64) < x && f.is_finite() && f >= 0.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        f
    }
}

/// The potential-area map of a new site among `rivals`, not counting pixels that
/// `own` stores already hold (world coordinates), on the pixel machine.
/// `progress(done, total)` is called as the counting proceeds.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::settle::{potential_areas, SettleOptions}, geometry::Frame};
///
/// let rivals = [DVec2::new(5.0, 5.0), DVec2::new(58.0, 42.0)];
/// let options = SettleOptions::new(Frame::pixels(64, 48)?);
/// let map = pixgeo::with_default_machine(|m| potential_areas(m, &rivals, &[], &options, &mut |_, _| {}))?;
/// assert!(map.best_area > 0 && map.area.len() == 64 * 48);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn potential_areas(
    machine: &Machine,
    rivals: &[DVec2],
    own: &[DVec2],
    options: &SettleOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<PotentialAreas> {
    let frame = options.frame;
    check(rivals, own, &frame, options.metric)?;
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
        return Err(Error::InvalidInput(format!(
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
    let rival_labels = voronoi(machine, rivals, &diagram_options)?.labels;
    let own_labels = if own.is_empty() {
        None
    } else {
        Some(voronoi(machine, own, &diagram_options)?.labels)
    };
    let keys = disc_radius_keys(
        &frame,
        options.metric,
        &to_pixels(rivals, &frame),
        &rival_labels,
        &to_pixels(own, &frame),
        own_labels.as_deref(),
    );
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
        metric: options.metric,
    };
    let area = match options.method {
        SettleMethod::Spans => count_spans(machine, &radii, push, &mut stats, progress)?,
        SettleMethod::Faithful => count_faithful(machine, &radii, push, &mut stats, progress)?,
    };
    Ok(PotentialAreas::new(&frame, area, stats))
}

fn to_pixels(sites: &[DVec2], frame: &Frame) -> Vec<DVec2> {
    sites.iter().map(|&s| frame.to_pixel(s)).collect()
}

/// The push constants of the settle programs (`glsl/settle.glsl`).
#[derive(Clone, Copy)]
struct Push {
    frame: Frame,
    metric: Metric,
}

impl Push {
    /// The kind of distance function and its exponent (`check` keeps polygons out).
    fn metric_code(&self) -> (u32, f32) {
        self.metric.shader_code().unwrap_or((0, 2.0))
    }

    fn words(&self, first: u32, count: u32, channel: u32) -> SettleWords {
        let (kind, p) = self.metric_code();
        [
            self.frame.width,
            self.frame.height,
            kind,
            p.to_bits(),
            first,
            count,
            channel,
        ]
    }
}

/// Difference pictures of the span counting (`glsl/settle_spans.comp`); the
/// first ends up holding the counts.
const SPAN_PICTURES: usize = 7;

fn count_spans(
    machine: &Machine,
    radii: &crate::machine::Buffer,
    push: Push,
    stats: &mut SettleStats,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u32>> {
    let frame = push.frame;
    let pixels = frame.len() as u32;
    let bytes = 4 * pixels as u64;
    let pictures = (0..SPAN_PICTURES)
        .map(|_| {
            let mut picture = machine.storage_buffer(bytes)?;
            picture.fill(0);
            Ok(picture)
        })
        .collect::<Result<Vec<_>>>()?;
    let buffers: Vec<_> = std::iter::once(radii).chain(&pictures).collect();
    let start = Instant::now();
    let kind = push.metric_code().0;
    // About 64 submissions, for progress; each within one dispatch's limits.
    let step = pixels
        .div_ceil(64)
        .clamp(1, MAX_GROUPS * SETTLE_SPANS[0].group());
    let mut first = 0;
    while first < pixels {
        let count = step.min(pixels - first);
        machine.run(|pass| {
            let kernel = SETTLE_SPANS.get(kind as usize).ok_or_else(|| {
                Error::InvalidInput(format!(
                    "settle spans are not built for distance kind {kind}"
                ))
            })?;
            pass.dispatch(
                kernel,
                &buffers,
                count,
                bytemuck::bytes_of(&push.words(first, count, 0)),
            )
        })?;
        first += count;
        progress(first as u64, pixels as u64);
    }
    machine.run(|pass| {
        let (w, h) = (frame.width, frame.height);
        // Columns, the two kinds of diagonals, rows.
        for (phase, lines) in [(0, w), (1, w + h - 1), (2, w + h - 1), (3, h)] {
            pass.dispatch(
                &SETTLE_SUMS,
                &buffers,
                lines,
                bytemuck::bytes_of(&[w, h, phase]),
            )?;
        }
        Ok(())
    })?;
    stats.count_ms = ms(start);
    let start = Instant::now();
    let area = pictures[0].read::<u32>(pixels as usize);
    stats.readback_ms = ms(start);
    Ok(area)
}

/// Discs one channel may count: 255 wrap-arounds of the 8-bit stencil, each
/// adding 1/255, fill the 8-bit channel, and a pixel is covered at most once per
/// disc.
const DISCS_PER_CHANNEL: u32 = 255 * 256;

fn count_faithful(
    machine: &Machine,
    radii: &crate::machine::Buffer,
    push: Push,
    stats: &mut SettleStats,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u32>> {
    let frame = push.frame;
    let pixels = frame.len() as u32;
    let (w, h) = (frame.width, frame.height);
    let color = machine.image(Format::Rgba8Unorm, w, h)?;
    let depth_stencil = machine.image(Format::DepthStencil, w, h)?;
    // Fig. 3.49: stencil starts at 1, passes where it is 0, and every fragment
    // increments it with wrap-around; passing fragments add their colour.
    let state = RasterState {
        depth: DepthTest::OFF,
        stencil: StencilTest {
            compare: Compare::Equal,
            compare_mask: 0xff,
            write_mask: 0xff,
            on_fail: StencilOp::IncrementWrap,
            on_depth_fail: StencilOp::IncrementWrap,
            on_pass: StencilOp::IncrementWrap,
        },
        color: ColorUpdate::Blend(Blend::ADD),
        color_mask: ChannelMask::ALL,
    };
    let params = DrawParams::default();
    let target = Target {
        color: Some(&color),
        depth_stencil: Some(&depth_stencil),
    };
    let mut total = vec![0u32; pixels as usize];
    let mut rgba = vec![0u32; pixels as usize];
    let mut count_ms = 0.0;
    let mut readback_ms = 0.0;
    let mut first = 0;
    let mut channel = 0;
    while first < pixels {
        let count = DISCS_PER_CHANNEL.min(pixels - first);
        let clear = Clear {
            color: (channel == 0).then_some(ClearColor::Float([0.0; 4])),
            depth: (first == 0).then_some(1.0),
            stencil: (first == 0).then_some(1),
        };
        let start = Instant::now();
        machine.run(|pass| {
            pass.bind_fragment_buffers(&[radii], None)?;
            pass.begin(target, clear)?;
            pass.draw(
                &state,
                &params,
                &Draw {
                    program: &SETTLE_DISC,
                    variant: push.metric_code().0,
                    push: bytemuck::bytes_of(&push.words(first, count, channel)),
                    vertex_buffers: &[],
                    vertices: 0..4,
                    instances: 0..count,
                },
            )?;
            pass.end()
        })?;
        count_ms += ms(start);
        first += count;
        channel += 1;
        if channel == 4 || first == pixels {
            let start = Instant::now();
            let rect = PixelRect::of(&color);
            machine.read_u32_into(&color, rect, &mut rgba, w as usize)?;
            total.par_iter_mut().zip(&rgba).for_each(|(t, &c)| {
                let wraps: u32 = c.to_le_bytes().iter().map(|&b| b as u32).sum();
                *t += 256 * wraps;
            });
            stats.readbacks += 1;
            readback_ms += ms(start);
            channel = 0;
        }
        progress(first as u64, pixels as u64);
    }
    // The hits since the last wrap: the stencil started at 1.
    let start = Instant::now();
    machine.read_stencil_into(
        &depth_stencil,
        PixelRect::of(&depth_stencil),
        &mut rgba,
        w as usize,
    )?;
    total
        .par_iter_mut()
        .zip(&rgba)
        .for_each(|(t, &s)| *t += (s + 255) % 256);
    stats.readbacks += 1;
    stats.count_ms = count_ms;
    stats.readback_ms = readback_ms + ms(start);
    Ok(total)
}

/// The potential-area map computed on the CPU with the thesis's own variant
/// (§3.12.3): every disc's border is walked row by row, +1 and -1 mark each row
/// span, and prefix sums along the rows give the counts. Threads take bands of
/// target rows: a band's differences stay in cache, and each disc that reaches
/// the band walks only the band's rows. Nearest sites come from
/// the CPU Voronoi diagram (Euclidean) or a search over all sites (other
/// metrics).
pub fn potential_areas_cpu(
    rivals: &[DVec2],
    own: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Result<PotentialAreas> {
    check(rivals, own, frame, metric)?;
    let start = Instant::now();
    let rivals_px = to_pixels(rivals, frame);
    let own_px = to_pixels(own, frame);
    let rival_labels = nearest_labels_cpu(rivals, frame, metric)?;
    let own_labels = if own.is_empty() {
        None
    } else {
        Some(nearest_labels_cpu(own, frame, metric)?)
    };
    let keys = disc_radius_keys(
        frame,
        metric,
        &rivals_px,
        &rival_labels,
        &own_px,
        own_labels.as_deref(),
    );
    let mut stats = SettleStats {
        device: "cpu".into(),
        rivals: rivals.len(),
        own: own.len(),
        discs: keys.iter().filter(|&&k| k > 0.0).count(),
        radii_ms: ms(start),
        ..Default::default()
    };
    let start = Instant::now();
    let (w, h) = (frame.width as usize, frame.height as usize);
    // How far each disc reaches along its row and column, and the farthest of
    // each source row.
    let limit = w.max(h) as i64;
    let reaches: Vec<i64> = keys
        .par_iter()
        .map(|&key| disc_reach(metric, key, limit))
        .collect();
    let row_reach: Vec<i64> = reaches
        .chunks(w)
        .map(|row| row.iter().copied().max().unwrap_or(-1))
        .collect();
    let mut area = vec![0i32; w * h];
    area.par_chunks_mut(BAND_ROWS * w)
        .enumerate()
        .for_each(|(b, band)| {
            let rows = (b * BAND_ROWS) as i64..((b + 1) * BAND_ROWS).min(h) as i64;
            for (py, reach) in row_reach.iter().enumerate() {
                let py = py as i64;
                if py + reach < rows.start || py - reach >= rows.end {
                    continue;
                }
                let source = py as usize * w;
                for x in 0..w {
                    let disc = (keys[source + x], reaches[source + x]);
                    add_band_spans(band, &rows, w as i64, metric, (x as i64, py), disc);
                }
            }
            for row in band.chunks_mut(w) {
                let mut sum = 0;
                for v in row {
                    sum += *v;
                    *v = sum;
                }
            }
        });
    stats.count_ms = ms(start);
    let area = area.into_iter().map(|v| v as u32).collect();
    Ok(PotentialAreas::new(frame, area, stats))
}

/// Target rows per task of the CPU variant.
const BAND_ROWS: usize = 16;

/// Whether offset (dx, dy) lies in the disc of radius key `key` (as
/// `in_disc` of `glsl/settle.glsl`, in float64).
fn in_disc(metric: Metric, dx: i64, dy: i64, key: f32) -> bool {
    match metric {
        // The same squared distance, exact in integers.
        Metric::L2 => ((dx * dx + dy * dy) as f64) < key as f64,
        _ => metric.key(DVec2::new(dx as f64, dy as f64)) < key as f64,
    }
}

/// The largest offset along a row or column inside the disc of `key`, at most
/// `limit`; -1 when the disc is empty.
fn disc_reach(metric: Metric, key: f32, limit: i64) -> i64 {
    if key.is_nan() || key <= 0.0 {
        return -1;
    }
    let mut m = metric.distance_of_key(key as f64).min(limit as f64) as i64;
    while m < limit && in_disc(metric, m + 1, 0, key) {
        m += 1;
    }
    while m >= 0 && !in_disc(metric, m, 0, key) {
        m -= 1;
    }
    m
}

/// The largest m <= `reach` with offset (m, dy) in the disc of `key` (-1 when
/// none): from the metric's closed form, then corrected step by step.
fn half_width(metric: Metric, dy: i64, key: f32, reach: i64) -> i64 {
    let (k, y) = (key as f64, dy as f64);
    let guess = match metric {
        Metric::L2 => (k - y * y).max(0.0).sqrt(),
        Metric::L1 => k - y,
        Metric::Lp(p) => (k.powf(p) - y.powf(p)).max(0.0).powf(1.0 / p),
        _ => k,
    };
    let mut m = (guess.max(0.0) as i64).min(reach);
    while m < reach && in_disc(metric, m + 1, dy, key) {
        m += 1;
    }
    while m >= 0 && !in_disc(metric, m, dy, key) {
        m -= 1;
    }
    m
}

/// Adds the row spans of the disc of pixel (x, y), of radius key `key` and
/// reach `reach` ([`disc_reach`]), on the target rows `rows` of a picture `w`
/// pixels wide to `band`, the differences of those rows. Rows are visited by
/// growing distance from the disc's centre row, where the span only shrinks.
fn add_band_spans(
    band: &mut [i32],
    rows: &std::ops::Range<i64>,
    w: i64,
    metric: Metric,
    (x, y): (i64, i64),
    (key, reach): (f32, i64),
) {
    if reach < 0 || y + reach < rows.start || y - reach >= rows.end {
        return;
    }
    let mut add = |row: i64, m: i64| {
        let base = ((row - rows.start) * w) as usize;
        band[base + (x - m).max(0) as usize] += 1;
        if x + m + 1 < w {
            band[base + (x + m + 1) as usize] -= 1;
        }
    };
    // Rows at and below the centre, then above it, each by growing distance.
    let below = rows.start.max(y)..rows.end.min(y + reach + 1);
    let above = rows.start.max(y - reach)..rows.end.min(y);
    let mut walk = |first_dy: i64, count: i64, row_of: &dyn Fn(i64) -> i64| {
        let mut m = half_width(metric, first_dy, key, reach);
        for k in 0..count {
            let dy = first_dy + k;
            while m >= 0 && !in_disc(metric, m, dy, key) {
                m -= 1;
            }
            if m < 0 {
                break;
            }
            add(row_of(dy), m);
        }
    };
    if !below.is_empty() {
        walk(below.start - y, below.end - below.start, &|dy| y + dy);
    }
    if !above.is_empty() {
        walk(y - (above.end - 1), above.end - above.start, &|dy| y - dy);
    }
}

/// Nearest site per pixel on the CPU: the thesis's growing sites (§3.12.1).
fn nearest_labels_cpu(sites: &[DVec2], frame: &Frame, metric: Metric) -> Result<Vec<u32>> {
    Ok(super::cpu::k_nearest(sites, frame, 1, metric)?.labels)
}

/// The refined settle point: a position (pixel coordinates) and the exact area
/// (square pixels) of the region a new site there would win, clipped to the
/// picture and without the own stores' regions.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Refined {
    pub position: [f64; 2],
    pub area: f64,
    /// The exact area at the pixel the search started from.
    pub start_area: f64,
    pub start_pixel: [u32; 2],
}

/// Refines the settle point beyond the pixels (Euclidean metric): from each of
/// the `starts` (row-major pixel indices), a compass search over the exact area
/// of the new site's Voronoi region (`cell::StolenArea`) climbs to a local
/// maximum, halving its step from one pixel to 1e-9 pixels; the best climb wins.
/// The result's area is at least the exact area at its starting pixel. Sites in
/// world coordinates; the result in pixel coordinates.
pub fn refine(rivals: &[DVec2], own: &[DVec2], frame: &Frame, starts: &[usize]) -> Result<Refined> {
    check(rivals, own, frame, Metric::L2)?;
    if starts.is_empty() {
        return Err(Error::InvalidInput("no pixel to refine from".into()));
    }
    let rivals = to_pixels(rivals, frame);
    let own = to_pixels(own, frame);
    let picture = cell::Rect {
        lo: DVec2::splat(-0.5),
        hi: DVec2::new(frame.width as f64 - 0.5, frame.height as f64 - 0.5),
    };
    let w = frame.width as usize;
    let climbs: Vec<Refined> = starts
        .par_iter()
        .map(|&k| {
            let pixel = [(k % w) as u32, (k / w) as u32];
            let start = DVec2::new(pixel[0] as f64, pixel[1] as f64);
            let stolen = cell::StolenArea::new(start, &rivals, &own, &picture);
            let area = |t: DVec2| stolen.at(t);
            let (position, best) = compass_search(start, &area, &picture);
            Refined {
                position: position.to_array(),
                area: best,
                start_area: area(start),
                start_pixel: pixel,
            }
        })
        .collect();
    climbs
        .into_iter()
        .max_by(|a, b| a.area.total_cmp(&b.area))
        .ok_or_else(|| Error::InvalidInput("no pixel to refine from".into()))
}

/// Climbs `f` from `start` within `bounds` by compass steps (eight directions),
/// halving the step whenever no direction improves.
fn compass_search(start: DVec2, f: &dyn Fn(DVec2) -> f64, bounds: &cell::Rect) -> (DVec2, f64) {
    let directions = [
        DVec2::new(1.0, 0.0),
        DVec2::new(-1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(0.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(-1.0, 1.0),
        DVec2::new(-1.0, -1.0),
    ];
    let (mut x, mut best) = (start, f(start));
    let mut step = 1.0;
    while step > 1e-9 {
        let improved = directions
            .iter()
            .map(|d| (x + *d * step).clamp(bounds.lo, bounds.hi))
            .map(|y| (y, f(y)))
            .filter(|&(_, v)| v > best)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match improved {
            Some((y, v)) => (x, best) = (y, v),
            None => step *= 0.5,
        }
    }
    (x, best)
}
