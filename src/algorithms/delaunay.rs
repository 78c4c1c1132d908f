//! The Delaunay triangulation of real points from a digital Voronoi diagram
//! (Cao, Edelsbrunner and Tan 2015; the pipeline of GPU-DT):
//!
//! 1. **grid**: the points' bounding box is laid over a texture; each pixel
//!    holding points takes one of them as its seed;
//! 2. **colouring** and **repair** ([`super::flooding::flood`]): the flooded
//!    digital Voronoi diagram of the seeds;
//! 3. **dualization** ([`super::flooding::dualize`]): its dual, a valid
//!    triangulation of the seeds at their pixel centres (the paper's theorem);
//! 4. **shifting**: the boundary is made convex, then every seed moves to its
//!    true position where its triangles stay counter-clockwise (and the hull
//!    convex); a seed that cannot is taken out and its hole refilled;
//! 5. **flips**: Lawson's flips until every edge of the seeds' triangulation
//!    is locally Delaunay (its hull is convex, so it is then Delaunay);
//! 6. **insertion**: the seeds taken out and the points that shared a pixel
//!    are inserted by a walk from their pixel's seed, each legalized by
//!    flips, which keeps the triangulation Delaunay.
//!
//! Every step keeps a valid triangulation and every predicate is exact, so
//! the result is a Delaunay triangulation of the input, whatever the grid.
//! The pixel centres are an exact scaled integer lattice (the cell side has a
//! three-bit mantissa and the origin is a multiple of it), so the dual's
//! orientations hold in floating point too.
//!
//! Few, sparse points can make the dual invalid: an inner point's region then
//! reaches the texture's border twice and meets the one outside region twice.
//! The mesh notices, and the points are inserted one by one in Hilbert order
//! instead ([`DelaunayStats::incremental`] says why).

use super::{envelope::hilbert_index, ms};
use crate::memory::Gather;
use std::time::Instant;

use glam::DVec2;

use crate::{
    algorithms::flooding::{dualize, flood, FloodingStats},
    cancel::Watch,
    error::{Error, Result},
    geometry::seed::Seed,
    geometry::{
        exact::predicates::orient,
        frame::{distinct_by, Checked},
        mesh::Mesh,
        scale,
        triangulation::{validate, Validity, DUMMY},
        Frame,
    },
    machine::Machine,
    Backend, Control,
};

/// Empty pixels kept around the points, so that the outside never pinches a
/// region against the texture's border.
pub(crate) const MARGIN: u32 = 4;

/// How to triangulate.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct DelaunayOptions {
    /// Texture pixels along the longer side of the bounding box (margins
    /// included); `None` chooses `default_grid`. The CPU, which floods no
    /// texture, checks it and leaves it unused.
    pub grid: Option<u32>,
    /// Check conditions I–III on the digital triangulation (on a device;
    /// the CPU makes none).
    pub check: bool,
    /// Progress, `(done, STEPS)` as each of the five steps ends (flooding,
    /// dualization, moving the seeds, flips, insertion), and cancellation.
    pub control: Control,
}

impl DelaunayOptions {
    pub fn grid(self, grid: Option<u32>) -> Self {
        Self { grid, ..self }
    }

    pub fn check(self, check: bool) -> Self {
        Self { check, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// The texture side from the number of points, as GPU-DT chooses it: about
/// one pixel per point (between 64 and 8192 pixels a side). Finer grids leave
/// fewer points to insert but cost more to flood and dualize than they save
/// (measured on lavapipe from 10⁴ to 10⁶ points).
pub(crate) fn default_grid(n: usize) -> u32 {
    ((n as f64).sqrt().ceil() as u32 + 2 * MARGIN).clamp(64, 8192)
}

/// What each phase did and took.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct DelaunayStats {
    pub width: u32,
    pub height: u32,
    /// The side of a pixel in input units.
    pub cell: f64,
    /// Distinct points, and those that are seeds.
    pub points: usize,
    pub seeds: usize,
    pub flooding: FloodingStats,
    pub dualize_ms: f64,
    /// Triangles of the digital triangulation.
    pub digital_triangles: usize,
    /// Shifting: flips that made the hull convex, seeds moved in place, seeds
    /// taken out.
    pub shift_ms: f64,
    pub hull_flips: usize,
    pub moved: usize,
    pub taken_out: usize,
    /// Insertion: points inserted and the flips that legalized them.
    pub insert_ms: f64,
    pub inserted: usize,
    pub insertion_flips: usize,
    /// Lawson's flips over the seeds' triangulation, before insertion.
    pub flip_ms: f64,
    pub delaunay_flips: usize,
    /// Why the triangulation was built by insertion alone, if it was: too
    /// few seeds, or too few that could stay in place.
    pub incremental: Option<String>,
}

/// A Delaunay triangulation.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Delaunay {
    /// Counter-clockwise triangles, as indices into the input.
    pub triangles: Vec<[u32; 3]>,
    /// Repeated points, each as (dropped, kept): the first of equal points is
    /// kept.
    pub duplicates: Vec<[u32; 2]>,
    /// Conditions I–III on the digital triangulation, when asked for.
    pub digital_validity: Option<Validity>,
    pub stats: DelaunayStats,
    /// The flooded digital diagram, on a device; `None` on the CPU.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub digital: Option<DigitalDiagram>,
}

impl Delaunay {
    /// The input points in the triangulation: all but the repeats, in order.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn distinct(&self) -> Vec<u32> {
        let n = (self.stats.points + self.duplicates.len()) as u32;
        let mut repeats = self.duplicates.iter().map(|d| d[0]).peekable();
        (0..n)
            .filter(|&v| repeats.next_if_eq(&v).is_none())
            .collect()
    }
}

/// The flooded digital Voronoi diagram behind a triangulation, for pictures.
#[derive(Clone, Debug, Default)]
pub struct DigitalDiagram {
    pub width: u32,
    pub height: u32,
    /// Pixel (0, 0)'s centre and the pixel side, in input units.
    pub origin: DVec2,
    pub cell: f64,
    /// Seed index per pixel, row-major; seed `i` is input point `seeds[i]`.
    pub labels: Vec<u32>,
    pub seeds: Vec<u32>,
    /// The dual, over input indices and [`DUMMY`].
    pub triangles: Vec<[u32; 3]>,
}

impl DigitalDiagram {
    /// Where input point `p` falls on the texture, in pixels.
    pub fn to_pixels(&self, p: DVec2) -> DVec2 {
        (p - self.origin) / self.cell
    }

    /// The texture as a [`Frame`] over the input's coordinates.
    pub fn frame(&self) -> Frame {
        Frame {
            width: self.width,
            height: self.height,
            origin: self.origin - DVec2::splat(0.5 * self.cell),
            scale: 1.0 / self.cell,
        }
    }
}

/// The smallest value q · 2^k (q in 4..=8) at least `x`, for a positive normal
/// `x`: products of small integers and such a value are exact.
fn three_bit_ceil(x: f64) -> f64 {
    let k = x.log2().floor() as i32 - 2;
    (4..=8)
        .map(|q| q as f64 * 2f64.powi(k))
        .find(|&c| c >= x)
        .unwrap_or(8.0 * 2f64.powi(k))
}

/// The Delaunay triangulation of `points` (at least three, not all on one
/// line; repeated points are reported and dropped). Any finite coordinates are
/// taken exactly: points whose magnitudes would overflow or underflow the exact
/// predicates are triangulated scaled by a power of two, which changes no
/// triangle. On [`Backend::Cpu`] the points are inserted in Hilbert order
/// alone; both routes give the same triangles, ties included (co-circular
/// points are decided by the input order, [`crate::geometry`]'s mesh).
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::delaunay::{delaunay, DelaunayOptions};
///
/// let points: Vec<DVec2> = (0..100).map(|i| DVec2::new((i % 10) as f64, (i / 10) as f64 * 1.1)).collect();
/// let options = DelaunayOptions::default().grid(Some(32));
/// let mesh = pixgeo::with_default_backend(pixgeo::Need::DeviceIfAny, |b| delaunay(b, &points, &options))?;
/// assert_eq!(mesh.triangles.len(), 2 * 9 * 9); // a lattice of 10 x 10 points
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn delaunay(
    backend: &Backend,
    points: &[DVec2],
    options: &DelaunayOptions,
) -> Result<Delaunay> {
    options.control.run(|| {
        delaunay_checked(
            backend,
            Checked::new(points)?,
            options,
            &mut |done, total| options.control.report(done, total),
        )
    })
}

/// [`delaunay`] of points checked where they entered.
pub(crate) fn delaunay_checked(
    backend: &Backend,
    points: Checked<'_>,
    options: &DelaunayOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Delaunay> {
    let points = points.sites();
    let k = scale::incircle_exponent(points)?;
    let machine = backend.machine();
    if k == 0 {
        return triangulate(machine, points, options, progress);
    }
    let mut result = triangulate(machine, &scale::scaled(points, k), options, progress)?;
    if let Some(d) = &mut result.digital {
        d.origin = DVec2::new(
            scale::times_power_of_two(d.origin.x, -k),
            scale::times_power_of_two(d.origin.y, -k),
        );
        d.cell = scale::times_power_of_two(d.cell, -k);
        result.stats.cell = d.cell;
    }
    Ok(result)
}

/// The steps [`delaunay_with_progress`] reports.
pub(crate) const STEPS: u64 = 5;

/// Points moved or inserted between looks at the cancel flag.
const WATCH_EVERY: usize = 1 << 14;

/// The distinct points of an input, in an order of the triangulation's.
struct Distinct {
    /// Input indices, the first of equal points.
    unique: Vec<u32>,
    /// (dropped, kept), sorted.
    duplicates: Vec<[u32; 2]>,
    /// The points of `unique`.
    real: Vec<DVec2>,
}

/// The distinct points (the first of equal ones) in `key`'s order, or why
/// they have no triangulation.
fn distinct_points<K: Ord + Send>(
    points: &[DVec2],
    key: impl Fn(DVec2) -> K + Sync,
) -> Result<Distinct> {
    let (unique, duplicates) = distinct_by(points, 0..points.len() as u32, key);
    if unique.len() < 3 {
        return Err(Error::too_few(
            3,
            unique.len(),
            format!(
                "a triangulation needs three distinct points; there are {}",
                unique.len()
            ),
        ));
    }
    let real: Vec<DVec2> = unique.iter().map(|&i| points[i as usize]).gather("real")?;
    if !(2..real.len()).any(|k| orient(real[0], real[1], real[k]) != 0.0) {
        return Err(Error::degenerate(
            "all points lie on one line: there is no triangle".into(),
        ));
    }
    Ok(Distinct {
        unique,
        duplicates,
        real,
    })
}

/// The finite triangles of `mesh` over input indices (`unique` maps the
/// mesh's vertices to them), each starting at its least index, sorted: the
/// same list whichever route built the mesh.
fn canonical_triangles(mesh: &Mesh, unique: &[u32]) -> Result<Vec<[u32; 3]>> {
    let rotated = mesh
        .triangles()
        .into_iter()
        .filter(|t| !t.contains(&DUMMY))
        .map(|t| {
            let [a, b, c] = t.map(|v| unique[v as usize]);
            if a < b && a < c {
                [a, b, c]
            } else if b < c {
                [b, c, a]
            } else {
                [c, a, b]
            }
        });
    // A counting sort by the least index (a vertex is the least of about
    // two triangles), then each run in order.
    let n = unique.iter().max().map_or(0, |&m| m as usize + 1);
    let mut start = crate::memory::filled(n + 1, 0u32, "triangles by vertex")?;
    let rotated: Vec<[u32; 3]> = rotated
        .inspect(|t| start[t[0] as usize + 1] += 1)
        .gather("rotated")?;
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut sorted = crate::memory::filled(rotated.len(), [0; 3], "sorted triangles")?;
    for t in rotated {
        let at = &mut next[t[0] as usize];
        sorted[*at as usize] = t;
        *at += 1;
    }
    for run in start.windows(2) {
        sorted[run[0] as usize..run[1] as usize].sort_unstable();
    }
    Ok(sorted)
}

/// The CPU route: the distinct points inserted in Hilbert order.
fn by_insertion(points: &[DVec2], progress: &mut dyn FnMut(u64, u64)) -> Result<Delaunay> {
    let watch = Watch::current();
    let (lo, hi) = bounds(points);
    let scale = 65535.0 / (hi - lo).max_element();
    let Distinct {
        unique,
        duplicates,
        real,
    } = distinct_points(points, |p| {
        let g = (p - lo) * scale;
        hilbert_index(g.x as u32, g.y as u32)
    })?;
    let started = Instant::now();
    let (mesh, flips) = insert_all(real, &unique, &watch)?;
    let stats = DelaunayStats {
        points: unique.len(),
        insert_ms: ms(started),
        inserted: unique.len() - 3,
        insertion_flips: flips,
        incremental: Some("on the CPU, by insertion alone".into()),
        ..Default::default()
    };
    progress(STEPS, STEPS);
    Ok(Delaunay {
        triangles: canonical_triangles(&mesh, &unique)?,
        duplicates,
        digital_validity: None,
        stats,
        digital: None,
    })
}

fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points.iter().fold((points[0], points[0]), |(lo, hi), &p| {
        (lo.min(p), hi.max(p))
    })
}

#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn triangulate(
    machine: Option<&Machine>,
    points: &[DVec2],
    options: &DelaunayOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Delaunay> {
    // Triangles (about two per point) are numbered in 32 bits too.
    if points.len() >= u32::MAX as usize / 2 {
        return Err(Error::out_of_range("too many points".into()));
    }
    let (lo, hi) = bounds(points);
    let span = (hi - lo).max_element();
    if span == 0.0 {
        return Err(Error::degenerate(format!(
            "all {} points are one point: a triangulation needs three distinct points not on one line",
            points.len()
        )));
    }
    // The grid is checked on both routes, so that they take the same options.
    let side = options.grid.unwrap_or_else(|| default_grid(points.len()));
    // The texture comes out at most two pixels wider than the grid.
    if side > crate::algorithms::flooding::MAX_SIDE - 2 {
        return Err(Error::out_of_range(format!(
            "a grid of {side} pixels is larger than {}",
            crate::algorithms::flooding::MAX_SIDE - 2
        )));
    }
    if side < 2 * MARGIN + 2 {
        return Err(Error::out_of_range(format!(
            "a grid of {side} pixels leaves no room inside its {MARGIN}-pixel margins"
        )));
    }
    let Some(machine) = machine else {
        return by_insertion(points, progress);
    };
    let watch = Watch::current();
    // 1. The grid over the bounding box.
    let cell = three_bit_ceil(span / (side - 2 * MARGIN - 1) as f64);
    let first = (lo / cell).floor() - MARGIN as f64;
    let origin = first * cell;
    let width = ((hi.x / cell).floor() - first.x) as u32 + MARGIN + 2;
    let height = ((hi.y / cell).floor() - first.y) as u32 + MARGIN + 2;
    let pixel_of = |p: DVec2| -> [i32; 2] {
        let g = ((p - origin) / cell).round();
        [
            (g.x as i32).clamp(0, width as i32 - 1),
            (g.y as i32).clamp(0, height as i32 - 1),
        ]
    };
    // The distinct points in Hilbert order over the pixels, so that neighbours
    // in the mesh are mostly neighbours in memory; equal points sort together.
    let Distinct {
        unique,
        duplicates,
        real,
    } = distinct_points(points, |p| {
        let s = pixel_of(p);
        hilbert_index(s[0] as u32, s[1] as u32)
    })?;
    let mut stats = DelaunayStats {
        points: real.len(),
        width,
        height,
        cell,
        ..Default::default()
    };
    let mut seed_at =
        crate::memory::filled(width as usize * height as usize, u32::MAX, "seeds' pixels")?;
    let mut seeds: Vec<Seed> = Vec::new();
    let mut seed_point: Vec<u32> = Vec::new();
    for (k, &p) in real.iter().enumerate() {
        let s = pixel_of(p);
        let slot = &mut seed_at[s[1] as usize * width as usize + s[0] as usize];
        if *slot == u32::MAX {
            *slot = seeds.len() as u32;
            seeds.push(s);
            seed_point.push(k as u32);
        }
    }
    stats.seeds = seeds.len();

    // 2–3. Flooding and its dual.
    let flooding = flood(machine, width, height, &seeds)?;
    stats.flooding = flooding.stats.clone();
    progress(1, STEPS);
    let started = Instant::now();
    let dual = dualize(machine, &flooding.labels, width, height)?;
    stats.dualize_ms = ms(started);
    progress(2, STEPS);
    stats.digital_triangles = dual.len();
    let to_point = |v: u32| {
        if v == DUMMY {
            DUMMY
        } else {
            seed_point[v as usize]
        }
    };
    let digital: Vec<[u32; 3]> = dual.iter().map(|t| t.map(to_point)).gather("digital")?;
    let centre = |s: Seed| origin + DVec2::new(s[0] as f64, s[1] as f64) * cell;
    let mut placed = real.clone();
    for (i, &s) in seeds.iter().enumerate() {
        placed[seed_point[i] as usize] = centre(s);
    }
    let digital_validity = options.check.then(|| {
        let centres: Vec<DVec2> = seeds.iter().map(|&s| centre(s)).collect();
        validate(&centres, &dual)
    });
    // 4. Shifting.
    let started = Instant::now();
    let seeds_collinear = !(2..seeds.len())
        .any(|k| orient(centre(seeds[0]), centre(seeds[1]), centre(seeds[k])) != 0.0);
    let mut mesh = None;
    let mut pending: Vec<u32> = Vec::new();
    if seeds.len() < 5 || seeds_collinear {
        stats.incremental = Some("fewer than five seeds, or all on one line".into());
    } else {
        match Mesh::new(placed, digital) {
            Err(e) => {
                stats.incremental = Some(format!("the digital triangulation is not valid: {e}"))
            }
            Ok(mut m) => {
                m.rank = unique.clone();
                stats.hull_flips = m.convexify();
                for (k, &v) in seed_point.iter().enumerate() {
                    if k % WATCH_EVERY == 0 {
                        watch.check()?;
                    }
                    if m.try_move(v, real[v as usize]) {
                        stats.moved += 1;
                    } else if m.remove(v).is_ok() {
                        pending.push(v);
                        stats.taken_out += 1;
                    } else {
                        stats.incremental = Some("fewer than five seeds stayed in place".into());
                        break;
                    }
                }
                if stats.incremental.is_none() {
                    mesh = Some(m);
                }
            }
        }
    }
    stats.shift_ms = ms(started);
    progress(3, STEPS);

    // 5. Lawson's flips make the seeds' triangulation (its hull convex)
    // Delaunay; inserting each other point and legalizing the edges it
    // makes keeps it so (insertion alone builds a Delaunay one too).
    watch.check()?;
    let started = Instant::now();
    if let Some(mesh) = &mut mesh {
        stats.delaunay_flips = mesh.make_delaunay();
    }
    stats.flip_ms = ms(started);
    progress(4, STEPS);

    // 6. Insertion, each point walking from its pixel's seed.
    let started = Instant::now();
    let mesh = match mesh {
        None => {
            let (built, flips) = insert_all(real.clone(), &unique, &watch)?;
            stats.inserted = real.len() - 3;
            stats.insertion_flips = flips;
            built
        }
        Some(mut mesh) => {
            let seed_of = |p: DVec2| {
                let s = pixel_of(p);
                seed_point[flooding.labels[s[1] as usize * width as usize + s[0] as usize] as usize]
            };
            let mut is_seed = crate::memory::filled(real.len(), false, "seed flags")?;
            for &v in &seed_point {
                is_seed[v as usize] = true;
            }
            pending.extend((0..real.len() as u32).filter(|&v| !is_seed[v as usize]));
            // In Hilbert order, each walk starting near the last point.
            pending.sort_unstable();
            let mut last = *seed_point
                .iter()
                .find(|&&v| mesh.contains(v))
                .expect("a mesh keeps four sites");
            for (k, &v) in pending.iter().enumerate() {
                if k % WATCH_EVERY == 0 {
                    watch.check()?;
                }
                let near = seed_of(real[v as usize]);
                let start = if mesh.contains(near) { near } else { last };
                mesh.points[v as usize] = real[v as usize];
                stats.insertion_flips += mesh.insert(v, start);
                last = v;
            }
            stats.inserted = pending.len();
            mesh
        }
    };
    stats.insert_ms = ms(started);
    let triangles = canonical_triangles(&mesh, &unique)?;
    progress(5, STEPS);
    Ok(Delaunay {
        triangles,
        duplicates,
        digital_validity,
        stats,
        digital: Some(DigitalDiagram {
            width,
            height,
            origin,
            cell,
            labels: flooding.labels,
            seeds: seed_point
                .iter()
                .map(|&v| unique[v as usize])
                .gather("labels")?,
            triangles: dual
                .iter()
                .map(|t| {
                    t.map(|v| {
                        if v == DUMMY {
                            DUMMY
                        } else {
                            unique[to_point(v) as usize]
                        }
                    })
                })
                .gather("triangles")?,
        }),
    })
}

/// A triangulation by insertion alone in Hilbert order, each point walking
/// from the one before, from a first counter-clockwise triangle (the points
/// are distinct and not all on one line).
fn insert_all(points: Vec<DVec2>, rank: &[u32], watch: &Watch) -> Result<(Mesh, usize)> {
    let (lo, hi) = bounds(&points);
    let scale = 65535.0 / (hi - lo).max_element();
    let mut order: Vec<u32> = (0..points.len() as u32).gather("order")?;
    order.sort_by_cached_key(|&v| {
        let g = (points[v as usize] - lo) * scale;
        hilbert_index(g.x as u32, g.y as u32)
    });
    let p = |k: usize| points[order[k] as usize];
    let c = (2..order.len())
        .find(|&k| orient(p(0), p(1), p(k)) != 0.0)
        .expect("the points are not all on one line");
    let first = if orient(p(0), p(1), p(c)) > 0.0 {
        [order[0], order[1], order[c]]
    } else {
        [order[1], order[0], order[c]]
    };
    let mut mesh = Mesh::triangle(points, first);
    mesh.rank = rank.to_vec();
    let mut flips = 0;
    let mut last = first[2];
    for (k, &v) in order.iter().filter(|v| !first.contains(v)).enumerate() {
        if k % WATCH_EVERY == 0 {
            watch.check()?;
        }
        flips += mesh.insert(v, last);
        last = v;
    }
    Ok((mesh, flips))
}
