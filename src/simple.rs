//! One call per problem, for the common case: points in, an answer out, on a
//! machine created once and shared. Each call names the full entry in
//! [`algorithms`](crate::algorithms) that takes a [`Machine`] and options.
//!
//! ```
//! use glam::DVec2;
//!
//! let points = [DVec2::new(10.0, 20.0), DVec2::new(40.5, 7.0), DVec2::new(30.0, 40.0)];
//! let diagram = pixgeo::voronoi(&points, 64, 48)?;
//! assert_eq!(diagram.labels[20 * 64 + 10], 0);
//! let world = diagram.frame.to_world(DVec2::new(10.0, 20.0)); // pixel (10, 20)'s centre
//! let mesh = pixgeo::delaunay(&points)?;
//! assert_eq!(mesh.triangles.len(), 1);
//! # Ok::<(), pixgeo::Error>(())
//! ```

use std::sync::Mutex;

use glam::DVec2;

use crate::{
    algorithms::{
        alpha_hull::{self, AlphaHull, AlphaOptions},
        area::{self, AreaAnswer, AreaOptions, Extreme},
        delaunay::{self, Delaunay, DelaunayOptions},
        distances::{self, Answer, Hausdorff},
        higher_order::{self, Furthest, KNearest, KNearestOptions},
        homothet::{self, EmptyOptions, EncloseOptions, HomothetAnswer, Unit},
        settle::{self, Refined, SettleOptions},
        voronoi::{self as diagram, VoronoiDiagram, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Backend, Machine, MachineOptions, Need, Result,
};

static DEFAULT: Mutex<Option<Machine>> = Mutex::new(None);

/// Runs `f` on the backend the calls of this module share, chosen by
/// [`Backend::choose`]'s rule for `need` from the environment
/// (`PIXGEO_DEVICE`, `PIXGEO_VALIDATION`): the CPU, or a machine made on
/// first use and kept for the life of the process. Calls from several
/// threads take turns on the machine; threads that should compute at once
/// make a [`Machine`] each. A failed creation is not kept: the next call
/// tries again.
pub fn with_default_backend<T>(need: Need, f: impl FnOnce(&Backend) -> Result<T>) -> Result<T> {
    let options = MachineOptions::from_env();
    if Backend::cpu_first(&options, need)? {
        return f(&Backend::Cpu);
    }
    let mut slot = DEFAULT.lock().unwrap_or_else(|e| e.into_inner());
    if slot.is_none() {
        match Machine::new(&options) {
            Ok(machine) => *slot = Some(machine),
            Err(e) => return f(&Backend::instead_of_device(&options, need, e)?.backend()),
        }
    }
    f(&Backend::from(slot.as_ref().expect("made above")))
}

/// Runs `f` on the machine the calls of this module share
/// ([`with_default_backend`]), for work drawn on a Vulkan device.
///
/// ```
/// let name = pixgeo::with_default_machine(|machine| Ok(machine.device_name().to_string()))?;
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn with_default_machine<T>(f: impl FnOnce(&Machine) -> Result<T>) -> Result<T> {
    let need = Need::Drawing("this call");
    with_default_backend(need, |backend| f(backend.device_for("this call")?))
}

/// The exact Euclidean Voronoi diagram of `points` on `width` x `height`
/// pixels, pixel (i, j) centred at world point (i, j): every pixel's nearest
/// point and its distance. Other metrics, bounding boxes, windows and fans:
/// [`algorithms::voronoi::voronoi`](crate::algorithms::voronoi::voronoi).
///
/// ```
/// # use glam::DVec2;
/// let d = pixgeo::voronoi(&[DVec2::new(1.0, 1.0), DVec2::new(6.0, 2.0)], 8, 4)?;
/// assert_eq!((d.labels[0], d.labels[7]), (0, 1));
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi(points: &[DVec2], width: u32, height: u32) -> Result<VoronoiDiagram> {
    let options = VoronoiOptions::exact(Frame::pixels(width, height)?);
    with_default_backend(Need::CpuUnlessGpu, |backend| {
        diagram::voronoi(backend, points, &options)
    })
}

/// Every pixel's `k` nearest points in order, exact (thesis §3.7), on pixels
/// as [`voronoi`] lays them out. Options:
/// [`algorithms::higher_order::k_nearest`](crate::algorithms::higher_order::k_nearest).
///
/// ```
/// # use glam::DVec2;
/// let near = pixgeo::k_nearest(&[DVec2::new(1.0, 1.0), DVec2::new(6.0, 2.0)], 8, 4, 2)?;
/// assert_eq!(near.level_labels(1)[0], 1); // the second nearest of pixel (0, 0)
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn k_nearest(points: &[DVec2], width: u32, height: u32, k: u32) -> Result<KNearest> {
    let frame = Frame::pixels(width, height)?;
    let options = KNearestOptions::exact(frame, k);
    with_default_backend(Need::DeviceIfAny, |backend| {
        higher_order::k_nearest(backend, points, &options)
    })
}

/// Every pixel's furthest point (thesis §3.7.1), on pixels as [`voronoi`] lays
/// them out.
///
/// ```
/// # use glam::DVec2;
/// let far = pixgeo::furthest(&[DVec2::new(1.0, 1.0), DVec2::new(6.0, 2.0)], 8, 4)?;
/// assert_eq!(far.labels[0], 1);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn furthest(points: &[DVec2], width: u32, height: u32) -> Result<Furthest> {
    let frame = Frame::pixels(width, height)?;
    with_default_backend(Need::CpuUnlessGpu, |backend| {
        higher_order::furthest(backend, points, &frame, Metric::L2)
    })
}

/// The Delaunay triangulation of `points` by flooding (Cao, Edelsbrunner and
/// Tan 2015), made Delaunay by exact flips; repeated points are reported and
/// left out.
///
/// ```
/// # use glam::DVec2;
/// let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y, DVec2::splat(0.5)];
/// assert_eq!(pixgeo::delaunay(&square)?.triangles.len(), 4);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn delaunay(points: &[DVec2]) -> Result<Delaunay> {
    with_default_backend(Need::CpuUnlessGpu, |b| {
        delaunay::delaunay(b, points, &DelaunayOptions::default())
    })
}

/// The Hausdorff distance between point sets `a` and `b`, both directions,
/// exact (thesis §3.11.1).
///
/// ```
/// # use glam::DVec2;
/// let h = pixgeo::hausdorff(&[DVec2::ZERO], &[DVec2::new(3.0, 4.0), DVec2::X])?;
/// assert_eq!(h.b_to_a.pair.distance, 5.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn hausdorff(a: &[DVec2], b: &[DVec2]) -> Result<Hausdorff> {
    with_default_backend(Need::CpuUnlessGpu, |backend| {
        distances::hausdorff(backend, a, b, &distances::HausdorffOptions::default())
    })
}

/// The two points farthest apart, exact (thesis §3.11.2).
///
/// ```
/// # use glam::DVec2;
/// let d = pixgeo::diameter(&[DVec2::ZERO, DVec2::X, DVec2::new(3.0, 4.0)])?;
/// assert_eq!(d.pair.distance, 5.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn diameter(points: &[DVec2]) -> Result<Answer> {
    with_default_machine(|m| distances::diameter(m, points, None))
}

/// The smallest circle holding every point (thesis ch. 4), exact: `centre`
/// and radius `scale` in [`HomothetAnswer::exact`]. Polygons and `k` of n:
/// [`algorithms::homothet::enclose`](crate::algorithms::homothet::enclose).
///
/// ```
/// # use glam::DVec2;
/// let c = pixgeo::enclosing_circle(&[DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0)])?;
/// assert!((c.exact.scale - 2.5).abs() < 1e-12);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn enclosing_circle(points: &[DVec2]) -> Result<HomothetAnswer> {
    with_default_backend(Need::CpuUnlessGpu, |backend| {
        homothet::enclose(backend, points, &EncloseOptions::new(Unit::Circle))
    })
}

/// The largest circle centred in the points' bounding box that holds none of
/// them in its interior (thesis ch. 5), exact. Regions and polygons:
/// [`algorithms::homothet::largest_empty`](crate::algorithms::homothet::largest_empty).
///
/// ```
/// # use glam::DVec2;
/// let c = pixgeo::largest_empty_circle(&[DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0)])?;
/// assert!((c.exact.scale - 3.125).abs() < 1e-12);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn largest_empty_circle(points: &[DVec2]) -> Result<HomothetAnswer> {
    let options = EmptyOptions::new(Unit::Circle);
    with_default_machine(|m| homothet::largest_empty(m, points, &options))
}

/// The α-hull of `points` (thesis §3.12) on a picture of 512 pixels along its
/// longer side: α = 0 the convex hull, α > 0 discs of radius 1/α holding
/// every point, α < 0 discs of radius 1/|α| holding none.
///
/// ```
/// # use glam::DVec2;
/// let hull = pixgeo::alpha_hull(&[DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::splat(0.2)], 0.0)?;
/// assert_eq!(hull.boundary_sites.len(), 3);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn alpha_hull(points: &[DVec2], alpha: f64) -> Result<AlphaHull> {
    with_default_machine(|m| alpha_hull::alpha_hull(m, points, &AlphaOptions::new(alpha)))
}

/// The smallest or largest triangle with three of `points` as vertices, exact
/// (the rotational sweep, on the CPU).
///
/// ```
/// # use glam::DVec2;
/// use pixgeo::algorithms::area::Extreme;
/// let points = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0), DVec2::new(1.0, 1.0)];
/// assert_eq!(pixgeo::extremal_triangle(&points, Extreme::Largest)?.area, 6.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn extremal_triangle(points: &[DVec2], extreme: Extreme) -> Result<AreaAnswer> {
    area::extremal_triangle(&Backend::Cpu, points, &AreaOptions::new(extreme))
}

/// The smallest or largest simple quadrangle with four of `points` as
/// vertices, exact (the rotational sweep, on the CPU).
///
/// ```
/// # use glam::DVec2;
/// use pixgeo::algorithms::area::Extreme;
/// let points = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(4.0, 3.0), DVec2::new(0.0, 3.0)];
/// assert_eq!(pixgeo::extremal_quadrangle(&points, Extreme::Smallest)?.area, 12.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn extremal_quadrangle(points: &[DVec2], extreme: Extreme) -> Result<AreaAnswer> {
    area::extremal_quadrangle(&Backend::Cpu, points, &AreaOptions::new(extreme))
}

/// The settle point (thesis §3.10): where a new point among `rivals` would be
/// nearest to the largest area of the `width` x `height` pixels (laid out as
/// in [`voronoi`]), refined to an exact position and area.
///
/// ```
/// # use glam::DVec2;
/// let best = pixgeo::settle(&[DVec2::new(2.0, 2.0), DVec2::new(60.0, 40.0)], 64, 48)?;
/// println!("at {:?}, winning {}", best.position, best.area);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn settle(rivals: &[DVec2], width: u32, height: u32) -> Result<Refined> {
    let options = SettleOptions::new(Frame::pixels(width, height)?);
    let map = with_default_backend(Need::DeviceIfAny, |backend| {
        settle::potential_areas(backend, rivals, &[], &options)
    })?;
    settle::refine(rivals, &[], &options.frame, &map.leaders(8))
}
