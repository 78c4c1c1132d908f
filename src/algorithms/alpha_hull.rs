//! Alpha hulls of point sets (thesis ch. 6, after Edelsbrunner, Kirkpatrick and
//! Seidel): for α > 0 the intersection of all closed discs of radius 1/α that hold
//! every site, for α < 0 what the open discs of radius -1/α that hold no site
//! leave of the plane, and the convex hull for α = 0.
//!
//! - **α < 0** (§6.3): the lower envelope of the sites' cones; a picture-wide
//!   rectangle at the depth of r = -1/α marks every pixel at least r from all
//!   sites (a centre of an empty disc); discs of radius r around the rim of that
//!   set erase the rest. Every disc centred inside the set is covered by the set
//!   and the rim's discs (a staircase path from such a centre towards a pixel
//!   gets no farther from it and leaves the set at a rim pixel), so the rim is
//!   enough. Empty discs whose centres lie outside the picture are not drawn, so
//!   pixels within r of the picture border may be wrongly inside: the picture
//!   reaches r beyond the sites where it can, and the result counts the inside
//!   pixels of that band.
//! - **α > 0, [`AlphaMethod::Hull`]** (§6.4.1): a counter-clockwise walk over the
//!   convex hull keeps the circles of radius R = 1/α through consecutive hull
//!   points that hold every hull point; the α-hull is the intersection of those
//!   circles, the pixels every one of them covers (counted with blending). The
//!   thesis tests a circle by reading back the hull points' pixels; the two
//!   points it passes through lie on its rim, where a pixel cannot decide, so
//!   pixgeo tests in exact arithmetic and draws only the circles that hold.
//! - **α > 0, [`AlphaMethod::Pixels`]** (§6.4.2): nothing but the machine. Discs
//!   of radius R around every site, counted, leave the pixels that can centre a
//!   disc holding all sites; discs of radius R around the first and last such
//!   pixel of every row (the set is convex, so they bound the rest), counted
//!   again, leave the hull. The picture must hold every such centre, so it
//!   spans 2R around the smallest enclosing circle's centre (the thesis's
//!   Fig. 6.6: a large R leaves the hull few pixels).
//!
//! A radius below the smallest enclosing circle's is an error: no disc holds
//! every site.

use crate::geometry::exact::predicates::convex_hull;
use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use crate::{
    algorithms::{
        cones::{draw_cones, ConeDraw, ConePush, SITE_FAN},
        voronoi::{draw_point_tiles, TileExtras, VoronoiOptions},
    },
    error::{Error, Result},
    geometry::exact::circle::welzl,
    geometry::{
        frame::{first_of_each, Checked},
        Frame,
    },
    machine::{
        shaders, Clear, ClearColor, Compare, DepthTest, Draw, DrawParams, Format, Fragments,
        GraphicsProgram, Image, Machine, Pass, PixelRect, RasterState, RectDraw, Target, Topology,
        VertexAttribute, VertexBuffer, VertexFormat,
    },
};

/// Picture side (pixels, longer axis) when none is given.
pub const DEFAULT_SIDE: u32 = Frame::DEFAULT_SIDE;

/// How a hull for α > 0 is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum AlphaMethod {
    /// Circles through consecutive points of a convex hull computed on the CPU.
    Hull,
    /// Two intersections of discs by counting, on the machine alone.
    Pixels,
}

/// What a pixel of [`AlphaHull::pixels`] is.
pub mod class {
    /// Outside the hull.
    pub const OUTSIDE: u8 = 0;
    /// Inside the hull.
    pub const INSIDE: u8 = 1;
    /// α < 0: at least r from every site, erased by the rectangle. α > 0 with
    /// [`super::AlphaMethod::Pixels`]: the centre of a disc holding every site
    /// (and outside the hull).
    pub const CENTRE: u8 = 2;
    /// α < 0: erased by a disc around the rim of the centres.
    pub const DISC: u8 = 3;
}

/// An α-hull on a picture.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AlphaHull {
    pub alpha: f64,
    /// |1/α| in world units; `None` for the convex hull (α = 0).
    pub radius: Option<f64>,
    /// How the hull was found.
    pub method: HullMethod,
    pub width: u32,
    pub height: u32,
    /// World point at the picture's corner (-0.5, -0.5), and pixels per world unit.
    pub origin: [f64; 2],
    pub scale: f64,
    /// Pixels inside the hull.
    pub inside: usize,
    /// Discs drawn (all passes).
    pub discs: usize,
    /// α > 0 with the hull method, and α = 0: the sites on the hull's boundary,
    /// counter-clockwise (duplicates once).
    pub boundary_sites: Vec<u32>,
    /// α < 0: pixels within this distance (world units) of the picture border
    /// may be inside only because discs centred beyond the border are not drawn.
    pub border_band: f64,
    /// α < 0: inside pixels in that band.
    pub uncertain: usize,
    /// One [`class`] per pixel, row-major (`[j][i]`).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub pixels: Vec<u8>,
    #[cfg_attr(feature = "serde", serde(skip))]
    pub frame: Frame,
}

impl AlphaHull {
    /// 1 inside the hull, 0 outside, row-major: the `--mask` array.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a picture whose room was reserved where it was placed"
    )]
    pub fn mask(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .map(|&c| u8::from(c == class::INSIDE))
            .collect()
    }
}

/// Which α-hull to draw, and where: α (0 the convex hull, > 0 discs of
/// radius 1/α holding every site, < 0 discs of radius 1/|α| holding none),
/// the algorithm for α > 0, and the picture.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct AlphaOptions {
    pub alpha: f64,
    pub method: AlphaMethod,
    pub canvas: Canvas,
}

impl AlphaOptions {
    /// The hull of `alpha` by [`AlphaMethod::Hull`] on a picture of
    /// [`DEFAULT_SIDE`] pixels.
    pub fn new(alpha: f64) -> Self {
        Self {
            alpha,
            method: AlphaMethod::Hull,
            canvas: Canvas::Side(DEFAULT_SIDE),
        }
    }

    pub fn method(self, method: AlphaMethod) -> Self {
        Self { method, ..self }
    }

    /// A picture whose longer side has `side` pixels, fitted to where the
    /// hull can be.
    pub fn side(self, side: u32) -> Self {
        let canvas = Canvas::Side(side);
        Self { canvas, ..self }
    }

    /// The picture `frame` (a map's extent, say). Pixels within -1/α of its
    /// border may be overestimated for α < 0 (the answer counts them); the
    /// pixel method needs the frame to hold every centre of a disc holding
    /// the sites.
    pub fn frame(self, frame: Frame) -> Self {
        let canvas = Canvas::Frame(frame);
        Self { canvas, ..self }
    }
}

/// The α-hull of `sites` as `options` say.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::alpha_hull::{alpha_hull, AlphaOptions};
///
/// let sites = [DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(10.0, 10.0), DVec2::new(0.0, 10.0)];
/// // Discs of radius 20 holding every site: a square with bulging sides.
/// let options = AlphaOptions::new(0.05).side(256);
/// let hull = pixgeo::with_default_machine(|m| alpha_hull(m, &sites, &options))?;
/// assert_eq!(hull.boundary_sites.len(), 4);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn alpha_hull(machine: &Machine, sites: &[DVec2], options: &AlphaOptions) -> Result<AlphaHull> {
    if let Canvas::Side(side) = options.canvas {
        if side == 0 || side > machine.max_picture_side() {
            return Err(Error::out_of_range(format!(
                "picture side {side}: it must be between 1 and {} on this device",
                machine.max_picture_side()
            )));
        }
    }
    hull_on(
        machine,
        Checked::new(sites)?,
        options.alpha,
        options.method,
        options.canvas,
    )
}

/// Where a hull is drawn: a picture of so many pixels along its longer side,
/// fitted around where the hull can be, or the user's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Canvas {
    Side(u32),
    Frame(Frame),
}

impl Canvas {
    /// The frame for a hull that lies in `[lo, hi]`, padded by `pad`.
    /// Refused up front where the process cannot hold the hull's pictures.
    fn around(self, lo: DVec2, hi: DVec2, pad: f64) -> Result<Frame> {
        let frame = match self {
            Canvas::Side(side) => frame_around(lo, hi, pad, side)?,
            Canvas::Frame(frame) => frame,
        };
        // A float picture of disc counts, its readback, the classes and the
        // centres' mask, with room (`docs/tuning.md`).
        frame.reserve(16, "an α-hull")?;
        Ok(frame)
    }

    /// The width of a pixel (world units) for sites spanning `[lo, hi]`.
    fn pixel(self, lo: DVec2, hi: DVec2) -> f64 {
        match self {
            Canvas::Side(side) => (hi - lo).max_element() / side as f64,
            Canvas::Frame(frame) => 1.0 / frame.scale,
        }
    }
}

fn hull_on(
    machine: &Machine,
    sites: Checked<'_>,
    alpha: f64,
    method: AlphaMethod,
    canvas: Canvas,
) -> Result<AlphaHull> {
    let sites = sites.sites();
    if !alpha.is_finite() {
        return Err(Error::not_finite(
            None,
            format!("alpha {alpha} is not finite"),
        ));
    }
    // The hull depends on where sites are, not on how many stand at one
    // place: the first of each position stands for all (a million copies
    // were a million cones and discs).
    let kept = first_of_each(sites);
    if kept.len() < sites.len() {
        let distinct: Vec<DVec2> = kept.iter().map(|&i| sites[i as usize]).gather("distinct")?;
        let mut hull = hull_on(machine, Checked::derived(&distinct), alpha, method, canvas)?;
        for site in &mut hull.boundary_sites {
            *site = kept[*site as usize];
        }
        return Ok(hull);
    }
    if alpha < 0.0 {
        negative(machine, sites, alpha, canvas)
    } else if alpha == 0.0 || bulge_below_resolution(sites, alpha, canvas) {
        let hull = convex(machine, sites, canvas)?;
        Ok(AlphaHull {
            alpha,
            radius: (alpha != 0.0).then(|| 1.0 / alpha),
            ..hull
        })
    } else {
        positive(machine, sites, alpha, method, canvas)
    }
}

/// Whether discs of radius 1/α bulge past the convex hull by less than a
/// thousandth of a pixel: over a chord d a disc's cap is d² α / 8 deep. The
/// α-hull is then the convex hull to within that band outside its edges, and
/// is computed so: drawn in float32, discs that large (from about 1e5 pixels
/// across) err by more than their caps are deep.
fn bulge_below_resolution(sites: &[DVec2], alpha: f64, canvas: Canvas) -> bool {
    let (lo, hi) = bounds(sites);
    let chord = (hi - lo).length();
    let pixel = canvas.pixel(lo, hi);
    chord * chord * alpha / 8.0 < 1e-3 * pixel
}

fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points
        .iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        })
}

/// A frame around `[lo, hi]` padded by `pad` on every side, and by at least a
/// few percent so that the hull's rim shows and the box never collapses.
fn frame_around(lo: DVec2, hi: DVec2, pad: f64, side: u32) -> Result<Frame> {
    let extent = (hi - lo).max_element();
    // Relative to the set's extent, so that a set of any size and at any
    // offset fills the picture; one point gets a box relative to its
    // magnitude.
    let magnitude = lo.abs().max(hi.abs()).max_element();
    let pad = match extent > 0.0 {
        true => pad.max(0.03 * extent),
        false => pad.max(1e-9 * magnitude),
    }
    .max(f64::MIN_POSITIVE);
    Frame::fitting(side, lo - pad, hi + pad)
}

/// How an α-hull was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum HullMethod {
    /// α < 0: the envelope of the empty discs.
    Envelope,
    /// α > 0: circles through consecutive hull points.
    Hull,
    /// α > 0: intersections of discs, counted on the device.
    Pixels,
    /// α = 0: the convex hull.
    Convex,
}

impl std::fmt::Display for HullMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            HullMethod::Envelope => "envelope",
            HullMethod::Hull => "hull",
            HullMethod::Pixels => "pixels",
            HullMethod::Convex => "convex",
        })
    }
}

/// The answer's frame fields and counts from its pixels.
fn finish(
    alpha: f64,
    method: HullMethod,
    frame: Frame,
    pixels: Vec<u8>,
    discs: usize,
) -> AlphaHull {
    AlphaHull {
        alpha,
        radius: (alpha != 0.0).then(|| 1.0 / alpha.abs()),
        method,
        width: frame.width,
        height: frame.height,
        origin: frame.origin.to_array(),
        scale: frame.scale,
        inside: pixels.iter().filter(|&&c| c == class::INSIDE).count(),
        discs,
        boundary_sites: Vec::new(),
        border_band: 0.0,
        uncertain: 0,
        pixels,
        frame,
    }
}

/// α < 0 (§6.3).
fn negative(machine: &Machine, sites: &[DVec2], alpha: f64, canvas: Canvas) -> Result<AlphaHull> {
    let r = -1.0 / alpha;
    let (lo, hi) = bounds(sites);
    // The hull lies in the sites' box; reaching r beyond it puts the border band
    // outside the hull, unless that would shrink the box to a sliver.
    let extent = (hi - lo).max_element();
    let pad = if extent > 0.0 { r.min(extent) } else { r };
    let frame = canvas.around(lo, hi, pad)?;
    let (w, h) = (frame.width as usize, frame.height as usize);
    let r_px = r * frame.scale;

    // The envelope, and the rectangle at depth r marking the empty discs' centres.
    let options = VoronoiOptions {
        distances: false,
        ..VoronoiOptions::exact(frame)
    };
    let mut centre = crate::memory::filled(w * h, false, "disc centres")?;
    draw_point_tiles(machine, sites, &options, TileExtras::default(), |tile| {
        let key = tile.keys.scale * r_px * r_px;
        let (tw, th) = (tile.ids.width(), tile.ids.height());
        if key <= 1.0 {
            let at_least_r = RasterState {
                depth: DepthTest {
                    compare: Compare::LessOrEqual,
                    write: false,
                },
                ..RasterState::OVERWRITE
            };
            machine.run(|pass| {
                pass.begin(
                    Target {
                        color: Some(tile.ids),
                        depth_stencil: Some(tile.depth),
                    },
                    Clear::default(),
                )?;
                let rect = RectDraw::full_picture(tw, th)
                    .at_depth(key as f32)
                    .uint([CENTRE_ID; 4]);
                pass.draw_rect(&at_least_r, &DrawParams::default(), &rect)?;
                pass.end()
            })?;
        }
        let ids = machine.read_u32(tile.ids, tile.inner)?;
        let tw = tile.inner.width as usize;
        for (k, id) in ids.iter().enumerate() {
            let (i, j) = (tile.x0 as usize + k % tw, tile.y0 as usize + k / tw);
            centre[j * w + i] = *id == CENTRE_ID;
        }
        Ok(())
    })?;

    // The rim: centres with a 4-neighbour that is none (or beyond the border).
    let is_centre = |i: isize, j: isize| {
        i >= 0
            && j >= 0
            && (i as usize) < w
            && (j as usize) < h
            && centre[j as usize * w + i as usize]
    };
    let mut rim: Vec<[f32; 4]> = Vec::new();
    for j in 0..h as isize {
        for i in 0..w as isize {
            if is_centre(i, j)
                && !(is_centre(i - 1, j)
                    && is_centre(i + 1, j)
                    && is_centre(i, j - 1)
                    && is_centre(i, j + 1))
            {
                rim.push([i as f32, j as f32, r_px as f32, 1.0]);
            }
        }
    }
    let covered = draw_discs(machine, &frame, &rim, false)?;
    let pixels: Vec<u8> = (0..w * h)
        .map(|k| {
            if centre[k] {
                class::CENTRE
            } else if covered[k] > 0.0 {
                class::DISC
            } else {
                class::INSIDE
            }
        })
        .gather("pixels")?;
    let mut hull = finish(alpha, HullMethod::Envelope, frame, pixels, rim.len());
    hull.border_band = r;
    hull.uncertain = (0..w * h)
        .filter(|&k| {
            let (i, j) = ((k % w) as f64, (k / w) as f64);
            let border = i.min(j).min(w as f64 - 1.0 - i).min(h as f64 - 1.0 - j) + 0.5;
            hull.pixels[k] == class::INSIDE && border < r_px
        })
        .count();
    Ok(hull)
}

/// The id the rectangle of §6.3 writes over the empty discs' centres.
const CENTRE_ID: u32 = u32::MAX - 1;

/// α = 0: the convex hull, its triangles drawn as a fan.
fn convex(machine: &Machine, sites: &[DVec2], canvas: Canvas) -> Result<AlphaHull> {
    let (lo, hi) = bounds(sites);
    let frame = canvas.around(lo, hi, 0.0)?;
    let hull = convex_hull(sites);
    let corners: Vec<DVec2> = hull
        .iter()
        .map(|&i| frame.to_pixel(sites[i as usize]))
        .gather("corners")?;
    let mut triangles: Vec<[f32; 3]> = Vec::new();
    for k in 1..corners.len().saturating_sub(1) {
        for v in [corners[0], corners[k], corners[k + 1]] {
            triangles.push([v.x as f32, v.y as f32, 0.0]);
        }
    }
    let (w, h) = (frame.width, frame.height);
    let image = machine.image(Format::R32Uint, w, h)?;
    let count = triangles.len() as u32;
    // A vertex buffer may not be empty.
    triangles.push([0.0; 3]);
    let mesh = machine.vertex_buffer(&triangles)?;
    let ones = machine.vertex_buffer(&crate::memory::filled(
        triangles.len(),
        1u32,
        "triangle ids",
    )?)?;
    draw_on(machine, &image, ClearColor::Uint([0; 4]), |pass| {
        draw_cones(
            pass,
            &SITE_FAN,
            &RasterState::OVERWRITE,
            &DrawParams::default(),
            &picture_push(w, h),
            &ConeDraw {
                mesh: &mesh,
                first_vertex: 0,
                vertex_count: count,
                instances: &ones,
                first_instance: 0,
                instance_count: u32::from(count > 0),
            },
        )
    })?;
    let inside = machine.read_u32(&image, PixelRect::of(&image))?;
    let pixels = inside
        .iter()
        .map(|&v| {
            if v == 1 {
                class::INSIDE
            } else {
                class::OUTSIDE
            }
        })
        .gather("pixels")?;
    let mut answer = finish(0.0, HullMethod::Convex, frame, pixels, 0);
    answer.boundary_sites = hull;
    Ok(answer)
}

/// One rendering pass into `image` alone, cleared to `clear` first.
fn draw_on<'r>(
    machine: &Machine,
    image: &'r Image,
    clear: ClearColor,
    draw: impl FnOnce(&mut Pass<'_, 'r>) -> Result<()>,
) -> Result<()> {
    machine.run(|pass| {
        pass.begin(
            Target {
                color: Some(image),
                depth_stencil: None,
            },
            Clear {
                color: Some(clear),
                ..Clear::default()
            },
        )?;
        draw(pass)?;
        pass.end()
    })
}

/// Closed discs, one per instance of `[x, y, radius, value]` in pixels (the
/// value written to a float target).
static DISC: GraphicsProgram = GraphicsProgram::new(
    "Disc",
    shaders::DISC_VERT,
    Fragments::One(shaders::DISC_FRAG),
    Topology::TriangleStrip,
    &[VertexBuffer {
        stride: std::mem::size_of::<[f32; 4]>() as u32,
        per_instance: true,
        attributes: &[VertexAttribute {
            location: 0,
            offset: 0,
            format: VertexFormat::F32x4,
        }],
    }],
    std::mem::size_of::<ConePush>(),
);

fn picture_push(width: u32, height: u32) -> ConePush {
    ConePush {
        picture_size: [width as f32, height as f32],
        offset: [0.0; 2],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: 0.0,
        levels: 1,
        metric: (0, 2.0).into(),
    }
}

/// Draws `discs` (`[x, y, radius, value]`, pixels) on a cleared float picture of
/// `frame`, overwriting or (with `count`) adding their values, and reads it back.
fn draw_discs(
    machine: &Machine,
    frame: &Frame,
    discs: &[[f32; 4]],
    count: bool,
) -> Result<Vec<f32>> {
    let (w, h) = (frame.width, frame.height);
    let image = machine.image(Format::R32Float, w, h)?;
    let state = if count {
        RasterState::count_with_blending()
    } else {
        RasterState::OVERWRITE
    };
    // A vertex buffer may not be empty.
    let instances = if discs.is_empty() {
        Vec::from([[0.0f32; 4]])
    } else {
        discs.to_vec()
    };
    let buffer = machine.vertex_buffer(&instances)?;
    // Runs of discs covering about DISC_PIXELS_PER_RUN pixels each, so that a
    // cancel (which the machine looks at every run) stops large pictures soon.
    let mut runs = Vec::from([0u32]);
    let mut covered = 0.0;
    for (k, d) in discs.iter().enumerate() {
        covered += 4.0 * f64::from(d[2]).powi(2).min(f64::from(w) * f64::from(h));
        if covered > DISC_PIXELS_PER_RUN {
            runs.push(k as u32 + 1);
            covered = 0.0;
        }
    }
    // No discs: one run that only clears.
    let n = discs.len() as u32;
    if runs.len() == 1 || runs.last() != Some(&n) {
        runs.push(n);
    }
    for (k, run) in runs.windows(2).enumerate() {
        // The first run clears the picture; the others draw over it.
        let clear = Clear {
            color: (k == 0).then_some(ClearColor::Float([0.0; 4])),
            ..Clear::default()
        };
        machine.run(|pass| {
            let target = Target {
                color: Some(&image),
                depth_stencil: None,
            };
            pass.begin(target, clear)?;
            pass.draw(
                &state,
                &DrawParams::default(),
                &Draw {
                    program: &DISC,
                    variant: 0,
                    push: bytemuck::bytes_of(&picture_push(w, h)),
                    vertex_buffers: &[&buffer],
                    vertices: 0..4,
                    instances: run[0]..run[1],
                },
            )?;
            pass.end()
        })?;
    }
    machine.read_f32(&image, PixelRect::of(&image))
}

/// Pixels the discs of one run cover, about: few enough that a cancel stops
/// a large picture soon, many enough that runs cost little (`docs/tuning.md`).
const DISC_PIXELS_PER_RUN: f64 = (1u64 << 29) as f64;

/// The fewest pixels the pixel method's hull may span: its picture must hold
/// every disc centre, 1/α around the sites, which leaves the hull itself a
/// smaller part of the picture as 1/α grows.
const MIN_PIXEL_HULL: f64 = 4.0;

/// The centre of the circle of radius `radius` through `s` and `t` on the left
/// of the direction s → t, if the two are at most a diameter apart.
fn centre_left_of(s: DVec2, t: DVec2, radius: f64) -> Option<DVec2> {
    let half = 0.5 * (t - s);
    let h2 = radius * radius - half.length_squared();
    // A radius that is the smallest enclosing circle's may fall short of half the
    // diameter by rounding.
    if h2 < -1e-9 * radius * radius {
        return None;
    }
    let normal = half.perp().normalize_or_zero();
    Some(s + half + normal * h2.max(0.0).sqrt())
}

/// The circles of radius `radius` of the hull walk (§6.4.1): from a point on
/// the smallest enclosing circle, counter-clockwise, each circle through the
/// current point and the first later hull point whose circle holds every hull
/// point. Returns the points passed (in order) and the circles' centres.
fn hull_walk(
    points: &[DVec2],
    hull: &[u32],
    radius: f64,
    mec_centre: DVec2,
) -> (Vec<u32>, Vec<DVec2>) {
    // Measured from a hull point, so that circles of a set far from the
    // origin (1e9 away, say) keep the digits their radius needs.
    let o = points[hull[0] as usize];
    let p = |k: usize| points[hull[k % hull.len()] as usize] - o;
    let mec_centre = mec_centre - o;
    let n = hull.len();
    let start = (0..n)
        .max_by(|&a, &b| {
            p(a).distance(mec_centre)
                .total_cmp(&p(b).distance(mec_centre))
        })
        .expect("a hull point");
    let slack = 1e-9 * radius;
    let holds = |c: DVec2| (0..n).all(|k| p(k).distance(c) <= radius + slack);
    let (mut passed, mut centres) = (Vec::from([hull[start]]), Vec::new());
    let mut s = start;
    // Every step advances s, so the walk ends within one turn.
    while s < start + n {
        let next = (s + 1..=start + n).find_map(|t| {
            centre_left_of(p(s), p(t), radius)
                .filter(|&c| holds(c))
                .map(|c| (t, c))
        });
        let Some((t, c)) = next else { break };
        centres.push(c + o);
        if t < start + n {
            passed.push(hull[t % n]);
        }
        s = t;
    }
    (passed, centres)
}

/// The circles of an α-hull for α = 1/`radius` > 0 (§6.4.1): the smallest
/// enclosing circle, and the hull walk's circles of that radius through
/// consecutive boundary sites, whose intersection is the hull.
#[derive(Clone, Debug)]
pub struct HullCircles {
    pub mec_centre: DVec2,
    pub mec_radius: f64,
    /// The sites on the hull's boundary, counter-clockwise (one for a single
    /// distinct site, whose hull is that point).
    pub boundary: Vec<u32>,
    /// The circles' centres (world units), one per boundary arc.
    pub centres: Vec<DVec2>,
    /// The radius, at least the smallest enclosing circle's.
    pub radius: f64,
}

/// The α-hull's circles for α = 1/`radius` > 0; a radius below the smallest
/// enclosing circle's is an error.
pub fn hull_circles(sites: &[DVec2], radius: f64) -> Result<HullCircles> {
    circles_of(Checked::new(sites)?, radius)
}

/// [`hull_circles`] of sites checked where they entered.
fn circles_of(sites: Checked<'_>, radius: f64) -> Result<HullCircles> {
    let sites = sites.sites();
    let hull = convex_hull(sites);
    let corners: Vec<DVec2> = hull.iter().map(|&i| sites[i as usize]).gather("corners")?;
    let mec = welzl(&corners);
    if radius.is_nan() || radius < mec.radius * (1.0 - 1e-12) {
        return Err(Error::out_of_range(format!(
            "alpha {} gives radius {radius}, smaller than the smallest enclosing circle's \
             radius {}: no disc of that radius holds every site (use alpha <= {})",
            1.0 / radius,
            mec.radius,
            1.0 / mec.radius
        )));
    }
    let radius = radius.max(mec.radius);
    let (boundary, centres) = if hull.len() > 1 {
        hull_walk(sites, &hull, radius, mec.centre)
    } else {
        (hull.clone(), Vec::new())
    };
    if hull.len() > 1 && centres.is_empty() {
        return Err(Error::Internal(format!(
            "no circle of radius {radius} through two hull points holds the others"
        )));
    }
    Ok(HullCircles {
        mec_centre: mec.centre,
        mec_radius: mec.radius,
        boundary,
        centres,
        radius,
    })
}

/// α > 0 (§6.4).
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn positive(
    machine: &Machine,
    sites: &[DVec2],
    alpha: f64,
    method: AlphaMethod,
    canvas: Canvas,
) -> Result<AlphaHull> {
    let circles = circles_of(Checked::derived(sites), 1.0 / alpha)?;
    let radius = circles.radius;
    match method {
        AlphaMethod::Hull => {
            // The hull lies in the smallest enclosing circle (α-hulls grow with α).
            let reach = DVec2::splat(circles.mec_radius);
            let frame =
                canvas.around(circles.mec_centre - reach, circles.mec_centre + reach, 0.0)?;
            let r_px = radius * frame.scale;
            let centres: Vec<DVec2> = circles
                .centres
                .iter()
                .map(|c| frame.to_pixel(*c))
                .gather("centres")?;
            // Float32 places a far centre within a few of its ulps: discs that
            // much smaller mark what is surely inside, that much larger what
            // is surely outside, and the pixels between are decided in f64.
            let far = centres
                .iter()
                .fold(0.0, |m: f64, c| m.max(c.abs().max_element()));
            let slack = 8.0 * f32::EPSILON as f64 * (far + r_px) + 1e-3;
            let discs_of = |r: f64| -> Vec<[f32; 4]> {
                centres
                    .iter()
                    .map(|c| [c.x as f32, c.y as f32, r as f32, 1.0])
                    .collect()
            };
            let discs = discs_of(r_px);
            let pixels = if circles.centres.is_empty() {
                // One distinct site: the hull is that point.
                let at = frame.to_pixel(sites[circles.boundary[0] as usize]);
                (0..frame.len())
                    .map(|k| {
                        let q = DVec2::new(
                            (k % frame.width as usize) as f64,
                            (k / frame.width as usize) as f64,
                        );
                        if q == at {
                            class::INSIDE
                        } else {
                            class::OUTSIDE
                        }
                    })
                    .gather("hull classes")?
            } else {
                let inner = draw_discs(machine, &frame, &discs_of(r_px - slack), true)?;
                let outer = draw_discs(machine, &frame, &discs_of(r_px + slack), true)?;
                let k = discs.len() as f32;
                let w = frame.width as usize;
                let in_every_disc = |q: DVec2| {
                    centres
                        .iter()
                        .all(|c| q.distance_squared(*c) <= r_px * r_px)
                };
                inner
                    .par_iter()
                    .zip(&outer)
                    .enumerate()
                    .map(|(p, (&i, &o))| {
                        let q = DVec2::new((p % w) as f64, (p / w) as f64);
                        if i == k || (o == k && in_every_disc(q)) {
                            class::INSIDE
                        } else {
                            class::OUTSIDE
                        }
                    })
                    .collect()
            };
            let mut answer = finish(alpha, HullMethod::Hull, frame, pixels, discs.len());
            answer.boundary_sites = circles.boundary;
            Ok(answer)
        }
        AlphaMethod::Pixels => {
            if sites.len() >= 1 << 24 {
                return Err(Error::out_of_range(
                    "the pixel method counts sites in float32: at most 2^24 of them".into(),
                ));
            }
            // Every centre of a disc holding all sites lies within the radius of
            // the smallest enclosing circle's centre.
            let (lo, hi) = (
                circles.mec_centre - DVec2::splat(radius),
                circles.mec_centre + DVec2::splat(radius),
            );
            let frame = canvas.around(lo, hi, 0.0)?;
            let covered =
                frame.origin + DVec2::new(frame.width as f64, frame.height as f64) / frame.scale;
            if frame.origin.cmpgt(lo).any() || covered.cmplt(hi).any() {
                return Err(Error::out_of_range(format!(
                    "the pixel method draws every centre of a disc holding the sites, which \
                     lie in [{}, {}] x [{}, {}]; the picture covers [{}, {}] x [{}, {}]: use \
                     the hull method or a picture that holds them",
                    lo.x, hi.x, lo.y, hi.y, frame.origin.x, covered.x, frame.origin.y, covered.y
                )));
            }
            let side = frame.width.max(frame.height);
            let hull_px = 2.0 * circles.mec_radius * frame.scale;
            if hull_px < MIN_PIXEL_HULL {
                return Err(Error::out_of_range(format!(
                    "the pixel method's picture reaches 1/α = {radius:e} around the sites, \
                     so their hull spans {hull_px:.2} of its {side} pixels (at least \
                     {MIN_PIXEL_HULL} needed): use the hull method, a larger α or a larger size"
                )));
            }
            let r_px = (radius * frame.scale) as f32;
            let around_sites: Vec<[f32; 4]> = sites
                .iter()
                .map(|s| {
                    let c = frame.to_pixel(*s);
                    [c.x as f32, c.y as f32, r_px, 1.0]
                })
                .gather("discs")?;
            let counts = draw_discs(machine, &frame, &around_sites, true)?;
            let n = sites.len() as f32;
            let w = frame.width as usize;
            let mut rims: Vec<[f32; 4]> = Vec::new();
            for (j, row) in counts.chunks(w).enumerate() {
                let first = row.iter().position(|&c| c == n);
                let last = row.iter().rposition(|&c| c == n);
                if let (Some(a), Some(b)) = (first, last) {
                    rims.push([a as f32, j as f32, r_px, 1.0]);
                    if b != a {
                        rims.push([b as f32, j as f32, r_px, 1.0]);
                    }
                }
            }
            if rims.is_empty() {
                return Err(Error::out_of_range(format!(
                    "radius {radius} is so close to the smallest enclosing circle's ({}) that \
                     no pixel centre of a {}x{} picture can centre a disc holding every site: \
                     use the hull method or a larger picture",
                    circles.mec_radius, frame.width, frame.height
                )));
            }
            let hull_counts = draw_discs(machine, &frame, &rims, true)?;
            let k = rims.len() as f32;
            let pixels = hull_counts
                .iter()
                .zip(&counts)
                .map(|(&c, &centre)| {
                    if c == k {
                        class::INSIDE
                    } else if centre == n {
                        class::CENTRE
                    } else {
                        class::OUTSIDE
                    }
                })
                .gather("values")?;
            Ok(finish(
                alpha,
                HullMethod::Pixels,
                frame,
                pixels,
                around_sites.len() + rims.len(),
            ))
        }
    }
}
