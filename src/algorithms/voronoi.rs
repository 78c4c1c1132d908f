//! The Voronoi diagram of point sites as the lower envelope of cones (thesis
//! §3.2–3.5): one cone per site, drawn with the depth test LESS, paints every pixel
//! with its nearest site.
//!
//! Two accuracy modes: [`Accuracy::Fan`] draws the thesis's triangle fans (a
//! distance diagram within ε; labels may deviate near bisectors as §3.4 analyses),
//! [`Accuracy::Exact`] writes the exact squared distance per fragment, so every
//! label is a nearest site. Three ways to size the cones: [`Speedup::None`]
//! (picture-wide cones, Hoff et al.), [`Speedup::Quadtree`] (the thesis's width
//! bounds with minmax-detected retries) and [`Speedup::Local`] (a radius per site).
//! With local radii, exact diagrams draw no cones at all: each fragment of one
//! picture-wide triangle takes the nearest of the sites listed for its screen
//! tile ([`NEAREST_TILES`]), the sites that can own one of its pixels.
//!
//! Pictures larger than one device image (or than [`VoronoiOptions::max_tile`])
//! are rendered tile by tile, each tile drawing only the cones that reach it, and
//! delivered as bands of rows ([`voronoi_bands`]) so that no more than a band is
//! ever held in memory.
//!
//! The file is long: besides the point diagram it holds the cone machinery the
//! other envelopes import (footprint sizing, batching, Hilbert order, screen tiles
//! and the records image), which is to become an envelope module of its own.

use std::{f64::consts::TAU, time::Instant};

use glam::DVec2;
use rayon::prelude::*;
use serde::Serialize;

use crate::{
    error::{Error, Result},
    geometry::{
        chain,
        cone::{
            check_fan_size, fan_distance_error, unit_fan, unit_footprint, FanShape,
            MAX_FAN_TRIANGLES, MIN_FAN_EPSILON,
        },
        frame::{check_sites, distance2_to_rect, distinct_by, farthest2_in_rect},
        metric::{DepthKey, Metric},
        radius::{self, TileCandidates},
        Frame,
    },
    machine::{
        ChannelMask, Clear, ClearColor, Compare, DepthTest, DrawParams, Format, Image, Machine,
        Pass, PixelRect, RasterState, StencilOp, StencilTest, Target,
    },
};

use super::envelope::{
    hilbert_index, records_image, DepthMap, DrawnTile, Tiling, BATCH, SCREEN_TILE_SIDE, UNIT_SQUARE,
};

use super::cones::{
    draw_cones, draw_over_target, ConeBatch, ConeDraw, ConeInstance, ConePush, CONE_EXACT,
    CONE_EXACT_BATCH, CONE_FAN, NEAREST_TILES,
};

/// The farthest (pixels) an exact cone may reach: float32 positions and
/// distances there are good to about a sixtieth of a pixel, and farther out
/// two sites' distances could tie or swap by more.
pub const MAX_EXACT_REACH: f64 = (1u32 << 18) as f64;

/// How cones are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Accuracy {
    /// Triangle fans. With `triangles: None` each cone gets the fewest triangles for
    /// an ε distance diagram at its own radius; `Some(T)` fixes T for every cone.
    Fan {
        epsilon: f64,
        triangles: Option<u32>,
    },
    /// The exact distance per fragment.
    Exact,
}

impl Accuracy {
    /// Fans for a distance diagram within one pixel.
    pub const FAN: Self = Self::Fan {
        epsilon: 1.0,
        triangles: None,
    };

    /// A clear error for a fan without a finite ε of at least
    /// [`MIN_FAN_EPSILON`] pixels, or with fewer than 3 or more than
    /// [`MAX_FAN_TRIANGLES`] triangles.
    pub fn check(self) -> Result<()> {
        if let Self::Fan { epsilon, triangles } = self {
            if !(epsilon >= MIN_FAN_EPSILON && epsilon.is_finite()) {
                return Err(Error::InvalidInput(format!(
                    "fan epsilon {epsilon:?} must be a finite distance of at least {MIN_FAN_EPSILON} \
                     pixels (the rasterizer's subpixel grid is 1/256 pixel)"
                )));
            }
            if triangles.is_some_and(|t| !(3..=MAX_FAN_TRIANGLES).contains(&t)) {
                return Err(Error::InvalidInput(format!(
                    "a fan has 3 to {MAX_FAN_TRIANGLES} triangles"
                )));
            }
        }
        Ok(())
    }
}

/// How far cones reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Speedup {
    /// Every cone covers the whole picture.
    None,
    /// One radius for all cones from the quadtree (thesis §3.5); uncovered pixels
    /// are found with minmax and the cones redrawn larger.
    Quadtree,
    /// A radius per site from the sites around it.
    Local,
}

/// What to compute. Start from [`VoronoiOptions::exact`] (or `default()`, a
/// 1024 x 1024 picture) and change what differs, by field or by setter:
/// `VoronoiOptions::exact(frame).metric(Metric::L1).ties(true)`. New fields
/// may be added, so the struct is not built by a literal outside pixgeo.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct VoronoiOptions {
    pub frame: Frame,
    /// The distance function (thesis §3.6); metrics other than L2 need exact mode.
    pub metric: Metric,
    pub accuracy: Accuracy,
    pub speedup: Speedup,
    /// Whether to read back the distance map (the z buffer) as well as the labels.
    pub distances: bool,
    /// Whether to count, per pixel, the sites at the smallest distance (thesis
    /// §3.6.4: L1 and L∞ have whole areas of equidistant points). Exact mode only.
    pub ties: bool,
    /// Largest tile side in pixels; `None` = as large as the device allows.
    pub max_tile: Option<u32>,
    /// Only this rectangle of the frame's pixels: the diagram's pixels there,
    /// bit for bit, ties included, drawn from the cones that reach it, so that
    /// windows computed apart (on other machines) tile into the whole diagram.
    /// Exact mode only. `None`: the whole frame.
    pub window: Option<PixelRect>,
}

impl VoronoiOptions {
    /// Exact labels with per-site radii on `frame`, distances included.
    pub fn exact(frame: Frame) -> Self {
        Self {
            frame,
            metric: Metric::L2,
            accuracy: Accuracy::Exact,
            speedup: Speedup::Local,
            distances: true,
            ties: false,
            max_tile: None,
            window: None,
        }
    }

    pub fn frame(self, frame: Frame) -> Self {
        Self { frame, ..self }
    }

    pub fn metric(self, metric: Metric) -> Self {
        Self { metric, ..self }
    }

    pub fn accuracy(self, accuracy: Accuracy) -> Self {
        Self { accuracy, ..self }
    }

    pub fn speedup(self, speedup: Speedup) -> Self {
        Self { speedup, ..self }
    }

    pub fn distances(self, distances: bool) -> Self {
        Self { distances, ..self }
    }

    pub fn ties(self, ties: bool) -> Self {
        Self { ties, ..self }
    }

    pub fn max_tile(self, max_tile: Option<u32>) -> Self {
        Self { max_tile, ..self }
    }

    pub fn window(self, window: Option<PixelRect>) -> Self {
        Self { window, ..self }
    }

    /// The window's pixels in the frame: the whole frame without one; an error
    /// for a window that is empty or leaves the frame.
    pub fn window_rect(&self) -> Result<PixelRect> {
        let f = self.frame;
        let Some(w) = self.window else {
            return Ok(PixelRect::sized(f.width, f.height));
        };
        if self.accuracy != Accuracy::Exact {
            return Err(Error::InvalidInput(
                "a window takes exact mode: a fan's interpolated depths round by where its \
                 tile lies, so fan windows would not match the whole diagram bit for bit"
                    .into(),
            ));
        }
        let inside = |at: u32, len: u32, side: u32| at.checked_add(len).is_some_and(|e| e <= side);
        if w.width == 0
            || w.height == 0
            || !inside(w.x, w.width, f.width)
            || !inside(w.y, w.height, f.height)
        {
            return Err(Error::InvalidInput(format!(
                "window {},{},{},{} (x0,y0,width,height) must be a nonempty rectangle inside the \
                 {}x{} picture",
                w.x, w.y, w.width, w.height, f.width, f.height
            )));
        }
        Ok(w)
    }
}

impl Default for VoronoiOptions {
    /// Exact labels and distances on 1024 x 1024 pixels, pixel (i, j) centred
    /// at world (i, j).
    fn default() -> Self {
        Self::exact(Frame::pixels(1024, 1024).expect("a valid picture"))
    }
}

/// How many cones were drawn with one kind of footprint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct ConeGroup {
    /// `tiles` (exact cones found per screen tile, not drawn), `batch` (exact
    /// cones drawn eight to a rectangle), `polygon` (an exact cone's own
    /// footprint), `ball`, `fan` or `chain`.
    pub kind: &'static str,
    /// The side of a screen tile in pixels, cones to a batch, corners of a
    /// polygon or ball, triangles of a fan or chain.
    pub size: u32,
    pub cones: usize,
}

/// How the diagram was made.
#[derive(Clone, Debug, Default, Serialize)]
pub struct VoronoiStats {
    pub device: String,
    pub sites: usize,
    /// Cones drawn (sites whose cone reaches the picture).
    pub cones: usize,
    /// Footprints of the cones.
    pub groups: Vec<ConeGroup>,
    /// Tiles the picture was cut into.
    pub tiles: usize,
    /// Rendering passes, over all tiles (more than one per tile when the quadtree's
    /// first radius was short).
    pub passes: u32,
    /// Cone radii (pixels) of the final pass: smallest, mean, largest.
    pub radius_min: f64,
    pub radius_mean: f64,
    pub radius_max: f64,
    /// Guaranteed bound on the distance overestimate (world units), apart from the
    /// rasterizer's subpixel snapping of fan vertices; 0 in exact mode.
    pub distance_error_bound: f64,
    /// Radii the quadtree retry loop tried, in order.
    pub radii_tried: Vec<f64>,
    /// Milliseconds: cone sizing on the CPU, rendering (all passes, with coverage
    /// checks), reading the result back.
    pub bounds_ms: f64,
    pub render_ms: f64,
    pub readback_ms: f64,
}

/// A Voronoi diagram on a picture.
#[derive(Clone, Debug)]
pub struct VoronoiDiagram {
    /// The arrays' size: the window's, or the whole picture's.
    pub width: u32,
    pub height: u32,
    /// The whole picture: [`Frame::to_world`] maps its pixels to world points.
    pub frame: Frame,
    /// The pixels of `frame` the arrays hold: array pixel (i, j) is the frame's
    /// pixel (window.x + i, window.y + j).
    pub window: PixelRect,
    /// Nearest site per pixel, row-major (`[j][i]`); `u32::MAX` where no site is.
    pub labels: Vec<u32>,
    /// Distance to that site in world units, row-major; empty unless
    /// [`VoronoiOptions::distances`].
    pub distances: Vec<f32>,
    /// Number of sites at the smallest distance per pixel (255 at most), row-major;
    /// empty unless [`VoronoiOptions::ties`].
    pub ties: Vec<u32>,
    pub stats: VoronoiStats,
}

/// Rows `y0 .. y0 + height` of the diagram, full width, row-major.
#[derive(Clone, Debug)]
pub struct Band {
    pub y0: u32,
    pub height: u32,
    pub labels: Vec<u32>,
    /// Empty unless [`VoronoiOptions::distances`].
    pub distances: Vec<f32>,
    /// Empty unless [`VoronoiOptions::ties`].
    pub ties: Vec<u32>,
}

/// One cone to draw, in pixel coordinates.
#[derive(Clone, Copy, Debug)]
struct Cone {
    site: DVec2,
    id: u32,
    /// Every owned pixel centre lies within this (Euclidean) distance; fragments
    /// beyond it are discarded.
    radius: f64,
    /// And within this distance in the diagram's metric (the radius for L2): the
    /// metric ball a footprint must cover.
    reach: f64,
    /// And inside this box, which batches draw (at most the radius's square).
    lo: DVec2,
    hi: DVec2,
}

impl Cone {
    /// The box cut to the square of side 2 reach around the site, which holds
    /// the metric's ball of that radius when the metric grows with each
    /// coordinate (all but polygon gauges).
    fn clip(&self) -> (DVec2, DVec2) {
        (
            self.lo.max(self.site - self.reach),
            self.hi.min(self.site + self.reach),
        )
    }
}

/// How a cone is drawn; the order is the draw order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Footprint {
    /// One of up to [`BATCH`] nearby exact cones drawn as one rectangle.
    Batch,
    /// A regular polygon with this many corners (exact cones; the square also
    /// around L∞ and L_p balls for p >= 2).
    Polygon(u32),
    /// A polygon around another metric's ball (exact cones): the metric's circle
    /// sampled at [`BALL_CORNERS`] equal angles (`chain::MetricFan::Uniform`).
    Ball,
    /// A triangle fan of this many triangles (for other metrics: over the metric's
    /// circle sampled at equal angles).
    Fan(u32),
    /// A fan over the thesis's polygonal chain of another metric's circle
    /// (§3.6.1–3.6.2), built for the radius of this [`chain::chain_level`].
    Chain(i32),
}

/// A cone with its footprint, ready to draw.
#[derive(Clone, Copy, Debug)]
struct Shaped {
    cone: Cone,
    footprint: Footprint,
    /// Radius of the footprint's corners.
    outer_radius: f64,
}

/// Corners of an exact cone's footprint around another metric's ball (L1 and
/// L_p for p < 2): eight hug every L_p ball within 6% of its area for p in
/// [0.5, 3] and within 50% for p = 0.3, where the regular polygon around the
/// Euclidean disc that holds the ball takes up to 5 times the ball's area for
/// p = 0.5 (0.67 r²), 26 times for p = 0.3.
const BALL_CORNERS: u32 = 8;

/// Largest radius of a batched cone. A batch's rectangle is the bounding box of
/// its cones, so one long cone would widen it for all eight; longer cones get a
/// polygon of their own.
const BATCH_RADIUS_LIMIT: f64 = 48.0;

/// A triangle's cost in fragments: lavapipe sets up and bins each one (a few
/// tenths of a microsecond for a small one), which outweighs many fragments.
const TRIANGLE_FRAGMENTS: f64 = 400.0;

/// The same for L_p whose keys cost powers (see `DepthKey`): a batch evaluates eight per
/// fragment, a cone of its own one, so only small cones batch (docs/tuning.md,
/// "Measured choices").
const BATCH_RADIUS_LIMIT_LP: f64 = 12.0;

/// Computes the Voronoi diagram of `sites` (world coordinates).
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::voronoi::{voronoi, VoronoiOptions}, geometry::{metric::Metric, Frame}};
///
/// let sites = [DVec2::new(2.0, 2.0), DVec2::new(6.0, 2.0)];
/// let options = VoronoiOptions::exact(Frame::pixels(9, 5)?).metric(Metric::L1).ties(true);
/// let d = pixgeo::with_default_machine(|m| voronoi(m, &sites, &options))?;
/// assert_eq!(d.ties[2 * 9 + 4], 2); // pixel (4, 2) is as near to both
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    let window = options.window_rect()?;
    let mut labels = Vec::new();
    let mut distances = Vec::new();
    let mut ties = Vec::new();
    let stats = voronoi_bands(machine, sites, options, |band| {
        // A picture of one band is handed over without a copy.
        if labels.is_empty() {
            labels = band.labels;
            distances = band.distances;
            ties = band.ties;
        } else {
            labels.extend_from_slice(&band.labels);
            distances.extend_from_slice(&band.distances);
            ties.extend_from_slice(&band.ties);
        }
        Ok(())
    })?;
    Ok(VoronoiDiagram {
        width: window.width,
        height: window.height,
        frame: options.frame,
        window,
        labels,
        distances,
        ties,
        stats,
    })
}

/// Computes the Voronoi diagram of `sites` (world coordinates) and hands it to
/// `sink` as bands of rows, top to bottom. A band is one row of tiles; tiles are as
/// large as the device (or [`VoronoiOptions::max_tile`]) allows, so only one band
/// is held at a time. The result does not depend on the tiling: every tile draws the
/// cones that reach it in the same order, so even ties resolve alike.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::voronoi::{voronoi_bands, VoronoiOptions}, geometry::Frame};
///
/// let sites = [DVec2::new(100.0, 50.0), DVec2::new(900.0, 700.0)];
/// let options = VoronoiOptions::exact(Frame::pixels(1000, 800)?).max_tile(Some(256));
/// let mut rows = 0;
/// pixgeo::with_default_machine(|m| {
///     voronoi_bands(m, &sites, &options, |band| {
///         rows += band.height; // write band.labels to a file here
///         Ok(())
///     })
/// })?;
/// assert_eq!(rows, 800);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi_bands(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
    mut sink: impl FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    // Equal sites stand the same cone, and the first of them (the smallest id)
    // wins every pixel any of them would: the others are dropped up front, so
    // repeats cost nothing. Counting ties counts them, so it keeps them all.
    if !options.ties {
        check_sites(sites)?;
        let (mut kept, repeats) = distinct_by(sites, 0..sites.len() as u32, |_| ());
        if !repeats.is_empty() {
            kept.sort_unstable();
            let distinct: Vec<DVec2> = kept.iter().map(|&i| sites[i as usize]).collect();
            let mut stats = distinct_bands(machine, &distinct, options, &mut |mut band| {
                for label in band.labels.iter_mut().filter(|l| **l != u32::MAX) {
                    *label = kept[*label as usize];
                }
                sink(band)
            })?;
            stats.sites = sites.len();
            return Ok(stats);
        }
    }
    distinct_bands(machine, sites, options, &mut sink)
}

/// [`voronoi_bands`] of sites that are distinct, or whose ties are counted.
fn distinct_bands(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
    sink: &mut dyn FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    let window = options.window_rect()?;
    let mut band: Option<Band> = None;
    let stats = draw_point_tiles(machine, sites, options, false, true, |tile| {
        if tile.x0 == window.x {
            if let Some(done) = band.take() {
                sink(done)?;
            }
            let pixels = tile.inner.height as usize * window.width as usize;
            band = Some(Band {
                y0: tile.y0,
                height: tile.inner.height,
                labels: vec![0; pixels],
                distances: if options.distances {
                    vec![0.0; pixels]
                } else {
                    Vec::new()
                },
                ties: if options.ties {
                    vec![0; pixels]
                } else {
                    Vec::new()
                },
            });
        }
        let band = band
            .as_mut()
            .expect("a band begins at the window's left edge");
        read_tile(machine, tile, &window, options, band)
    })?;
    if let Some(done) = band {
        sink(done)?;
    }
    Ok(stats)
}

/// Draws the Voronoi diagram of points tile by tile, handing each tile to
/// `visit` while it is on the device (tiles of a row of tiles left to right, rows
/// top to bottom). `stencil` asks for a stencil in the depth image.
pub(crate) fn draw_point_tiles(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
    stencil: bool,
    power_keys: bool,
    mut visit: impl FnMut(&DrawnTile<'_>) -> Result<()>,
) -> Result<VoronoiStats> {
    check_sites(sites)?;
    options.frame.check()?;
    if options.ties && matches!(options.metric, Metric::Polygon(_)) {
        return Err(Error::InvalidInput(
            "equal distances are counted for the L_p metrics; polygonal distances are drawn as fans".into(),
        ));
    }
    let options = &VoronoiOptions {
        accuracy: drawn_accuracy(options.metric, options.accuracy),
        ..*options
    };
    if options.ties && options.accuracy != Accuracy::Exact {
        return Err(Error::InvalidInput(
            "equal distances are counted in exact mode only".into(),
        ));
    }
    options.accuracy.check()?;
    let frame = options.frame;
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites: sites.len(),
        ..Default::default()
    };

    let started = Instant::now();
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    // Exact cones are found per screen tile where their boxes are tight (local
    // radii) and ties need not count each cone's own fragments; their squares
    // cut to the boxes are drawn where the tiles' lists would be too long.
    let tiled =
        options.accuracy == Accuracy::Exact && options.speedup == Speedup::Local && !options.ties;
    // L_p and L∞ tiles find their candidates directly, in fewer measurements
    // than the regions' boxes take (L∞'s boxes hold diamonds) and with shorter
    // lists; the regions' reaches come with them. L1's boxes from Delaunay
    // neighbours cost less.
    let candidates = match options.metric {
        Metric::Lp(_) | Metric::LInf if tiled => {
            radius::tile_candidates(&pixels, &frame, SCREEN_TILE_SIDE, options.metric)
        }
        _ => None,
    };
    let attempts = match &candidates {
        Some(c) => vec![(
            None,
            reach_cones(&pixels, &frame, options.metric, &c.reaches),
        )],
        None => cone_attempts(&pixels, &frame, options.speedup, options.metric),
    };
    // Exact cones discard fragments beyond their radius.
    let exact_reach = attempts
        .iter()
        .flat_map(|(_, cones)| cones)
        .map(|c| c.radius)
        .fold(1.0, f64::max)
        * 1.001;
    if options.accuracy == Accuracy::Exact && exact_reach > MAX_EXACT_REACH {
        return Err(Error::InvalidInput(format!(
            "sites lie up to {exact_reach:.3e} pixels from pixels they own: the device's \
             float32 resolves distances there to {:.2e} pixels, not exactly (up to {MAX_EXACT_REACH} \
             pixels it resolves a sixtieth); use the CPU algorithm (--device cpu), exact in f64",
            exact_reach * f32::EPSILON as f64
        )));
    }
    if let Accuracy::Fan {
        epsilon,
        triangles: None,
    } = options.accuracy
    {
        check_fan_size(exact_reach, epsilon)?;
    }
    let key = match (power_keys, options.accuracy) {
        (true, Accuracy::Exact) => DepthKey::for_cones(options.metric, exact_reach),
        _ => DepthKey::Metric(options.metric),
    };
    let shaped: Vec<Vec<Shaped>> = attempts
        .iter()
        .map(|(_, cones)| {
            if tiled {
                cones
                    .iter()
                    .map(|cone| Shaped {
                        cone: *cone,
                        footprint: Footprint::Polygon(4),
                        outer_radius: cone.reach * std::f64::consts::SQRT_2,
                    })
                    .collect()
            } else {
                shape_cones(
                    cones,
                    &frame,
                    options.accuracy,
                    options.metric,
                    key,
                    !options.ties,
                )
            }
        })
        .collect();
    // A cone sized by the quadtree may reach past every pixel a site owns.
    if let Some(t) = shaped.iter().flatten().find_map(|s| match s.footprint {
        Footprint::Fan(t) if t > MAX_FAN_TRIANGLES => Some(t),
        _ => None,
    }) {
        return Err(Error::InvalidInput(format!(
            "a fan cone would need {t} triangles, more than {MAX_FAN_TRIANGLES}: \
             give a larger epsilon, or use exact mode"
        )));
    }
    let batches: Vec<Vec<ConeBatch>> = shaped.iter().map(|s| batches_of(s)).collect();
    // One depth scale for every tile and attempt, the largest cone's: fan
    // heights reach the outer radius at the rim.
    let reach = match options.accuracy {
        Accuracy::Exact => exact_reach,
        Accuracy::Fan { .. } => {
            shaped
                .iter()
                .flatten()
                .map(|s| s.outer_radius)
                .fold(1.0, f64::max)
                * 1.001
        }
    };
    let scale = depth_scale(reach, options.accuracy, key);
    stats.bounds_ms = ms(started);

    let meshes = chain::FanMeshes::new(options.metric);
    // A band of rows is held on the host: keep it to about 2^26 pixels, in
    // whole screen tiles.
    let band_rows =
        ((1u64 << 26) / frame.width as u64) as u32 / SCREEN_TILE_SIDE * SCREEN_TILE_SIDE;
    let window = options.window_rect()?;
    let tiling = Tiling::new(machine, options.max_tile, window, band_rows)?;
    let (tile_w, tile_h) = (tiling.tile_w, tiling.tile_h);
    let picture = Picture {
        ids: machine.image(Format::R32Uint, tile_w, tile_h)?,
        depth: machine.image(
            if options.ties || stencil {
                Format::DepthStencil
            } else {
                Format::Depth
            },
            tile_w,
            tile_h,
        )?,
    };

    let exact = options.accuracy == Accuracy::Exact;
    let keys = DepthMap {
        key: exact.then_some(key),
        scale: if exact { scale.fragment } else { scale.vertex },
        pixels_per_unit: frame.scale,
        offset: 0.0,
    };
    // Tile candidates are the picture's: the tiles of a view must be among them.
    let aligned = |tile: u32, whole: u32| tile >= whole || tile % SCREEN_TILE_SIDE == 0;
    let aligned = aligned(tile_w, window.width)
        && aligned(tile_h, window.height)
        && window.x % SCREEN_TILE_SIDE == 0
        && window.y % SCREEN_TILE_SIDE == 0;
    let mut final_attempt = 0;
    let mut drawn_by_tiles = tiled;
    for (x0, y0, inner) in tiling.tiles() {
        let view = TileView {
            origin: DVec2::new(x0 as f64, y0 as f64),
            width: tile_w,
            height: tile_h,
        };
        stats.tiles += 1;
        let started = Instant::now();
        for (k, (cones, batches)) in shaped.iter().zip(&batches).enumerate() {
            stats.passes += 1;
            let draws = Draws {
                cones,
                batches,
                accuracy: options.accuracy,
                metric: options.metric,
                key,
                meshes: &meshes,
                scale,
                ties: options.ties,
                tiled,
                candidates: candidates.as_ref().filter(|_| aligned),
                sites: &pixels,
            };
            drawn_by_tiles &= render(machine, &picture, &view, &draws)?;
            final_attempt = final_attempt.max(k);
            // Picture-wide and local radii cover every pixel by construction; the
            // quadtree's radius is checked with minmax, the thesis's way: a pixel
            // no truncated cone reached keeps the "no site" id, the largest value.
            let covered = options.speedup != Speedup::Quadtree
                || machine.minmax(&picture.ids, inner)?.max[0] < u32::MAX as f64;
            if covered {
                break;
            }
            if k + 1 == shaped.len() {
                return Err(Error::InvalidInput(
                        "cones left pixels uncovered; this is a pixgeo bug, please report it with the sites".into(),
                    ));
            }
        }
        stats.render_ms += ms(started);
        let started = Instant::now();
        visit(&DrawnTile {
            ids: &picture.ids,
            depth: &picture.depth,
            x0,
            y0,
            inner,
            keys,
        })?;
        stats.readback_ms += ms(started);
    }

    let last = &shaped[final_attempt];
    stats.radii_tried = attempts[..=final_attempt]
        .iter()
        .filter_map(|(r, _)| *r)
        .collect();
    stats.cones = last.len();
    stats.groups = if drawn_by_tiles {
        vec![ConeGroup {
            kind: "tiles",
            size: SCREEN_TILE_SIDE,
            cones: last.len(),
        }]
    } else {
        groups_of(last)
            .into_iter()
            .map(|g| ConeGroup {
                kind: match g.footprint {
                    Footprint::Batch => "batch",
                    Footprint::Polygon(_) => "polygon",
                    Footprint::Ball => "ball",
                    Footprint::Fan(_) => "fan",
                    Footprint::Chain(_) => "chain",
                },
                size: match g.footprint {
                    Footprint::Batch => BATCH as u32,
                    Footprint::Polygon(k) | Footprint::Fan(k) => k,
                    Footprint::Ball => BALL_CORNERS,
                    Footprint::Chain(level) => {
                        meshes
                            .unit_mesh(metric_fan(options.accuracy), chain::level_radius(level))
                            .len() as u32
                            - 2
                    }
                },
                cones: g.count as usize,
            })
            .collect()
    };
    if !last.is_empty() {
        let radii = last.iter().map(|s| s.cone.radius);
        stats.radius_min = radii.clone().fold(f64::INFINITY, f64::min);
        stats.radius_max = radii.clone().fold(0.0, f64::max);
        stats.radius_mean = radii.sum::<f64>() / last.len() as f64;
    }
    stats.distance_error_bound = match options.accuracy {
        Accuracy::Exact => 0.0,
        Accuracy::Fan {
            epsilon,
            triangles: None,
        } if options.metric == Metric::L2 => epsilon / frame.scale,
        Accuracy::Fan {
            triangles: Some(t), ..
        } if options.metric == Metric::L2 => fan_distance_error(stats.radius_max, t) / frame.scale,
        Accuracy::Fan { .. } => {
            metric_fan(options.accuracy).error_bound(options.metric, stats.radius_max) / frame.scale
        }
    };
    Ok(stats)
}

/// The accuracy a diagram is drawn with: a polygon's distance is piecewise
/// linear, so the fan over the polygon itself is exact, and is what exact mode
/// draws; every other metric as asked.
pub(crate) fn drawn_accuracy(metric: Metric, accuracy: Accuracy) -> Accuracy {
    match (metric, accuracy) {
        (Metric::Polygon(_), Accuracy::Exact) => Accuracy::FAN,
        _ => accuracy,
    }
}

/// How fans of metrics other than L2 are built for `accuracy` (a fan mode).
pub(crate) fn metric_fan(accuracy: Accuracy) -> chain::MetricFan {
    match accuracy {
        Accuracy::Fan {
            triangles: Some(corners),
            ..
        } => chain::MetricFan::Uniform { corners },
        Accuracy::Fan { epsilon, .. } => chain::MetricFan::Chain { epsilon },
        Accuracy::Exact => unreachable!("exact cones have no fan"),
    }
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Cones of the `reaches` (in the metric) of tile candidates, half a
/// Euclidean pixel wider as other local radii are, each in the square of its
/// reach.
fn reach_cones(pixels: &[DVec2], frame: &Frame, metric: Metric, reaches: &[f64]) -> Vec<Cone> {
    let (a, b) = metric.euclidean_bounds();
    pixels
        .iter()
        .zip(reaches)
        .enumerate()
        .map(|(i, (p, r))| {
            let reach = r + 0.5 * b;
            Cone {
                site: *p,
                id: i as u32,
                radius: (reach / a).min(frame.farthest_pixel(*p) + 0.5),
                reach,
                lo: p - reach,
                hi: p + reach,
            }
        })
        .filter(|c| frame.distance_to_pixels(c.site) <= c.radius)
        .collect()
}

/// The cones of each pass to try, with the quadtree radius a pass uses (if any).
fn cone_attempts(
    pixels: &[DVec2],
    frame: &Frame,
    speedup: Speedup,
    metric: Metric,
) -> Vec<(Option<f64>, Vec<Cone>)> {
    // The radius that reaches every pixel from a site, plus half a pixel so that
    // rasterization rules at a footprint's rim never drop a pixel centre.
    let picture_wide: Vec<f64> = pixels
        .iter()
        .map(|p| frame.farthest_pixel(*p) + 0.5)
        .collect();
    let b = metric.euclidean_bounds().1;
    let cones_with = |radius: &dyn Fn(usize) -> f64| -> Vec<Cone> {
        pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let r = radius(i);
                Cone {
                    site: *p,
                    id: i as u32,
                    radius: r,
                    reach: b * r,
                    lo: p - r,
                    hi: p + r,
                }
            })
            .filter(|c| c.radius > 0.0 && frame.distance_to_pixels(c.site) <= c.radius)
            .collect()
    };
    match speedup {
        Speedup::None => vec![(None, cones_with(&|i| picture_wide[i]))],
        Speedup::Local if metric != Metric::L2 => {
            // L1 and L∞ regions lie in boxes from their neighbours, clipped to the
            // picture's pixel centres.
            let boxes = radius::region_boxes(pixels, frame, metric)
                .unwrap_or_else(|| vec![None; pixels.len()]);
            let (first, last) = frame.pixel_centres();
            let clipped: Vec<Option<(DVec2, DVec2)>> = boxes
                .iter()
                .map(|b| b.map(|(lo, hi)| (lo.clamp(first, last), hi.clamp(first, last))))
                .collect();
            // The other metrics, the sites left without a box, and L∞'s boxes
            // (which hold diamonds) are bounded by the cover measured in the
            // metric (radius::local_metric_radii), half a Euclidean pixel wider
            // as for L2 (b / 2 in the metric); polygon gauges by the Euclidean
            // cover, stretched. Each is (Euclidean radius, reach in the metric).
            let covered = metric != Metric::L1 || boxes.iter().any(Option::is_none);
            let a = metric.euclidean_bounds().0;
            // Each with the box of the cover's cells the site may own a pixel of.
            let everywhere = (DVec2::NEG_INFINITY, DVec2::INFINITY);
            let cover: Vec<(f64, f64, (DVec2, DVec2))> = if !covered {
                vec![(f64::INFINITY, f64::INFINITY, everywhere); pixels.len()]
            } else if let Some(regions) = radius::local_metric_regions(pixels, frame, metric) {
                regions
                    .into_iter()
                    .map(|r| ((r.reach + 0.5 * b) / a, r.reach + 0.5 * b, (r.lo, r.hi)))
                    .collect()
            } else {
                let (cell, bin) = radius::k_cell_and_bin(frame, pixels.len(), 1);
                radius::k_local_radii(pixels, frame, 1, cell, bin, metric.stretch())
                    .into_iter()
                    .map(|r| (r + 0.5, b * (r + 0.5), everywhere))
                    .collect()
            };
            let mut cones = cones_with(&|i| {
                let corner = clipped[i].map_or(f64::INFINITY, |(lo, hi)| {
                    farthest2_in_rect(pixels[i], lo, hi).sqrt() + 0.5
                });
                cover[i].0.min(corner).min(picture_wide[i])
            });
            // A metric that grows with each coordinate and is 1 on the axes keeps
            // each coordinate's offset within the reach.
            let axes_bounded = !matches!(metric, Metric::Polygon(_));
            for cone in &mut cones {
                let i = cone.id as usize;
                let (_, reach, (lo, hi)) = cover[i];
                cone.reach = cone.reach.min(reach);
                if axes_bounded {
                    cone.lo = cone.lo.max(cone.site - reach);
                    cone.hi = cone.hi.min(cone.site + reach);
                }
                for (lo, hi) in clipped[i].into_iter().chain([(lo, hi)]) {
                    cone.lo = cone.lo.max(lo - 0.5);
                    cone.hi = cone.hi.min(hi + 0.5);
                }
            }
            vec![(None, cones)]
        }
        Speedup::Local => {
            let bounds =
                radius::cell_bounds(pixels, frame, radius::default_bin(frame, pixels.len()));
            let mut cones = cones_with(&|i| (bounds[i].radius + 0.5).min(picture_wide[i]));
            // The region's box, half a pixel wider like the radius.
            for cone in &mut cones {
                let b = &bounds[cone.id as usize];
                cone.lo = cone.lo.max(b.lo - 0.5);
                cone.hi = cone.hi.min(b.hi + 0.5);
            }
            vec![(None, cones)]
        }
        Speedup::Quadtree => {
            let bounds = radius::quadtree_width_bounds(pixels, frame);
            let widest = picture_wide.iter().copied().fold(0.0, f64::max);
            // The quadtree's widths are Euclidean; other metrics stretch them.
            let stretch = metric.stretch();
            let bounds = radius::WidthBounds {
                lower: bounds.lower * stretch,
                upper: bounds.upper.map(|u| u * stretch),
                ..bounds
            };
            // Coverage certifies a radius for Euclidean cones alone: under another
            // metric a pixel's nearest site may lie `stretch` times farther
            // (Euclidean) than the site whose cone covered it. Only the upper
            // bound, stretched, holds every region.
            let mut radii = radius::retry_radii(&bounds, widest);
            if metric != Metric::L2 {
                radii.drain(..radii.len() - 1);
            }
            radii
                .into_iter()
                .map(|r| (Some(r), cones_with(&|i| (r + 0.5).min(picture_wide[i]))))
                .collect()
        }
    }
}

/// Corners of a long exact cone's footprint polygon, a regular K-gon around the
/// disc it must cover: K - 2 triangles of area `K tan(pi / K) r²`. On lavapipe a
/// triangle costs as much as many fragments (`TRIANGLE_FRAGMENTS`), so
/// hexagons (3.5 r²) give way to octagons (3.3 r²) only where the saved fragments
/// pay for the two extra triangles.
fn polygon_corners(radius: f64) -> u32 {
    if radius < 70.0 {
        6
    } else {
        8
    }
}

/// Chooses each cone's footprint and sorts the cones into draw order: batched
/// cones first, along a Hilbert curve so that a batch's cones are neighbours, then
/// the others by footprint and site id.
///
/// Without `batch` every exact cone gets a footprint of its own: counting ties
/// needs each cone's own fragments. `key` is what exact cones write: keys that
/// need powers batch only short cones.
fn shape_cones(
    cones: &[Cone],
    frame: &Frame,
    accuracy: Accuracy,
    metric: Metric,
    key: DepthKey,
    batch: bool,
) -> Vec<Shaped> {
    let batch_radius_limit = match key {
        DepthKey::Metric(Metric::Lp(_)) => BATCH_RADIUS_LIMIT_LP,
        _ => BATCH_RADIUS_LIMIT,
    };
    // L∞ balls and L_p balls for p >= 2 fill 88% or more of their bounding
    // square, which takes two triangles where the octagon takes eight (lavapipe
    // sets up and bins each).
    let square_ball = match metric {
        Metric::LInf => true,
        Metric::Lp(p) => p >= 2.0,
        _ => false,
    };
    // Measuring the sampled circle costs far more than scaling it: the ball
    // footprint's outer radius and area at reach 1.
    let (unit_ball_outer, unit_ball_area) = match (accuracy, metric) {
        (Accuracy::Exact, Metric::L1 | Metric::Lp(_)) if !square_ball => {
            let fan = chain::MetricFan::Uniform {
                corners: BALL_CORNERS,
            };
            let outer = fan.outer_radius_of_reach(metric, 1.0);
            let rim = fan.unit_mesh(metric, 1.0);
            let area = (1..rim.len() - 1)
                .map(|k| f64::from(rim[k][0] * rim[k + 1][1] - rim[k + 1][0] * rim[k][1]) / 2.0)
                .sum::<f64>();
            (outer, area * outer * outer)
        }
        _ => (1.0, 0.0),
    };
    // An exact cone drawn on its own: its footprint, outer radius and cost in
    // fragments, a triangle counting as TRIANGLE_FRAGMENTS. The square of side
    // 2 reach around the site (its corners reach √2 away), cut to the region's
    // box, holds the ball of every metric that grows with each coordinate.
    let alone = |cone: &Cone| -> (Footprint, f64, f64) {
        let (lo, hi) = cone.clip();
        let square_area = (hi - lo).max(DVec2::ZERO).element_product();
        let square = (
            Footprint::Polygon(4),
            cone.reach * std::f64::consts::SQRT_2,
            square_area + 2.0 * TRIANGLE_FRAGMENTS,
        );
        if square_ball {
            return square;
        }
        let r = cone.reach;
        let (footprint, outer, area) = if metric != Metric::L2 {
            (Footprint::Ball, r * unit_ball_outer, unit_ball_area * r * r)
        } else {
            let k = polygon_corners(cone.radius);
            let outer = FanShape::with_triangles(cone.radius, k).outer_radius;
            let area = 0.5 * k as f64 * (TAU / k as f64).sin() * outer * outer;
            (Footprint::Polygon(k), outer, area)
        };
        let corners = match footprint {
            Footprint::Polygon(k) => k,
            _ => BALL_CORNERS,
        };
        let cost = area + (corners - 2) as f64 * TRIANGLE_FRAGMENTS;
        if square.2 < cost {
            square
        } else {
            (footprint, outer, cost)
        }
    };
    let mut shaped: Vec<Shaped> = cones
        .iter()
        .map(|cone| {
            let fan = |s: FanShape| (Footprint::Fan(s.triangles), s.outer_radius);
            let (footprint, outer_radius) = match accuracy {
                Accuracy::Exact if batch && cone.radius < batch_radius_limit => {
                    (Footprint::Batch, cone.radius)
                }
                Accuracy::Exact => {
                    let (footprint, outer, _) = alone(cone);
                    (footprint, outer)
                }
                Accuracy::Fan {
                    triangles: Some(t), ..
                } if metric == Metric::L2 => fan(FanShape::with_triangles(cone.radius, t)),
                Accuracy::Fan {
                    epsilon,
                    triangles: None,
                } if metric == Metric::L2 => {
                    fan(FanShape::for_distance_error(cone.radius, epsilon))
                }
                Accuracy::Fan {
                    triangles: Some(t), ..
                } => (
                    Footprint::Fan(t),
                    metric_fan(accuracy).outer_radius_of_reach(metric, cone.reach),
                ),
                Accuracy::Fan { .. } => {
                    let outer = metric_fan(accuracy).outer_radius_of_reach(metric, cone.reach);
                    // L1 and L∞ chains are their exact circles at every radius.
                    let level = match metric {
                        Metric::L1 | Metric::LInf | Metric::Polygon(_) => 0,
                        _ => chain::chain_level(outer),
                    };
                    (Footprint::Chain(level), outer)
                }
            };
            Shaped {
                cone: *cone,
                footprint,
                outer_radius,
            }
        })
        .collect();
    let side = frame.width.max(frame.height) as f64;
    let curve = |p: DVec2| {
        let q = |v: f64| ((v + 0.5) / side * 65536.0).clamp(0.0, 65535.0) as u32;
        hilbert_index(q(p.x), q(p.y))
    };
    let order = |s: &Shaped| match s.footprint {
        Footprint::Batch => (s.footprint, curve(s.cone.site), s.cone.id),
        _ => (s.footprint, 0, s.cone.id),
    };
    shaped.sort_by_cached_key(order);
    // Cheap keys batch wide cones where the batch's rectangle, evaluating
    // every cone per fragment, costs less than the cones drawn alone. Whole
    // batches leave, so the others keep their grouping.
    if matches!(key, DepthKey::PowerSum(_)) {
        let batched = shaped
            .iter()
            .take_while(|s| s.footprint == Footprint::Batch)
            .count();
        for chunk in shaped[..batched].chunks_mut(BATCH) {
            let (lo, hi) = chunk
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), s| {
                    (lo.min(s.cone.lo - 0.5), hi.max(s.cone.hi + 0.5))
                });
            let singles: Vec<(Footprint, f64, f64)> =
                chunk.iter().map(|s| alone(&s.cone)).collect();
            let batch_cost = (hi - lo).element_product() * BATCH as f64;
            if batch_cost > singles.iter().map(|a| a.2).sum::<f64>() {
                for (s, a) in chunk.iter_mut().zip(singles) {
                    (s.footprint, s.outer_radius, _) = a;
                }
            }
        }
        shaped.sort_by_cached_key(order);
    }
    shaped
}

/// Instances of the batch program: the batched cones (a prefix of `shaped`) in
/// runs of [`BATCH`], each with the bounding box of its cones' footprints. The
/// last batch repeats its last cone to fill its slots.
fn batches_of(shaped: &[Shaped]) -> Vec<ConeBatch> {
    let batched = shaped
        .iter()
        .take_while(|s| s.footprint == Footprint::Batch)
        .count();
    shaped[..batched]
        .chunks(BATCH)
        .map(|chunk| {
            let mut batch = ConeBatch {
                rect: [f32::MAX, f32::MAX, f32::MIN, f32::MIN],
                sites: [0.0; 2 * BATCH],
                radii2: [0.0; BATCH],
                ids: [0; BATCH],
            };
            for k in 0..BATCH {
                let cone = chunk[k.min(chunk.len() - 1)].cone;
                let (p, r) = (cone.site, cone.radius);
                batch.sites[2 * k] = p.x as f32;
                batch.sites[2 * k + 1] = p.y as f32;
                batch.radii2[k] = (r * r) as f32;
                batch.ids[k] = cone.id;
                // Half a pixel more, so that the rectangle's rasterization rules
                // never drop a pixel centre on the rim.
                let (lo, hi) = (cone.lo - 0.5, cone.hi + 0.5);
                batch.rect = [
                    batch.rect[0].min(lo.x as f32),
                    batch.rect[1].min(lo.y as f32),
                    batch.rect[2].max(hi.x as f32),
                    batch.rect[3].max(hi.y as f32),
                ];
            }
            batch
        })
        .collect()
}

/// Powers of two that map cone heights (fan) or squared distances (exact) into the
/// depth range [0, 1]; powers of two keep the mapping exact.
#[derive(Clone, Copy, Debug)]
struct DepthScale {
    vertex: f64,
    fragment: f64,
}

/// The scales for cones that reach no farther than `reach` (Euclidean): exact
/// cones discard fragments beyond their radius; fan heights reach the outer
/// radius at the rim.
fn depth_scale(reach: f64, accuracy: Accuracy, key: DepthKey) -> DepthScale {
    match accuracy {
        Accuracy::Exact => DepthScale {
            vertex: 0.0,
            fragment: key.scale(reach),
        },
        Accuracy::Fan { .. } => DepthScale {
            vertex: reach.log2().ceil().exp2().recip(),
            fragment: 0.0,
        },
    }
}

/// A run of cones with one footprint: one instanced draw.
#[derive(Clone, Copy, Debug)]
struct Group {
    footprint: Footprint,
    first: u32,
    count: u32,
}

fn groups_of(shaped: &[Shaped]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for (i, s) in shaped.iter().enumerate() {
        match groups.last_mut() {
            Some(g) if g.footprint == s.footprint => g.count += 1,
            _ => groups.push(Group {
                footprint: s.footprint,
                first: i as u32,
                count: 1,
            }),
        }
    }
    groups
}

/// The GPU-side buffers of one tile.
struct Picture {
    ids: Image,
    depth: Image,
}

impl Picture {
    /// Begins rendering into the tile, its ids cleared to "no site", its depths
    /// to the farthest, and its stencil to 0 where `stencil`.
    fn begin<'r>(&'r self, pass: &mut Pass<'_, 'r>, stencil: bool) -> Result<()> {
        pass.begin(
            Target {
                color: Some(&self.ids),
                depth_stencil: Some(&self.depth),
            },
            Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: stencil.then_some(0),
            },
        )
    }
}

/// The part of the picture a tile image shows: pixel `(i, j)` of the tile image is
/// pixel `origin + (i, j)` of the picture.
#[derive(Clone, Copy, Debug)]
struct TileView {
    origin: DVec2,
    width: u32,
    height: u32,
}

impl TileView {
    /// The tile's pixel centres: corners `(lo, hi)` in picture pixels.
    fn centres(&self) -> (DVec2, DVec2) {
        let size = DVec2::new(self.width as f64, self.height as f64);
        (self.origin, self.origin + size - 1.0)
    }

    /// Whether a disc of radius `r` around `p` (picture pixels) meets the tile.
    fn reaches(&self, p: DVec2, r: f64) -> bool {
        let (lo, hi) = self.centres();
        distance2_to_rect(p, lo, hi) <= r * r
    }

    /// Whether the rectangle `[lo, hi]` (picture pixels) holds a pixel centre of
    /// the tile's range.
    fn meets(&self, lo: [f32; 2], hi: [f32; 2]) -> bool {
        let (a, b) = self.centres();
        lo[0] as f64 <= b.x && hi[0] as f64 >= a.x && lo[1] as f64 <= b.y && hi[1] as f64 >= a.y
    }
}

/// What one pass draws.
struct Draws<'a> {
    /// All cones in draw order; the batched ones are drawn through `batches`.
    cones: &'a [Shaped],
    batches: &'a [ConeBatch],
    accuracy: Accuracy,
    metric: Metric,
    /// What exact cones write.
    key: DepthKey,
    /// Fan meshes of other metrics, made once for every tile and pass.
    meshes: &'a chain::FanMeshes,
    scale: DepthScale,
    /// Count the cones at each pixel's lowest depth in the stencil.
    ties: bool,
    /// Take the envelope of exact cones per screen tile from the sites whose
    /// box meets it ([`NEAREST_TILES`]) instead of drawing them.
    tiled: bool,
    /// Or from each tile's candidates, found directly.
    candidates: Option<&'a TileCandidates>,
    /// Every site (picture pixels), by id.
    sites: &'a [DVec2],
}

/// Items binned to the screen tiles of a target: tile `t` (row-major, tiles of
/// [`SCREEN_TILE_SIDE`] pixels) holds `items[start[t]..start[t + 1]]`.
struct ScreenTiles {
    start: Vec<u32>,
    items: Vec<u32>,
    across: usize,
    /// The target's last pixel centre.
    last: DVec2,
}

impl ScreenTiles {
    /// The tiles of a `width` x `height` target whose pixel (0, 0) is picture
    /// pixel `origin`, each `(id, lo, hi)` of `boxes` going to every tile with a
    /// pixel centre in `[lo, hi]` (picture pixels). `None` where the tiles would
    /// hold more items than the target has pixels (64 per pixel): drawing them
    /// costs less then.
    fn bin(
        origin: DVec2,
        width: u32,
        height: u32,
        boxes: impl Iterator<Item = (u32, DVec2, DVec2)>,
    ) -> Option<Self> {
        let side = SCREEN_TILE_SIDE as usize;
        let across = (width as usize).div_ceil(side);
        let tiles = across * (height as usize).div_ceil(side);
        let last = DVec2::new(width as f64 - 1.0, height as f64 - 1.0);
        // Each item's tiles: first and last column and row.
        let spans: Vec<(u32, [usize; 4])> = boxes
            .filter_map(|(id, lo, hi)| {
                let first = (lo - origin).ceil().max(DVec2::ZERO);
                let end = (hi - origin).floor().min(last);
                (first.x <= end.x && first.y <= end.y).then(|| {
                    (
                        id,
                        [first.x, first.y, end.x, end.y].map(|v| v as usize / side),
                    )
                })
            })
            .collect();
        let rows = |[x0, y0, x1, y1]: [usize; 4]| {
            (y0..=y1).map(move |y| y * across + x0..=y * across + x1)
        };
        let mut start = vec![0u32; tiles + 1];
        for &(_, span) in &spans {
            for row in rows(span) {
                for t in row {
                    start[t + 1] += 1;
                }
            }
        }
        for t in 0..tiles {
            start[t + 1] += start[t];
        }
        if start[tiles] as u64 > width as u64 * height as u64 {
            return None;
        }
        let mut next = start[..tiles].to_vec();
        let mut items = vec![0u32; start[tiles] as usize];
        for (id, span) in spans {
            for row in rows(span) {
                for t in row {
                    items[next[t] as usize] = id;
                    next[t] += 1;
                }
            }
        }
        Some(Self {
            start,
            items,
            across,
            last,
        })
    }

    /// The tiles of a `width` x `height` target whose pixel (0, 0) is picture
    /// pixel `origin` (a multiple of the tile side), holding the `candidates`
    /// of the picture's tiles; `None` where they would hold more items than the
    /// target has pixels.
    fn of_candidates(
        candidates: &TileCandidates,
        origin: DVec2,
        width: u32,
        height: u32,
    ) -> Option<Self> {
        debug_assert_eq!(candidates.side, SCREEN_TILE_SIDE);
        let side = SCREEN_TILE_SIDE as usize;
        let across = (width as usize).div_ceil(side);
        let down = (height as usize).div_ceil(side);
        let (x0, y0) = (origin.x as usize / side, origin.y as usize / side);
        let picture_down = (candidates.start.len() - 1) / candidates.across;
        let list = |t: usize| {
            let (tx, ty) = (x0 + t % across, y0 + t / across);
            if tx < candidates.across && ty < picture_down {
                let k = ty * candidates.across + tx;
                &candidates.items[candidates.start[k] as usize..candidates.start[k + 1] as usize]
            } else {
                &[]
            }
        };
        let mut start = Vec::with_capacity(across * down + 1);
        start.push(0u32);
        for t in 0..across * down {
            start.push(start[t] + list(t).len() as u32);
        }
        if start[across * down] as u64 > width as u64 * height as u64 {
            return None;
        }
        let items = (0..across * down).flat_map(list).copied().collect();
        Some(Self {
            start,
            items,
            across,
            last: DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
        })
    }

    /// The first and last pixel centre of tile `t` (target pixels).
    fn centres(&self, t: usize) -> (DVec2, DVec2) {
        let side = SCREEN_TILE_SIDE as f64;
        let lo = DVec2::new((t % self.across) as f64, (t / self.across) as f64) * side;
        (lo, (lo + side - 1.0).min(self.last))
    }

    fn tiles(&self) -> usize {
        self.start.len() - 1
    }

    /// The first item of tile `t` and the number of its items.
    fn range(&self, t: usize) -> (u32, u32) {
        (self.start[t], self.start[t + 1] - self.start[t])
    }
}

/// The records of [`NEAREST_TILES`] for `view`: one texel per screen
/// tile (its first site texel and its number of sites), then its sites, a site
/// going to every tile with a pixel centre in its box. Where keys take powers,
/// each tile's sites come by the smallest key of a pixel of the tile from them,
/// so that a fragment can stop at the first that cannot beat its nearest: a
/// texel per site (x, y as float bits, that key as float bits, id). Other keys
/// cost less than the ordering, and their sites come by id, so that a fragment
/// needs ids only for its nearest: two texels per pair of sites (x, y, x, y as
/// float bits; 0, 0, id, id), a tile with an odd number repeating its last.
/// `None` where the lists would be too long.
fn tile_records(view: &TileView, draws: &Draws<'_>) -> Option<Vec<[u32; 4]>> {
    let key = draws.key;
    let ordered = !matches!(
        key,
        DepthKey::Metric(Metric::L2 | Metric::L1 | Metric::LInf)
    );
    let bins = match draws.candidates {
        Some(candidates) => {
            ScreenTiles::of_candidates(candidates, view.origin, view.width, view.height)?
        }
        None => {
            let boxes = draws.cones.iter().map(|s| {
                let (lo, hi) = s.cone.clip();
                (s.cone.id, lo, hi)
            });
            ScreenTiles::bin(view.origin, view.width, view.height, boxes)?
        }
    };
    let tiles = bins.tiles();
    let site_texels = |t: usize| {
        let count = bins.range(t).1 as usize;
        if ordered {
            count
        } else {
            2 * count.div_ceil(2)
        }
    };
    let mut texels: Vec<[u32; 4]> = Vec::with_capacity(tiles + bins.items.len() + tiles);
    let mut next = tiles;
    texels.extend((0..tiles).map(|t| {
        let first = next as u32;
        next += site_texels(t);
        [first, bins.range(t).1, 0, 0]
    }));
    texels.resize(next, [0; 4]);
    let mut sites = &mut texels[tiles..];
    let mut lists = Vec::with_capacity(tiles);
    for t in 0..tiles {
        let (list, rest) = sites.split_at_mut(site_texels(t));
        lists.push(list);
        sites = rest;
    }
    lists
        .into_par_iter()
        .enumerate()
        .for_each_init(Vec::new, |entries, (t, list)| {
            let (first, count) = bins.range(t);
            let (lo, hi) = bins.centres(t);
            let (lo, hi) = (lo + view.origin, hi + view.origin);
            entries.clear();
            entries.extend(
                bins.items[first as usize..(first + count) as usize]
                    .iter()
                    .map(|&id| {
                        // The device's coordinates, and a margin for its rounding.
                        let site = draws.sites[id as usize].as_vec2();
                        let least = match ordered {
                            true => {
                                let site = site.as_dvec2();
                                (key.of_offset(site - site.clamp(lo, hi)) * (1.0 - 1e-4)) as f32
                            }
                            false => 0.0,
                        };
                        (least, id, site)
                    }),
            );
            entries.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            if ordered {
                for (&(least, id, site), texel) in entries.iter().zip(list) {
                    *texel = [site.x.to_bits(), site.y.to_bits(), least.to_bits(), id];
                }
            } else {
                for (pair, texels) in entries.chunks(2).zip(list.chunks_exact_mut(2)) {
                    let (a, b) = (pair[0], pair[pair.len() - 1]);
                    texels[0] = [a.2.x, a.2.y, b.2.x, b.2.y].map(f32::to_bits);
                    texels[1] = [0, 0, a.1, b.1];
                }
            }
        });
    Some(texels)
}

/// Draws the lower envelope of exact cones into the tile from the screen
/// tiles' lists of sites ([`tile_records`]); `false` where the lists would be
/// too long.
fn render_tiles(
    machine: &Machine,
    picture: &Picture,
    view: &TileView,
    draws: &Draws<'_>,
    push: &ConePush,
) -> Result<bool> {
    let Some(texels) = tile_records(view, draws) else {
        return Ok(false);
    };
    let Some((upload, records)) = records_image(machine, texels)? else {
        return Ok(false);
    };
    machine.run(|pass| {
        pass.upload_for_fragments(&upload, &records)?;
        pass.bind_fragment_buffers(&[], Some(&records))?;
        picture.begin(pass, false)?;
        draw_over_target(
            pass,
            &NEAREST_TILES,
            &RasterState::lower_envelope(),
            &DrawParams::default(),
            push,
        )?;
        pass.end()
    })?;
    Ok(true)
}

/// Draws the lower envelope of the cones that reach `view` into the tile;
/// whether it was found from screen tiles' lists of sites.
fn render(
    machine: &Machine,
    picture: &Picture,
    view: &TileView,
    draws: &Draws<'_>,
) -> Result<bool> {
    let push = ConePush {
        picture_size: [view.width as f32, view.height as f32],
        offset: [view.origin.x as f32, view.origin.y as f32],
        vertex_depth_scale: draws.scale.vertex as f32,
        fragment_depth_scale: draws.scale.fragment as f32,
        levels: 1,
        // Polygons are drawn as fans only (see `voronoi_bands`).
        metric: draws.key.shader_code().unwrap_or((0, 2.0)).into(),
    };
    if draws.tiled && render_tiles(machine, picture, view, draws, &push)? {
        return Ok(true);
    }
    let batches: Vec<ConeBatch> = draws
        .batches
        .iter()
        .filter(|b| view.meets([b.rect[0], b.rect[1]], [b.rect[2], b.rect[3]]))
        .copied()
        .collect();
    let visible: Vec<Shaped> = draws
        .cones
        .iter()
        .filter(|s| s.footprint != Footprint::Batch && view.reaches(s.cone.site, s.cone.radius))
        .copied()
        .collect();
    let groups = groups_of(&visible);
    let mut mesh: Vec<[f32; 3]> = UNIT_SQUARE.to_vec();
    let mut ranges = Vec::with_capacity(groups.len());
    for g in &groups {
        let vertices = match g.footprint {
            Footprint::Batch => unreachable!("batched cones are drawn as batches"),
            Footprint::Polygon(k) => unit_footprint(k),
            Footprint::Ball => draws
                .meshes
                .unit_mesh(
                    chain::MetricFan::Uniform {
                        corners: BALL_CORNERS,
                    },
                    1.0,
                )
                .to_vec(),
            Footprint::Fan(t) if draws.metric == Metric::L2 => unit_fan(t),
            Footprint::Fan(_) => draws
                .meshes
                .unit_mesh(metric_fan(draws.accuracy), 1.0)
                .to_vec(),
            Footprint::Chain(level) => draws
                .meshes
                .unit_mesh(metric_fan(draws.accuracy), chain::level_radius(level))
                .to_vec(),
        };
        ranges.push((mesh.len() as u32, vertices.len() as u32));
        mesh.extend(vertices);
    }
    let instances: Vec<ConeInstance> = visible
        .iter()
        .map(|s| {
            let c = &s.cone;
            let cone = ConeInstance::new(c.id, c.site.into(), s.outer_radius, c.radius);
            match s.footprint {
                // Clamping an axis-aligned square's corners cuts it exactly.
                Footprint::Polygon(4) if draws.accuracy == Accuracy::Exact => {
                    let (lo, hi) = c.clip();
                    ConeInstance {
                        clip: [lo.x, lo.y, hi.x, hi.y].map(|v| v as f32),
                        ..cone
                    }
                }
                _ => cone,
            }
        })
        .chain(std::iter::once(bytemuck::Zeroable::zeroed()))
        .collect();
    let mesh_buffer = machine.vertex_buffer(&mesh)?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    let batch_buffer = if batches.is_empty() {
        None
    } else {
        Some(machine.vertex_buffer(&batches)?)
    };
    let state = RasterState::lower_envelope();
    let params = DrawParams::default();
    machine.run(|pass| {
        picture.begin(pass, draws.ties)?;
        if let Some(batch_buffer) = &batch_buffer {
            draw_cones(
                pass,
                &CONE_EXACT_BATCH,
                &state,
                &params,
                &push,
                &ConeDraw {
                    mesh: &mesh_buffer,
                    first_vertex: 0,
                    vertex_count: UNIT_SQUARE.len() as u32,
                    instances: batch_buffer,
                    first_instance: 0,
                    instance_count: batches.len() as u32,
                },
            )?;
        }
        // The lower envelope, then (for ties) the thesis's second pass of §3.6.4:
        // every cone again with the depth test EQUAL, the stencil counting the
        // cones that reach the lowest depth.
        let count = RasterState {
            depth: DepthTest {
                compare: Compare::Equal,
                write: false,
            },
            stencil: StencilTest::on_pass(Compare::Always, 0xff, 0xff, StencilOp::IncrementClamp),
            color_mask: ChannelMask::NONE,
            ..RasterState::OVERWRITE
        };
        let passes: &[&RasterState] = if draws.ties {
            &[&state, &count]
        } else {
            &[&state]
        };
        for state in passes {
            for (g, &(first_vertex, vertex_count)) in groups.iter().zip(&ranges) {
                let program = match draws.accuracy {
                    Accuracy::Exact => &CONE_EXACT,
                    Accuracy::Fan { .. } => &CONE_FAN,
                };
                draw_cones(
                    pass,
                    program,
                    state,
                    &params,
                    &push,
                    &ConeDraw {
                        mesh: &mesh_buffer,
                        first_vertex,
                        vertex_count,
                        instances: &instance_buffer,
                        first_instance: g.first,
                        instance_count: g.count,
                    },
                )?;
            }
        }
        pass.end()
    })?;
    Ok(false)
}

/// Reads the picture part of a tile into `band` at the tile's column, turning
/// depths into distances in world units.
fn read_tile(
    machine: &Machine,
    tile: &DrawnTile<'_>,
    window: &PixelRect,
    options: &VoronoiOptions,
    band: &mut Band,
) -> Result<()> {
    let (inner, x0) = (tile.inner, (tile.x0 - window.x) as usize);
    let (width, w) = (window.width as usize, inner.width as usize);
    machine.read_u32_into(tile.ids, inner, &mut band.labels[x0..], width)?;
    if options.ties {
        machine.read_stencil_into(tile.depth, inner, &mut band.ties[x0..], width)?;
    }
    if !options.distances {
        return Ok(());
    }
    machine.read_f32_into(tile.depth, inner, &mut band.distances[x0..], width)?;
    let keys = tile.keys;
    band.distances
        .par_chunks_mut(width)
        .zip(band.labels.par_chunks(width))
        .for_each(|(depths, ids)| {
            for (z, id) in depths[x0..x0 + w].iter_mut().zip(&ids[x0..x0 + w]) {
                *z = if *id == u32::MAX {
                    f32::INFINITY
                } else {
                    keys.distance(*z) as f32
                };
            }
        });
    Ok(())
}
