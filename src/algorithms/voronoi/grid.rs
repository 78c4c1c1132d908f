//! Exact Euclidean Voronoi labels found on the CPU, for devices whose
//! rasterizer is software and slower than a search ([`super::Method::Grid`]).
//!
//! Each block of 8 x 8 pixels gathers, from a grid of the sites, every site that
//! can be nearest to one of its pixels: those within the distance of the site
//! nearest the block's centre plus the block's diagonal, nearest the centre
//! first. Where sites are dense, each quarter of the block gathers a shorter
//! list from the block's.
//!
//! - A block (or quarter) whose nearest site beats every listed rival at all
//!   its pixels by more than the keys' error bound is that site's whole: a
//!   rival's key less the owner's is linear in the pixel, so its value at the
//!   centre bounds it over the block.
//! - Any other pixel takes its nearest in doubles, stopping at the first
//!   candidate whose lower bound over the block cannot beat it. Where its two
//!   nearest keys are not apart by more than their error bound (rounding, and
//!   the error of the sites' pixel coordinates), it is marked, and the
//!   certifier decides it exactly, as it decides the device's marked pixels.
//!
//! So every label is the exact nearest site.

use rayon::prelude::*;

use glam::DVec2;

use super::{Band, VoronoiOptions, VoronoiStats};
use crate::algorithms::certify::{Certifier, Region, MARK};
use crate::algorithms::ms;
use crate::{cancel::Watch, error::Result, geometry::metric::Metric};

/// Pixels a side of the blocks that share one candidate list.
const BLOCK: u32 = 8;

/// Relative slack on float distances and keys: far above their rounding.
const SLACK: f64 = 1e-12;

/// A site that may be nearest to a pixel of a block, with a lower bound of its
/// float key over the block's pixels.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    at: DVec2,
    bound: f64,
    id: u32,
}

/// The diagram of the distinct `sites` over `options`' window, L2 and exact,
/// handed to `sink` as bands of rows; the caller has checked the sites.
pub(crate) fn grid_bands(
    sites: &[DVec2],
    options: &VoronoiOptions,
    device: &str,
    sink: &mut dyn FnMut(Band) -> Result<()>,
) -> Result<VoronoiStats> {
    options.frame.check()?;
    if sites.len() >= MARK as usize {
        return Err(crate::Error::out_of_range(format!(
            "the grid labels fewer than {MARK} sites; {} given",
            sites.len()
        )));
    }
    let window = options.window_rect()?;
    let mut stats = VoronoiStats {
        device: device.to_string(),
        method: super::Method::Grid,
        sites: sites.len(),
        ..Default::default()
    };
    let started = std::time::Instant::now();
    let certifier = Certifier::new(sites, &options.frame, Metric::L2)?;
    stats.bounds_ms = ms(started);
    let width = window.width as usize;
    // A band of rows is held at a time: about 2^26 pixels, in whole blocks.
    let band_rows = (((1usize << 26) / width) as u32 / BLOCK).max(1) * BLOCK;
    let watch = Watch::current();
    for y0 in (window.y..window.y + window.height).step_by(band_rows as usize) {
        let height = band_rows.min(window.y + window.height - y0);
        let region = Region {
            x0: window.x,
            y0,
            width: window.width,
            height,
            stride: width,
            k: 1,
        };
        let started = std::time::Instant::now();
        let mut labels = crate::memory::filled(width * height as usize, 0u32, "labels")?;
        labels
            .par_chunks_mut(width * BLOCK as usize)
            .enumerate()
            .try_for_each_init(
                || Lists::new(&certifier),
                |lists, (row, labels)| {
                    watch.check()?;
                    let y = y0 + row as u32 * BLOCK;
                    for x in (0..window.width).step_by(BLOCK as usize) {
                        let corner = [window.x + x, y];
                        let size = [BLOCK.min(window.width - x), (labels.len() / width) as u32];
                        lists.block(&certifier, corner, size, &mut labels[x as usize..], width);
                    }
                    Ok::<_, crate::Error>(())
                },
            )?;
        stats.render_ms += ms(started);
        let started = std::time::Instant::now();
        let mut ties = if options.ties {
            crate::memory::filled(labels.len(), 1, "tie counts")?
        } else {
            Vec::new()
        };
        let counts = options.ties.then_some(&mut ties[..]);
        stats.mended += certifier.certify_marked(region, &mut labels, None, counts)?;
        let mut distances = Vec::new();
        if options.distances {
            distances = crate::memory::filled(labels.len(), 0.0, "distances")?;
            certifier.label_distances(region, &labels, &mut distances);
        }
        stats.certify_ms += ms(started);
        sink(Band {
            y0,
            height,
            labels,
            distances,
            ties,
        })?;
    }
    Ok(stats)
}

/// Candidate lists reused from block to block, and the keys' error bound.
struct Lists {
    apart: Apart,
    block: Vec<Candidate>,
    part: Vec<Candidate>,
}

impl Lists {
    fn new(certifier: &Certifier<'_>) -> Self {
        Self {
            apart: Apart::new(certifier.largest_error()),
            block: Vec::new(),
            part: Vec::new(),
        }
    }

    /// Labels the block of `size` pixels whose first is the frame's pixel
    /// `corner`, into `labels` (its first pixel first, rows `stride` apart).
    fn block(
        &mut self,
        certifier: &Certifier<'_>,
        corner: [u32; 2],
        size: [u32; 2],
        labels: &mut [u32],
        stride: usize,
    ) {
        let (places, grid) = (certifier.places(), certifier.grid());
        let (error, apart) = (certifier.largest_error(), self.apart);
        let first = DVec2::new(corner[0] as f64, corner[1] as f64);
        let last = first + DVec2::new(size[0] as f64 - 1.0, size[1] as f64 - 1.0);
        let centre = (first + last) / 2.0;
        let Some((_, nearest)) = grid.nearest(centre) else {
            for j in 0..size[1] as usize {
                labels[j * stride..][..size[0] as usize].fill(u32::MAX);
            }
            return;
        };
        let reach = gather_reach(first, last, nearest, error);
        let around = grid
            .around(centre, reach)
            .map(|id| (places[id as usize], id));
        gather(around, first, last, nearest, error, &mut self.block);
        let fill = |labels: &mut [u32], [dx, dy]: [u32; 2], [w, h]: [u32; 2], label: u32| {
            for j in dy..dy + h {
                labels[j as usize * stride..][dx as usize..(dx + w) as usize].fill(label);
            }
        };
        // Where sites are dense, quarters of the block take shorter lists,
        // drawn from the block's, which holds every site that can be nearest
        // to one of their pixels, and the site nearest their centres too.
        // A block split in quarters only hands its sites on.
        let dense = self.block.len() > PART_FROM;
        if !dense {
            order(&mut self.block, first, last);
            if let Some(owner) = sole_owner(apart, &self.block, 0, first, last) {
                return fill(labels, [0, 0], size, owner);
            }
        }
        for dy in (0..size[1]).step_by(PART as usize) {
            for dx in (0..size[0]).step_by(PART as usize) {
                let part = [PART.min(size[0] - dx), PART.min(size[1] - dy)];
                let first = first + DVec2::new(dx as f64, dy as f64);
                let last = first + DVec2::new(part[0] as f64 - 1.0, part[1] as f64 - 1.0);
                let centre = (first + last) / 2.0;
                let nearest = |c: &Candidate| c.at.distance_squared(centre);
                let (list, owner) = if dense {
                    let nearest = self.block.iter().map(nearest).fold(f64::INFINITY, f64::min);
                    let within = self.block.iter().map(|c| (c.at, c.id));
                    gather(within, first, last, nearest.sqrt(), error, &mut self.part);
                    order(&mut self.part, first, last);
                    (&self.part, 0)
                } else {
                    let keys = self.block.iter().map(nearest).enumerate();
                    let owner = keys.min_by(|a, b| a.1.total_cmp(&b.1)).map_or(0, |k| k.0);
                    (&self.block, owner)
                };
                if let Some(label) = sole_owner(apart, list, owner, first, last) {
                    fill(labels, [dx, dy], part, label);
                    continue;
                }
                for j in dy..dy + part[1] {
                    let row = &mut labels[j as usize * stride..];
                    for i in dx..dx + part[0] {
                        let p = first + DVec2::new((i - dx) as f64, (j - dy) as f64);
                        row[i as usize] = nearest_of(apart, list, p);
                    }
                }
            }
        }
    }
}

/// The site `list[owner]` if it is surely, and exactly, the nearest to
/// every pixel of the block from `first` to `last`; `list` holds every site
/// that can be nearest to one of them, in order of bounds that hold over
/// the block, and the site nearest the centre of the block it was gathered
/// for. Each other site's key less the owner's is linear in the pixel, so
/// its least over the block is at a corner, from its value at the centre.
fn sole_owner(
    apart: Apart,
    list: &[Candidate],
    owner: usize,
    first: DVec2,
    last: DVec2,
) -> Option<u32> {
    let site = list.get(owner)?;
    let centre = (first + last) / 2.0;
    let half = (last - first) / 2.0;
    let reach = half.length();
    let key = site.at.distance_squared(centre);
    // The owner's largest key over the block, and the keys surely beyond it.
    let most = ((key.sqrt() + reach) * (1.0 + SLACK)).powi(2);
    let beyond = apart.above(most);
    let margin = beyond - most;
    for (k, other) in list.iter().enumerate() {
        if other.bound > beyond {
            break;
        }
        if k == owner {
            continue;
        }
        let slope = 2.0 * (site.at - other.at);
        let other_key = other.at.distance_squared(centre);
        let least = other_key - key - slope.x.abs() * half.x - slope.y.abs() * half.y;
        // Rounding, of the keys and of this sum, is far below this slack.
        let largest = 2.0 * (other_key + reach * reach) + most;
        // NaN (overflowed keys) fails too.
        if least.partial_cmp(&(margin + 1e-11 * largest)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
    }
    Some(site.id)
}

/// Pixels a side of the quarters of a block.
const PART: u32 = BLOCK / 2;

/// Blocks with more candidates than this gather a list for each quarter.
const PART_FROM: usize = 12;

/// How far from the centre of the block from `first` to `last` a site can
/// lie and still be nearest to one of its pixels, when the site nearest the
/// centre lies `nearest` from it: no farther than that site from the pixel,
/// the places' errors counted twice over, the float distances' rounding by
/// the slack.
fn gather_reach(first: DVec2, last: DVec2, nearest: f64, error: f64) -> f64 {
    let half_diagonal = first.distance(last) / 2.0;
    (nearest + 2.0 * half_diagonal + 3.0 * error) * (1.0 + SLACK) + 1e-9
}

/// Into `out`, the candidates of the block of pixels from `first` to `last`
/// among `sites` (every site that can be nearest to one of its pixels, and
/// the site nearest its centre, `nearest` from it), unordered, each `bound`
/// its squared distance from the centre until [`order`].
fn gather(
    sites: impl Iterator<Item = (DVec2, u32)>,
    first: DVec2,
    last: DVec2,
    nearest: f64,
    error: f64,
    out: &mut Vec<Candidate>,
) {
    let centre = (first + last) / 2.0;
    let reach = gather_reach(first, last, nearest, error);
    let within = reach * reach;
    out.clear();
    for (at, id) in sites {
        let squared = at.distance_squared(centre);
        if squared <= within {
            out.push(Candidate {
                at,
                bound: squared,
                id,
            });
        }
    }
}

/// Orders the candidates [`gather`] left, nearest the centre of the block
/// from `first` to `last` first, each with a lower bound of its key over
/// the block.
fn order(list: &mut [Candidate], first: DVec2, last: DVec2) {
    let half_diagonal = first.distance(last) / 2.0;
    // Non-negative doubles order as their bits do.
    list.sort_unstable_by_key(|c| c.bound.to_bits());
    for c in list.iter_mut() {
        let gap = ((c.bound.sqrt() - half_diagonal) * (1.0 - SLACK) - 1e-9).max(0.0);
        c.bound = gap * gap;
    }
}

/// Float keys surely beyond a key `k`, exactly too: those above
/// `k * scale + shift`.
///
/// The exact distance of a site is within `3 e` of the float one, where e
/// bounds its place's error, and float keys are within the slack of the
/// square of the float distance. So a key k2 is surely farther than k when
/// `sqrt(k2) (1 - ε) > sqrt(k) (1 + ε) + 3 e`, which the line implies:
/// squared, with `sqrt(k) <= (1 + k) / 2` in the cross term.
#[derive(Clone, Copy, Debug)]
struct Apart {
    scale: f64,
    shift: f64,
}

impl Apart {
    fn new(error: f64) -> Self {
        let (up, down) = (1.0 + SLACK, (1.0 - SLACK) * (1.0 - SLACK));
        let cross = 3.0 * error * up;
        Self {
            scale: (up * up + cross) / down * up,
            shift: (cross + 9.0 * error * error) / down * up,
        }
    }

    fn above(self, key: f64) -> f64 {
        key * self.scale + self.shift
    }
}

/// The nearest of `candidates` to pixel `p` in doubles, with [`MARK`] set
/// where another site's key is within the error bound of its key.
fn nearest_of(apart: Apart, candidates: &[Candidate], p: DVec2) -> u32 {
    // The first is the nearest so far even where keys overflow to infinity.
    let Some((first, rest)) = candidates.split_first() else {
        return u32::MAX;
    };
    let (mut best, mut label, mut second) = (first.at.distance_squared(p), first.id, f64::INFINITY);
    let mut beyond = apart.above(best);
    for c in rest {
        if c.bound > beyond.min(second) {
            break;
        }
        // Without branches: which candidate is nearest is unpredictable.
        let key = c.at.distance_squared(p);
        let nearer = key < best;
        second = second.min(if nearer { best } else { key });
        label = if nearer { c.id } else { label };
        best = best.min(key);
        beyond = apart.above(best);
    }
    if second > beyond {
        label
    } else {
        label | MARK
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::exact::compare_distances;

    /// Sites mirrored about the block's corner pixel, one a few ulps
    /// nearer, far enough off that their keys' float difference is mostly
    /// rounding: whenever the other site is as near at some pixel, the owner
    /// is not given the block.
    #[test]
    fn a_near_tie_at_a_corner_keeps_the_block_from_one_owner() {
        let (first, last) = (DVec2::ZERO, DVec2::splat(3.0));
        let apart = Apart::new(0.0);
        let mut list = Vec::new();
        let (mut ties, mut plain_says_owner) = (0, 0);
        for far in [
            123456.789,
            345678.912,
            2345678.91,
            7654321.987,
            34567891.23,
            98765432.1,
        ] {
            for ulps in -4i64..=4 {
                let owner = DVec2::splat(far);
                let other = DVec2::new(
                    f64::from_bits((-far).to_bits().wrapping_add_signed(-ulps)),
                    -far,
                );
                let sites = [(owner, 0), (other, 1)];
                let nearest = owner.distance((first + last) / 2.0);
                gather(sites.into_iter(), first, last, nearest, 0.0, &mut list);
                order(&mut list, first, last);
                let corner = DVec2::ZERO;
                if compare_distances(corner, other, corner, owner).is_gt() {
                    continue;
                }
                ties += 1;
                assert_eq!(
                    sole_owner(apart, &list, 0, first, last),
                    None,
                    "{far} {ulps}"
                );
                // The linear bound taken in doubles alone.
                let half = (last - first) / 2.0;
                let centre = first + half;
                let slope = 2.0 * (owner - other);
                let least = other.distance_squared(centre)
                    - owner.distance_squared(centre)
                    - slope.x.abs() * half.x
                    - slope.y.abs() * half.y;
                plain_says_owner += usize::from(least > 0.0);
            }
        }
        assert!(
            ties > 0 && plain_says_owner > 0,
            "{ties} ties, {plain_says_owner} misread"
        );
    }
}
