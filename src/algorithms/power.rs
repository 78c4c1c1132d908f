//! Power (Laguerre) diagrams and their duals, regular (weighted Delaunay)
//! triangulations: each site `s` with weight `w` owns the points whose power
//! `|p - s|² - w` from it is least. A site whose cell is empty is hidden.
//!
//! The regular triangulation is built by incremental insertion in Hilbert
//! order with flips (Edelsbrunner and Shah 1996): a new site whose lifted
//! point lies on or above the lower hull is hidden at once; an illegal edge
//! whose quadrilateral is not convex takes out its reflex corner if three
//! triangles surround it, a site the new one hides. Every predicate is
//! exact ([`crate::geometry::exact::power`]).
//!
//! The cells are the rectangle clipped by the radical axes with each site's
//! neighbours in the triangulation, every decision exact and every corner
//! the double nearest the exact one, as for Voronoi cells
//! ([`crate::algorithms::cells`]).
//!
//! The diagram's labels walk the triangulation: from the last pixel's site
//! to a neighbour of less power until none has less (on a regular
//! triangulation this finds the least, as a power cell is convex and
//! crossing its edge lowers the power), then the lowest index among those
//! of equal power. The powers are the doubles nearest the exact ones.

use crate::memory::Gather;
use std::{
    cmp::Ordering,
    sync::atomic::{AtomicU64, Ordering as AtomicOrdering},
};

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    algorithms::cells::{Cells, CellsOptions},
    algorithms::envelope::hilbert_index,
    cancel::Watch,
    control::Control,
    geometry::{
        exact::cell::CellBuilder,
        exact::power::{compare_power, power_of, PowerEstimate, Weighted},
        exact::predicates::orient,
        frame::check_sites,
        mesh::Mesh,
        triangulation::DUMMY,
        Frame,
    },
    machine::PixelRect,
    Error, Result,
};

/// A regular triangulation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Regular {
    /// Counter-clockwise triangles, as indices into the input.
    pub triangles: Vec<[u32; 3]>,
    /// The sites whose power cells are empty, ascending. Of sites at one
    /// point, all but the heaviest (the first of equal weights) are hidden.
    pub hidden: Vec<u32>,
}

impl Regular {
    /// Each of `sites` sites' neighbours in the triangulation, ascending.
    pub fn neighbours(&self, sites: usize) -> Result<Vec<Vec<u32>>> {
        let mut neighbours = crate::memory::filled(sites, Vec::new(), "the sites' neighbours")?;
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                neighbours[a as usize].push(b);
                neighbours[b as usize].push(a);
            }
        }
        for n in &mut neighbours {
            n.sort_unstable();
            n.dedup();
        }
        Ok(neighbours)
    }

    /// The power cells of `sites`, whose regular triangulation this is,
    /// clipped to `options.rect`.
    pub fn cells(&self, sites: &[Weighted], options: &CellsOptions) -> Result<Cells> {
        options.control.run(|| self.cells_of(sites, options))
    }

    fn cells_of(&self, sites: &[Weighted], options: &CellsOptions) -> Result<Cells> {
        let rect = &options.rect;
        rect.check()?;
        let points: Vec<DVec2> = sites.iter().map(|s| s.at).gather("points")?;
        let weights: Vec<f64> = sites.iter().map(|s| s.weight).gather("weights")?;
        let neighbours = self.neighbours(sites.len())?;
        // A hidden site has no cell.
        let jobs: Vec<(u32, &[u32])> = neighbours
            .iter()
            .enumerate()
            .filter(|(i, _)| self.hidden.binary_search(&(*i as u32)).is_err())
            .map(|(i, around)| (i as u32, &around[..]))
            .gather("jobs")?;
        let built =
            CellBuilder::weighted(&points, &weights, *rect).cells(&jobs, &options.control)?;
        let mut polygons = crate::memory::filled(sites.len(), Vec::new(), "power cells")?;
        for (&(i, _), cell) in jobs.iter().zip(built) {
            polygons[i as usize] = cell;
        }
        Ok(Cells {
            polygons,
            duplicates: Vec::new(),
        })
    }
}

/// The power cells of `sites` (finite, not all on one line) clipped to
/// `rect`: per site its cell's corners counter-clockwise, each the double
/// nearest the exact corner, so that neighbouring cells share corners bit
/// for bit and the cells tile the rectangle; empty for a hidden site or a
/// cell with no area in the rectangle.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::{cells::CellsOptions, power::power_cells}, geometry::{cell::Rect, exact::power::Weighted}};
///
/// let at = [(1.0, 1.0, 0.0), (3.0, 1.0, 0.0), (2.0, 3.0, 0.0), (2.0, 1.6, -9.0)];
/// let sites: Vec<Weighted> = at
///     .iter()
///     .map(|&(x, y, weight)| Weighted { at: DVec2::new(x, y), weight })
///     .collect();
/// let rect = Rect { lo: DVec2::ZERO, hi: DVec2::new(4.0, 4.0) };
/// let cells = power_cells(&sites, &CellsOptions::new(rect))?;
/// assert!(cells.polygons[3].is_empty()); // too light to own a point
/// let total: f64 = (0..4).map(|i| cells.area(i)).sum();
/// assert!((total - 16.0).abs() < 1e-12);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn power_cells(sites: &[Weighted], options: &CellsOptions) -> Result<Cells> {
    regular_triangulation(sites)?.cells(sites, options)
}

/// The regular triangulation of `sites` (finite, not all on one line).
pub fn regular_triangulation(sites: &[Weighted]) -> Result<Regular> {
    let points: Vec<DVec2> = sites.iter().map(|s| s.at).gather("points")?;
    check_sites(&points)?;
    if let Some(i) = sites.iter().position(|s| !s.weight.is_finite()) {
        return Err(Error::not_finite(
            Some(i),
            format!("site {i}'s weight {} is not finite", sites[i].weight),
        ));
    }
    // Of sites at one point the heaviest stays.
    let mut order: Vec<u32> = (0..sites.len() as u32).gather("order")?;
    order.sort_by(|&a, &b| {
        let (p, q) = (sites[a as usize], sites[b as usize]);
        (p.at.x, p.at.y)
            .partial_cmp(&(q.at.x, q.at.y))
            .expect("finite")
            .then(q.weight.total_cmp(&p.weight))
            .then(a.cmp(&b))
    });
    let mut hidden = Vec::new();
    order.dedup_by(|later, kept| {
        let same = sites[*later as usize].at == sites[*kept as usize].at;
        if same {
            hidden.push(*later);
        }
        same
    });
    let (lo, hi) = order.iter().fold((points[0], points[0]), |(lo, hi), &v| {
        (lo.min(points[v as usize]), hi.max(points[v as usize]))
    });
    let scale = 65535.0 / (hi - lo).max_element().max(f64::MIN_POSITIVE);
    order.sort_by_cached_key(|&v| {
        let g = ((points[v as usize] - lo) * scale).min(DVec2::splat(65535.0));
        hilbert_index(g.x as u32, g.y as u32)
    });
    let p = |k: usize| points[order[k] as usize];
    let Some(c) = (2..order.len()).find(|&k| orient(p(0), p(1), p(k)) != 0.0) else {
        return Err(Error::degenerate(
            "the sites lie on one line: a regular triangulation needs three not in line".into(),
        ));
    };
    let first = if orient(p(0), p(1), p(c)) > 0.0 {
        [order[0], order[1], order[c]]
    } else {
        [order[1], order[0], order[c]]
    };
    let mut mesh = Mesh::triangle(points, first);
    mesh.weights = sites.iter().map(|s| s.weight).gather("mesh")?;
    let watch = Watch::current();
    let mut last = first[2];
    for (k, &v) in order.iter().filter(|v| !first.contains(v)).enumerate() {
        if k % (1 << 14) == 0 {
            watch.check()?;
        }
        if !mesh.contains(last) {
            last = *first
                .iter()
                .chain(order.iter())
                .find(|&&u| mesh.contains(u))
                .expect("sites");
        }
        mesh.insert(v, last);
        if mesh.contains(v) {
            last = v;
        }
    }
    hidden.extend(&mesh.hidden);
    hidden.sort_unstable();
    Ok(Regular {
        triangles: mesh
            .triangles()
            .into_iter()
            .filter(|t| !t.contains(&DUMMY))
            .gather("triangles")?,
        hidden,
    })
}

/// A power diagram on a raster.
#[derive(Clone, Debug)]
pub struct PowerDiagram {
    /// Each pixel's site of least power (ties to the lower index), row-major.
    pub labels: Vec<u32>,
    /// Each pixel centre's power from it, the double nearest the exact one.
    pub powers: Vec<f64>,
    /// How many sites share that least power at each pixel centre.
    pub ties: Vec<u32>,
    pub regular: Regular,
}

/// Where to draw a power diagram: the picture, a window of its pixels
/// (`None`: all of them), and the work's progress (rows done) and
/// cancellation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct PowerOptions {
    pub frame: Frame,
    pub window: Option<PixelRect>,
    pub control: Control,
}

impl PowerOptions {
    pub fn new(frame: Frame) -> Self {
        Self {
            frame,
            window: None,
            control: Control::new(),
        }
    }

    /// Only the pixels of `window`, a rectangle of the frame's: the same
    /// labels and powers bit for bit, so that windows computed apart tile
    /// into the whole diagram.
    pub fn window(self, window: Option<PixelRect>) -> Self {
        Self { window, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// The power diagram of `sites` at every pixel centre of `options.frame` (or
/// of its window).
pub fn power_diagram(sites: &[Weighted], options: &PowerOptions) -> Result<PowerDiagram> {
    options.control.run(|| diagram_of(sites, options))
}

fn diagram_of(sites: &[Weighted], options: &PowerOptions) -> Result<PowerDiagram> {
    let frame = &options.frame;
    let rect = frame.window_rect(options.window)?;
    let regular = regular_triangulation(sites)?;
    let neighbours = regular.neighbours(sites.len())?;
    let copies = copies(sites)?;
    let start = regular.triangles[0][0];
    let (watch, rows_done) = (Watch::current(), AtomicU64::new(0));
    let rows: Vec<Vec<(u32, u32, f64)>> = (rect.y..rect.y + rect.height)
        .into_par_iter()
        .map(|j| {
            watch.check()?;
            let mut at = start;
            let row = (rect.x..rect.x + rect.width).map(|i| {
                let p = frame.to_world(DVec2::new(i as f64, j as f64));
                let (least, ties) = least_power(p, sites, &neighbours, &copies, at);
                at = least;
                (least, ties, power_of(p, sites[least as usize]))
            });
            let row = row.gather("row")?;
            let done = rows_done.fetch_add(1, AtomicOrdering::Relaxed) + 1;
            options.control.report(done, rect.height as u64);
            Ok(row)
        })
        .collect::<Result<_>>()?;
    let pixels = rows.iter().flatten();
    Ok(PowerDiagram {
        labels: pixels.clone().map(|p| p.0).gather("pixels")?,
        ties: pixels.clone().map(|p| p.1).gather("labels")?,
        powers: pixels.map(|p| p.2).gather("ties")?,
        regular,
    })
}

/// For each site, how many later sites repeat it (the same point and
/// weight): the triangulation keeps the first alone.
fn copies(sites: &[Weighted]) -> Result<Vec<u32>> {
    let key = |i: u32| {
        let s = sites[i as usize];
        (
            (s.at.x + 0.0).to_bits(),
            (s.at.y + 0.0).to_bits(),
            (s.weight + 0.0).to_bits(),
        )
    };
    let mut order: Vec<u32> = (0..sites.len() as u32).gather("order")?;
    order.sort_unstable_by_key(|&i| (key(i), i));
    let mut copies = crate::memory::filled(sites.len(), 0, "the sites' copies")?;
    for run in order.chunk_by(|&a, &b| key(a) == key(b)) {
        copies[run[0] as usize] = run.len() as u32 - 1;
    }
    Ok(copies)
}

/// The site of least power at `p` (the lowest index of equals) and how many
/// share it, repeats counted ([`copies`]), walking from `from` over the
/// triangulation's edges.
fn least_power(
    p: DVec2,
    sites: &[Weighted],
    neighbours: &[Vec<u32>],
    copies: &[u32],
    from: u32,
) -> (u32, u32) {
    let mut at = from;
    // In doubles first: a neighbour surely of less power is the next step;
    // with every neighbour surely of more, `at` is the only least.
    'walk: loop {
        let here = PowerEstimate::of(p, sites[at as usize]);
        let mut unsure = false;
        for &n in &neighbours[at as usize] {
            match PowerEstimate::of(p, sites[n as usize]).compare(here) {
                Some(Ordering::Less) => {
                    at = n;
                    continue 'walk;
                }
                Some(_) => {}
                None => unsure = true,
            }
        }
        if !unsure {
            return (at, 1 + copies[at as usize]);
        }
        let less = |n: &&u32| compare_power(p, sites[**n as usize], sites[at as usize]).is_lt();
        match neighbours[at as usize].iter().find(less) {
            Some(&n) => at = n,
            None => break,
        }
    }
    // Sites of equal least power own p together; their cells meet there,
    // so each is reached from another over an edge.
    let mut equal = Vec::from([at]);
    let mut k = 0;
    while k < equal.len() {
        let s = equal[k];
        k += 1;
        for &n in &neighbours[s as usize] {
            let tie = compare_power(p, sites[n as usize], sites[at as usize]).is_eq();
            if tie && !equal.contains(&n) {
                equal.push(n);
            }
        }
    }
    let ties = equal.iter().map(|&e| 1 + copies[e as usize]).sum();
    (*equal.iter().min().expect("at least one"), ties)
}
