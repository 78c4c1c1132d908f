//! Vector Voronoi cells: the Euclidean cells of point sites as convex
//! polygons clipped to a rectangle, built from the exact Delaunay
//! triangulation.
//!
//! A site's cell is the intersection of the half-planes nearer to it than to
//! each of its Delaunay neighbours, so the triangulation's exact predicates
//! decide which bisectors bound a cell, and exact clipping places them: every
//! corner is the double nearest the exact corner, so neighbouring cells share
//! their corners bit for bit and the cells form a valid coverage of the
//! rectangle. Degenerate inputs take the same path: co-circular sites add
//! bisectors through a shared corner, which clip nothing; repeated sites
//! share the first one's cell; sites on one line (or fewer than three
//! distinct) are neighbours in their order along it; sites outside the
//! rectangle may have an empty cell.

use crate::memory::Gather;
use std::collections::HashMap;

use glam::DVec2;

use super::delaunay::{delaunay_checked, DelaunayOptions};
use crate::{
    error::Result,
    geometry::{
        cell::Rect,
        exact::cell::CellBuilder,
        exact::predicates::orient,
        frame::{check_sites, Checked},
    },
    Backend, Control,
};

/// Where the cells are built: the rectangle they are clipped to, and the
/// work's progress (cells built of all) and cancellation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CellsOptions {
    pub rect: Rect,
    pub control: Control,
}

impl CellsOptions {
    /// Cells clipped to `rect`.
    pub fn new(rect: Rect) -> Self {
        Self {
            rect,
            control: Control::new(),
        }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// The cells of a set of sites.
#[derive(Clone, Debug, Default)]
pub struct Cells {
    /// Per input site, its cell's corners counter-clockwise; empty where the
    /// cell misses the rectangle. A repeated site has the cell of the first
    /// site equal to it.
    pub polygons: Vec<Vec<DVec2>>,
    /// Repeated sites, each as (repeat, first).
    pub duplicates: Vec<[u32; 2]>,
}

impl Cells {
    /// The area of cell `i` (taken about its first corner, which keeps far
    /// coordinates from cancelling).
    pub fn area(&self, i: usize) -> f64 {
        let c = &self.polygons[i];
        let Some(&o) = c.first() else { return 0.0 };
        let n = c.len();
        0.5 * (0..n)
            .map(|k| (c[k] - o).perp_dot(c[(k + 1) % n] - o))
            .sum::<f64>()
    }
}

/// The Voronoi cells of `sites` (finite) clipped to `options.rect`, reporting
/// the cells built to `options.control`.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::cells::{voronoi_cells, CellsOptions}, geometry::cell::Rect};
///
/// let sites = [DVec2::new(1.0, 1.0), DVec2::new(3.0, 1.0), DVec2::new(2.0, 3.0)];
/// let rect = Rect { lo: DVec2::ZERO, hi: DVec2::new(4.0, 4.0) };
/// let cells = voronoi_cells(&pixgeo::Backend::Cpu, &sites, &CellsOptions::new(rect))?;
/// let total: f64 = (0..3).map(|i| cells.area(i)).sum();
/// assert!((total - 16.0).abs() < 1e-12);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi_cells(backend: &Backend, sites: &[DVec2], options: &CellsOptions) -> Result<Cells> {
    options.control.run(|| cells_of(backend, sites, options))
}

fn cells_of(backend: &Backend, sites: &[DVec2], options: &CellsOptions) -> Result<Cells> {
    let rect = &options.rect;
    if sites.is_empty() {
        rect.check()?;
        return Ok(Cells::default());
    }
    check_sites(sites)?;
    rect.check()?;
    // The first of equal sites stands for them all.
    let mut first: HashMap<(u64, u64), u32> = HashMap::new();
    let mut duplicates = Vec::new();
    let mut distinct = Vec::new();
    for (i, p) in sites.iter().enumerate() {
        let key = ((p.x + 0.0).to_bits(), (p.y + 0.0).to_bits());
        match first.get(&key) {
            Some(&f) => duplicates.push([i as u32, f]),
            None => {
                first.insert(key, i as u32);
                distinct.push(i as u32);
            }
        }
    }
    let neighbours = neighbours(backend, sites, &distinct)?;
    let jobs: Vec<(u32, &[u32])> = distinct
        .iter()
        .zip(&neighbours)
        .map(|(&i, around)| (i, &around[..]))
        .gather("jobs")?;
    let built = CellBuilder::new(sites, *rect).cells(&jobs, &options.control)?;
    let mut polygons = crate::memory::filled(sites.len(), Vec::new(), "cells")?;
    for (&i, cell) in distinct.iter().zip(built) {
        polygons[i as usize] = cell;
    }
    for &[repeat, f] in &duplicates {
        polygons[repeat as usize] = polygons[f as usize].clone();
    }
    Ok(Cells {
        polygons,
        duplicates,
    })
}

/// Each distinct site's Voronoi neighbours (input indices).
fn neighbours(backend: &Backend, sites: &[DVec2], distinct: &[u32]) -> Result<Vec<Vec<u32>>> {
    let at = |i: u32| sites[i as usize];
    let on_one_line = distinct.len() < 3 || {
        let (a, b) = (at(distinct[0]), at(distinct[1]));
        distinct[2..].iter().all(|&c| orient(a, b, at(c)) == 0.0)
    };
    let slot: HashMap<u32, usize> = distinct
        .iter()
        .enumerate()
        .map(|(k, &i)| (i, k))
        .gather("slot")?;
    let mut around = crate::memory::filled(distinct.len(), Vec::new(), "the sites' neighbours")?;
    if on_one_line {
        // Neighbours along the line, in the order of the first two sites.
        let mut order: Vec<u32> = distinct.to_vec();
        if let [a, b, ..] = order[..] {
            let (origin, direction) = (at(a), at(b) - at(a));
            order.sort_by(|&p, &q| {
                (at(p) - origin)
                    .dot(direction)
                    .total_cmp(&(at(q) - origin).dot(direction))
            });
        }
        for pair in order.windows(2) {
            around[slot[&pair[0]]].push(pair[1]);
            around[slot[&pair[1]]].push(pair[0]);
        }
        return Ok(around);
    }
    // The distinct sites of a list checked where it entered.
    let points: Vec<DVec2> = distinct.iter().map(|&i| at(i)).gather("points")?;
    let options = DelaunayOptions::default();
    let mesh = delaunay_checked(backend, Checked::derived(&points), &options, &mut |_, _| {})?;
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            around[a].push(distinct[b]);
            around[b].push(distinct[a]);
        }
    }
    for list in &mut around {
        list.sort_unstable();
        list.dedup();
    }
    Ok(around)
}
