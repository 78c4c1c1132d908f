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
//! tile (`super::cones::NEAREST_TILES`), the sites that can own one of its pixels.
//!
//! Pictures larger than one device image (or than [`VoronoiOptions::max_tile`])
//! are rendered tile by tile, each tile drawing only the cones that reach it, and
//! delivered as bands of rows ([`voronoi_bands`]) so that no more than a band is
//! ever held in memory.
//!
//! The cones are sized, shaped and drawn by the envelope module
//! (`algorithms/envelope/`); this file is the diagram's pass script and its
//! readback. On a software rasterizer exact Euclidean labels are searched
//! for on the CPU instead ([`Method::Grid`], `grid.rs`), with the
//! same answer.

use super::ms;
use crate::memory::Gather;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::{
        cone::fan_distance_error,
        frame::{distinct_by, Checked},
        metric::Metric,
        site::Sites,
        Frame,
    },
    machine::{DeviceClass, Machine, PixelRect},
    Backend, Control,
};

use super::certify::{Certifier, Region};
use super::envelope::{
    drawn_accuracy, metric_fan, ConePlan, ConeSpec, DrawnTile, Picture, TileView, Tiling,
    SCREEN_TILE_SIDE,
};
mod grid;
pub mod sites;

use grid::grid_bands;

pub use super::envelope::{Accuracy, ConeGroup, Speedup, MAX_EXACT_REACH};

/// What to compute. Start from [`VoronoiOptions::exact`] (or `default()`, a
/// 1024 x 1024 picture) and change what differs, by field or by setter:
/// `VoronoiOptions::exact(frame).metric(Metric::L1).ties(true)`. New fields
/// may be added, so the struct is not built by a literal outside pixgeo.
#[derive(Clone, Debug, PartialEq)]
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
    /// How exact labels are found: drawn, or searched for on the CPU.
    pub method: Method,
    /// Progress (rows of the window done) and cancellation.
    pub control: Control,
}

/// How an exact diagram's labels are found; every way gives the same labels,
/// distances and ties, bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize),
    serde(rename_all = "lowercase")
)]
pub enum Method {
    /// [`Method::Grid`] for Euclidean exact diagrams on a software rasterizer,
    /// where it is faster; [`Method::Cones`] otherwise.
    #[default]
    Auto,
    /// The lower envelope of cones drawn on the device (the thesis's way).
    Cones,
    /// A search of a grid of the sites on the CPU, each pixel's nearest proven
    /// as the drawn ones are: Euclidean exact diagrams only.
    Grid,
}

impl Method {
    /// Refuses options this method cannot compute.
    fn check(self, options: &VoronoiOptions) -> Result<()> {
        if self == Method::Grid && !options.grid_fits() {
            return Err(Error::unsupported_option(
                "the grid method finds exact Euclidean labels; other metrics and fan mode \
                 take the cones"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The way `options` are computed on `machine`.
    fn resolve(self, machine: &Machine, options: &VoronoiOptions) -> Result<Method> {
        self.check(options)?;
        let software = machine.device_class() == DeviceClass::Software;
        Ok(match self {
            Method::Auto if software && options.grid_fits() => Method::Grid,
            Method::Auto => Method::Cones,
            method => method,
        })
    }
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
            method: Method::Auto,
            control: Control::default(),
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

    pub fn method(self, method: Method) -> Self {
        Self { method, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }

    /// Whether [`Method::Grid`] finds the labels these options ask for:
    /// exact and Euclidean.
    pub fn grid_fits(&self) -> bool {
        self.metric == Metric::L2 && self.accuracy == Accuracy::Exact
    }

    /// Whether these options' labels can be found without a Vulkan device
    /// ([`voronoi`] on [`Backend::Cpu`]): the grid fits, and the cones are not asked for.
    pub fn on_cpu_alone(&self) -> bool {
        self.grid_fits() && self.method != Method::Cones
    }

    /// The window's pixels in the frame ([`Frame::window_rect`]); windows
    /// take exact mode.
    pub fn window_rect(&self) -> Result<PixelRect> {
        if self.window.is_some() && self.accuracy != Accuracy::Exact {
            return Err(Error::unsupported_option(
                "a window takes exact mode: a fan's interpolated depths round by where its \
                 tile lies, so fan windows would not match the whole diagram bit for bit"
                    .into(),
            ));
        }
        self.frame.window_rect(self.window)
    }
}

impl Default for VoronoiOptions {
    /// Exact labels and distances on 1024 x 1024 pixels, pixel (i, j) centred
    /// at world (i, j).
    fn default() -> Self {
        Self::exact(Frame::pixels(1024, 1024).expect("a valid picture"))
    }
}

/// How the diagram was made.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VoronoiStats {
    pub device: String,
    /// How the labels were found: [`Method::Cones`] or [`Method::Grid`].
    pub method: Method,
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
    /// Pixels whose drawn label (or tie count) the exact check replaced.
    pub mended: usize,
    /// Milliseconds the exact check took.
    pub certify_ms: f64,
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

impl VoronoiDiagram {
    /// The diagram of the whole picture `frame`, without tie counts.
    pub fn whole(frame: Frame, labels: Vec<u32>, distances: Vec<f32>, stats: VoronoiStats) -> Self {
        VoronoiDiagram {
            width: frame.width,
            height: frame.height,
            frame,
            window: PixelRect::sized(frame.width, frame.height),
            labels,
            distances,
            ties: Vec::new(),
            stats,
        }
    }
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

/// Computes the Voronoi diagram of `sites` (world coordinates) on
/// `backend`: cones or the grid on a device's machine (as
/// [`VoronoiOptions::method`] picks), the grid on the CPU alone (Euclidean
/// exact diagrams only). Every route gives the same diagram bit for bit.
/// Sites of any shape and weight ([`Site`](crate::geometry::site::Site)) take
/// the route of [`sites`].
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::voronoi::{voronoi, VoronoiOptions}, geometry::{metric::Metric, Frame}, Backend};
///
/// let sites = [DVec2::new(2.0, 2.0), DVec2::new(6.0, 2.0)];
/// let options = VoronoiOptions::exact(Frame::pixels(9, 5)?).ties(true);
/// let d = voronoi(&Backend::Cpu, &sites, &options)?;
/// assert_eq!((d.labels[2 * 9 + 3], d.labels[2 * 9 + 5]), (0, 1));
/// assert_eq!(d.ties[2 * 9 + 4], 2); // pixel (4, 2) is as near to both
/// let l1 = options.metric(Metric::L1);
/// let d = pixgeo::with_default_machine(|m| voronoi(&Backend::Device(m), &sites, &l1))?;
/// assert_eq!(d.ties[2 * 9 + 4], 2);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi<'a>(
    backend: &Backend,
    sites: impl Into<Sites<'a>>,
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    match sites.into() {
        Sites::Points(points) => voronoi_checked(backend, Checked::new(points)?, options),
        Sites::General(sites) => sites::voronoi_of_sites(backend, sites, options),
    }
}

/// [`voronoi`] of sites checked where they entered.
pub(crate) fn voronoi_checked(
    backend: &Backend,
    sites: Checked<'_>,
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    whole_diagram(options, |sink| bands(backend, sites, options, sink))
}

/// The diagram of `options`' window from the bands `bands` hands over.
fn whole_diagram(
    options: &VoronoiOptions,
    bands: impl FnOnce(&mut dyn FnMut(Band) -> Result<()>) -> Result<VoronoiStats>,
) -> Result<VoronoiDiagram> {
    let window = options.window_rect()?;
    let pixels = window.width as usize * window.height as usize;
    let each = 4 + 4 * options.distances as u64 + 4 * options.ties as u64;
    crate::memory::reserve_picture(window.width, window.height, each, "a Voronoi diagram")?;
    let mut labels = Vec::new();
    let mut distances = Vec::new();
    let mut ties = Vec::new();
    let stats = bands(&mut |band| {
        // A picture of one band is handed over without a copy; more bands
        // grow it once to the whole picture, not by doubling.
        if labels.is_empty() {
            labels = band.labels;
            distances = band.distances;
            ties = band.ties;
            room_for_all(&mut labels, pixels);
            room_for_all(&mut distances, pixels);
            room_for_all(&mut ties, pixels);
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

/// Room in `v`, a first band of a picture's values (or none), for the whole
/// picture of `pixels`.
fn room_for_all<T>(v: &mut Vec<T>, pixels: usize) {
    if !v.is_empty() {
        v.reserve_exact(pixels - v.len());
    }
}

/// Computes the Voronoi diagram of `sites` (world coordinates) on `backend`
/// and hands it to `sink` as bands of rows, top to bottom. On a device a band
/// is one row of tiles; tiles are as large as the device (or
/// [`VoronoiOptions::max_tile`]) allows, so only one band is held at a time.
/// The result does not depend on the tiling or the route.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::voronoi::{voronoi_bands, VoronoiOptions}, geometry::Frame};
///
/// let sites = [DVec2::new(100.0, 50.0), DVec2::new(900.0, 700.0)];
/// let options = VoronoiOptions::exact(Frame::pixels(1000, 800)?).max_tile(Some(256));
/// let mut rows = 0;
/// pixgeo::with_default_machine(|m| {
///     voronoi_bands(&pixgeo::Backend::Device(m), &sites, &options, |band| {
///         rows += band.height; // write band.labels to a file here
///         Ok(())
///     })
/// })?;
/// assert_eq!(rows, 800);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi_bands(
    backend: &Backend,
    sites: &[DVec2],
    options: &VoronoiOptions,
    sink: impl FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    bands(backend, Checked::new(sites)?, options, sink)
}

/// [`voronoi_bands`] of sites checked where they entered.
fn bands(
    backend: &Backend,
    sites: Checked<'_>,
    options: &VoronoiOptions,
    mut sink: impl FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    let sites = sites.sites();
    let window = options.window_rect()?;
    let mut sink = |band: Band| {
        let rows = band.y0 + band.height - window.y;
        options.control.report(rows.into(), window.height.into());
        sink(band)
    };
    options.control.run(|| match backend {
        Backend::Device(machine) => repeats_once(sites, options, &mut sink, &mut |sites, sink| {
            distinct_bands(machine, sites, options, sink)
        }),
        Backend::Cpu => {
            if options.method == Method::Cones {
                return Err(Error::unsupported_option("cones are drawn on a Vulkan device; on the CPU alone labels are found by the grid"
                        .into(),));
            }
            let options = &options.clone().method(Method::Grid);
            Method::Grid.check(options)?;
            repeats_once(sites, options, &mut sink, &mut |sites, sink| {
                grid_bands(sites, options, "cpu", sink)
            })
        }
    })
}

/// A route that hands the bands of the diagram of distinct sites to a sink.
type DrawBands<'a> =
    dyn FnMut(&[DVec2], &mut dyn FnMut(Band) -> Result<()>) -> Result<VoronoiStats> + 'a;

/// The bands of the diagram of `sites` from `draw`, which draws the
/// diagram of distinct sites.
fn repeats_once(
    sites: &[DVec2],
    options: &VoronoiOptions,
    sink: &mut dyn FnMut(Band) -> Result<()>,
    draw: &mut DrawBands<'_>,
) -> Result<VoronoiStats> {
    // Equal sites stand the same cone, and the first of them (the smallest id)
    // wins every pixel any of them would: the others are dropped up front, so
    // repeats cost nothing. Tie counts add the repeats of each position tied
    // (found exactly where more than one is), over the whole picture.
    if options.ties && options.window.is_some() {
        return draw(sites, sink);
    }
    let (mut kept, repeats) = distinct_by(sites, 0..sites.len() as u32, |_| ());
    if repeats.is_empty() {
        return draw(sites, sink);
    }
    kept.sort_unstable();
    let distinct: Vec<DVec2> = kept.iter().map(|&i| sites[i as usize]).gather("distinct")?;
    let mut repeated = crate::memory::filled(distinct.len(), 1u32, "repeats")?;
    let position = |i: u32| kept.binary_search(&i).expect("a kept site");
    for &[_, first] in &repeats {
        repeated[position(first)] += 1;
    }
    let ties = options
        .ties
        .then(|| Certifier::new(&distinct, &options.frame, options.metric))
        .transpose()?;
    let width = options.frame.width as usize;
    let mut stats = draw(&distinct, &mut |mut band: Band| {
        if let Some(certifier) = &ties {
            for (k, (label, count)) in band.labels.iter().zip(&mut band.ties).enumerate() {
                if *label == u32::MAX {
                    continue;
                }
                let pixel = [(k % width) as i64, (band.y0 as usize + k / width) as i64];
                let sum: u32 = match *count {
                    1 => repeated[*label as usize],
                    _ => certifier
                        .tied_with(pixel, *label)
                        .iter()
                        .map(|&s| repeated[s as usize])
                        .sum(),
                };
                *count = sum.min(255);
            }
        }
        for label in band.labels.iter_mut().filter(|l| **l != u32::MAX) {
            *label = kept[*label as usize];
        }
        sink(band)
    })?;
    stats.sites = sites.len();
    Ok(stats)
}

/// [`voronoi_bands`] of sites that are distinct, or whose ties are counted.
fn distinct_bands(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
    sink: &mut dyn FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    if options.method.resolve(machine, options)? == Method::Grid {
        return grid_bands(sites, options, machine.device_name(), sink);
    }
    let window = options.window_rect()?;
    let started = Instant::now();
    // Polygons are drawn as fans in exact mode too, and certified like cones.
    let certifier = match options.accuracy {
        Accuracy::Exact => Some(Certifier::new(sites, &options.frame, options.metric)?),
        Accuracy::Fan { .. } => None,
    };
    let (mut mended, mut certify_ms) = (0, ms(started));
    let mut band: Option<Band> = None;
    let extras = TileExtras {
        power_keys: true,
        near_ties: true,
        ..TileExtras::default()
    };
    let mut stats = draw_point_tiles(machine, sites, options, extras, |tile| {
        if tile.x0 == window.x {
            if let Some(done) = band.take() {
                sink(done)?;
            }
            let pixels = tile.inner.height as usize * window.width as usize;
            band = Some(Band {
                y0: tile.y0,
                height: tile.inner.height,
                labels: crate::memory::filled(pixels, 0, "labels")?,
                distances: if options.distances {
                    crate::memory::filled(pixels, 0.0, "distances")?
                } else {
                    Vec::new()
                },
                ties: if options.ties {
                    crate::memory::filled(pixels, 0, "tie counts")?
                } else {
                    Vec::new()
                },
            });
        }
        let band = band
            .as_mut()
            .expect("a band begins at the window's left edge");
        read_tile(machine, tile, &window, options, band)?;
        let x0 = (tile.x0 - window.x) as usize;
        let region = Region {
            x0: tile.x0,
            y0: tile.y0,
            width: tile.inner.width,
            height: tile.inner.height,
            stride: window.width as usize,
            k: 1,
        };
        if let Some(certifier) = &certifier {
            let started = Instant::now();
            let certify = if tile.marked {
                Certifier::certify_marked
            } else {
                Certifier::certify
            };
            let ties = options.ties.then(|| &mut band.ties[x0..]);
            mended += certify(certifier, region, &mut band.labels[x0..], None, ties)?;
            // Each distance from its label, the same in every tile.
            if options.distances {
                let (labels, distances) = (&band.labels[x0..], &mut band.distances[x0..]);
                certifier.label_distances(region, labels, distances);
            }
            certify_ms += ms(started);
        }
        Ok(())
    })?;
    if let Some(done) = band {
        sink(done)?;
    }
    stats.mended = mended;
    stats.certify_ms = certify_ms;
    Ok(stats)
}

/// What the tiles of [`draw_point_tiles`] hold besides labels and depths.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TileExtras {
    /// A stencil in the depth image.
    pub stencil: bool,
    /// Exact depths as power sums where the metric allows
    /// (`DepthKey::for_cones`).
    pub power_keys: bool,
    /// Near ties marked in the labels' top bit where the route can tell
    /// (`DrawnTile::marked`).
    pub near_ties: bool,
}

/// Draws the Voronoi diagram of points tile by tile, handing each tile to
/// `visit` while it is on the device (tiles of a row of tiles left to right, rows
/// top to bottom). The caller has checked the sites where they entered.
pub(crate) fn draw_point_tiles(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
    extras: TileExtras,
    mut visit: impl FnMut(&DrawnTile<'_>) -> Result<()>,
) -> Result<VoronoiStats> {
    options.frame.check()?;
    if options.ties && matches!(options.metric, Metric::Polygon(_)) {
        return Err(Error::unsupported_option("equal distances are counted for the L_p metrics; polygonal distances are drawn as fans".into(),));
    }
    // Windows take exact mode, polygons' (drawn as fans, then certified) too.
    let window = options.window_rect()?;
    let options = &VoronoiOptions {
        accuracy: drawn_accuracy(options.metric, options.accuracy),
        ..options.clone()
    };
    if options.ties && options.accuracy != Accuracy::Exact {
        return Err(Error::unsupported_option(
            "equal distances are counted in exact mode only".into(),
        ));
    }
    options.accuracy.check_for(options.metric)?;
    let frame = options.frame;
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        method: Method::Cones,
        sites: sites.len(),
        ..Default::default()
    };

    let started = Instant::now();
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).gather("pixels")?;
    let spec = ConeSpec {
        metric: options.metric,
        accuracy: options.accuracy,
        speedup: options.speedup,
        ties: options.ties,
        power_keys: extras.power_keys,
        mark_near_ties: extras.near_ties,
    };
    let plan = ConePlan::new(machine, pixels, &frame, spec)?;
    stats.bounds_ms = ms(started);

    // A band of rows is held on the host: keep it to about 2^26 pixels, in
    // whole screen tiles.
    let band_rows =
        ((1u64 << 26) / frame.width as u64) as u32 / SCREEN_TILE_SIDE * SCREEN_TILE_SIDE;
    let tiling = Tiling::new(machine, options.max_tile, window, band_rows)?;
    let (tile_w, tile_h) = (tiling.tile_w, tiling.tile_h);
    let picture = Picture::new(machine, tile_w, tile_h, options.ties || extras.stencil)?;
    let keys = plan.depth_map(frame.scale);
    // Tile candidates are the picture's: the tiles of a view must be among them.
    let aligned = |tile: u32, whole: u32| tile >= whole || tile % SCREEN_TILE_SIDE == 0;
    let aligned = aligned(tile_w, window.width)
        && aligned(tile_h, window.height)
        && window.x % SCREEN_TILE_SIDE == 0
        && window.y % SCREEN_TILE_SIDE == 0;
    let mut final_attempt = 0;
    let mut drawn_by_tiles = plan.is_tiled();
    for (x0, y0, inner) in tiling.tiles() {
        let view = TileView {
            origin: DVec2::new(x0 as f64, y0 as f64),
            width: tile_w,
            height: tile_h,
        };
        stats.tiles += 1;
        let started = Instant::now();
        let mut tile_by_lists = false;
        for k in 0..plan.attempts() {
            stats.passes += 1;
            tile_by_lists = plan.render(machine, &picture, &view, k, aligned)?;
            drawn_by_tiles &= tile_by_lists;
            final_attempt = final_attempt.max(k);
            // Picture-wide and local radii cover every pixel by construction; the
            // quadtree's radius is checked with minmax, the thesis's way: a pixel
            // no truncated cone reached keeps the "no site" id, the largest value.
            let covered = options.speedup != Speedup::Quadtree
                || machine.minmax(&picture.ids, inner)?.max[0] < u32::MAX as f64;
            if covered {
                break;
            }
            if k + 1 == plan.attempts() {
                return Err(Error::Internal("cones left pixels uncovered".into()));
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
            marked: tile_by_lists && plan.marks_near_ties(),
        })?;
        stats.readback_ms += ms(started);
    }

    stats.radii_tried = plan.radii_tried(final_attempt);
    stats.groups = plan.groups(final_attempt, drawn_by_tiles);
    let radii = plan.radii(final_attempt);
    stats.cones = radii.clone().count();
    if stats.cones > 0 {
        stats.radius_min = radii.clone().fold(f64::INFINITY, f64::min);
        stats.radius_max = radii.clone().fold(0.0, f64::max);
        stats.radius_mean = radii.sum::<f64>() / stats.cones as f64;
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
