//! Vector cells traced from a label raster: each label's region as polygons
//! along the pixels' edges, for the diagrams whose cells have no closed form
//! (other metrics, weighted and extended sites, higher orders). A traced
//! boundary lies within half a pixel of the diagram's true one wherever the
//! raster's labels are right.
//!
//! Every pixel side between two labels (or on the raster's border) is an edge
//! with its label's pixel on its left; following each label's edges gives its
//! outer rings counter-clockwise and its holes clockwise. Where two pixels of
//! a label touch only at a corner, the trace keeps to the pixel it goes
//! round, so they make two rings that meet at a point, which is valid for
//! GeoJSON and shapely.

use std::collections::HashMap;

/// A corner of the pixel grid: (column, row) of the corner at the low x, low
/// y of pixel (column, row); corners run from (0, 0) to (width, height).
pub(crate) type Corner = (u32, u32);

/// One label's region: polygons, each an outer ring followed by its holes.
/// Rings are closed implicitly (the last corner joins the first), and keep
/// only the corners where the boundary turns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    pub label: u32,
    pub polygons: Vec<Vec<Vec<Corner>>>,
}

/// Unit steps along the grid: +x, +y, -x, -y.
const STEPS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The regions of every label of `labels` (row-major, `width` wide) except
/// `skip` (no site), in increasing label order.
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
pub fn trace_regions(labels: &[u32], width: u32, skip: u32) -> Vec<Region> {
    let w = width as usize;
    let h = labels.len() / w.max(1);
    let at = |x: i64, y: i64| -> Option<u32> {
        (x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h)
            .then(|| labels[y as usize * w + x as usize])
    };
    // Each label's edges: start corner and step, its pixel on the left.
    let mut edges: HashMap<u32, Vec<(Corner, u8)>> = HashMap::new();
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let l = labels[y as usize * w + x as usize];
            if l == skip {
                continue;
            }
            let (cx, cy) = (x as u32, y as u32);
            // The square's sides counter-clockwise, each with the neighbour
            // across it.
            let sides = [
                ((cx, cy), 0u8, (x, y - 1)),
                ((cx + 1, cy), 1, (x + 1, y)),
                ((cx + 1, cy + 1), 2, (x, y + 1)),
                ((cx, cy + 1), 3, (x - 1, y)),
            ];
            for (start, step, (nx, ny)) in sides {
                if at(nx, ny) != Some(l) {
                    edges.entry(l).or_default().push((start, step));
                }
            }
        }
    }
    let mut labels_seen: Vec<u32> = edges.keys().copied().collect();
    labels_seen.sort_unstable();
    labels_seen
        .into_iter()
        .map(|label| Region {
            label,
            polygons: polygons(rings(&edges[&label])),
        })
        .collect()
}

fn next(c: Corner, step: u8) -> Corner {
    let (dx, dy) = STEPS[step as usize];
    ((c.0 as i64 + dx) as u32, (c.1 as i64 + dy) as u32)
}

/// Follows the edges into closed rings.
fn rings(edges: &[(Corner, u8)]) -> Vec<Vec<Corner>> {
    let mut from: HashMap<Corner, Vec<u8>> = HashMap::new();
    for &(c, s) in edges {
        from.entry(c).or_default().push(s);
    }
    let mut rings = Vec::new();
    for &(start, first) in edges {
        let taken = |from: &mut HashMap<Corner, Vec<u8>>, c: Corner, s: u8| {
            let out = from
                .get_mut(&c)
                .expect("an edge leaves every corner reached");
            match out.iter().position(|&t| t == s) {
                Some(k) => {
                    out.swap_remove(k);
                    true
                }
                None => false,
            }
        };
        if !taken(&mut from, start, first) {
            continue;
        }
        let mut ring = Vec::from([start]);
        let (mut at, mut step) = (next(start, first), first);
        loop {
            // The sharpest left turn first: left, straight, right, which keeps
            // to the pixel on the left where two of the label's pixels touch
            // at a corner. Back at the start, the ring closes where that turn
            // is its first edge.
            let open = |s: u8| from.get(&at).is_some_and(|o| o.contains(&s));
            let choice = [(step + 1) % 4, step, (step + 3) % 4]
                .into_iter()
                .find(|&s| open(s) || (at == start && s == first))
                .expect("a boundary goes on from every corner it reaches");
            if at == start && choice == first {
                break;
            }
            taken(&mut from, at, choice);
            if choice != step {
                ring.push(at);
            }
            at = next(at, choice);
            step = choice;
        }
        // The start is a corner only if the ring turns there.
        if step == first {
            ring.remove(0);
        }
        rings.push(ring);
    }
    rings
}

/// Twice the ring's signed area: positive counter-clockwise.
fn twice_area(ring: &[Corner]) -> i64 {
    let n = ring.len();
    (0..n)
        .map(|k| {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            a.0 as i64 * b.1 as i64 - b.0 as i64 * a.1 as i64
        })
        .sum()
}

/// Whether the point (x + 1/2, y + 1/2), a pixel's centre, is inside `ring`.
fn holds(ring: &[Corner], (x, y): (i64, i64)) -> bool {
    let (px, py) = (2 * x + 1, 2 * y + 1);
    let n = ring.len();
    let mut inside = false;
    for k in 0..n {
        let (a, b) = (ring[k], ring[(k + 1) % n]);
        let (ax, ay, bx, by) = (
            2 * a.0 as i64,
            2 * a.1 as i64,
            2 * b.0 as i64,
            2 * b.1 as i64,
        );
        // Vertical edges only cross a horizontal ray (the others are along
        // rows of corners, which a centre's row never meets).
        if ax == bx && (ay > py) != (by > py) && ax > px {
            inside = !inside;
        }
    }
    inside
}

/// Groups rings into polygons: each outer ring (counter-clockwise) with the
/// holes (clockwise) inside it.
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
fn polygons(rings: Vec<Vec<Corner>>) -> Vec<Vec<Vec<Corner>>> {
    let (outer, holes): (Vec<_>, Vec<_>) = rings.into_iter().partition(|r| twice_area(r) > 0);
    let mut out: Vec<Vec<Vec<Corner>>> = outer.into_iter().map(|r| Vec::from([r])).collect();
    for hole in holes {
        // The pixel on the left of the hole's first edge is the label's, and
        // inside exactly one outer ring: the smallest that holds it.
        let (a, b) = (hole[0], hole[1]);
        let (dx, dy) = (
            (b.0 as i64 - a.0 as i64).signum(),
            (b.1 as i64 - a.1 as i64).signum(),
        );
        // Left of a step (dx, dy) is (-dy, dx); the pixel there touches the
        // edge's first unit.
        let x = a.0 as i64 + if dx < 0 || -dy < 0 { -1 } else { 0 };
        let y = a.1 as i64 + if dy < 0 || dx < 0 { -1 } else { 0 };
        let host = out
            .iter()
            .enumerate()
            .filter(|(_, p)| holds(&p[0], (x, y)))
            .min_by_key(|(_, p)| twice_area(&p[0]))
            .map(|(k, _)| k)
            .expect("a hole lies inside an outer ring of its label");
        out[host].push(hole);
    }
    out
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// A polygon's area: its outer ring's less its holes'.
    fn area(polygon: &[Vec<Corner>]) -> i64 {
        polygon.iter().map(|r| twice_area(r)).sum::<i64>() / 2
    }

    fn inside(polygon: &[Vec<Corner>], pixel: (i64, i64)) -> bool {
        holds(&polygon[0], pixel) && !polygon[1..].iter().any(|h| holds(h, pixel))
    }

    #[test]
    fn regions_cover_their_pixels_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for (w, h, labels) in [
            (13usize, 9usize, 3u32),
            (20, 17, 2),
            (1, 1, 1),
            (7, 1, 2),
            (16, 16, 6),
        ] {
            let raster: Vec<u32> = (0..w * h).map(|_| rng.gen_range(0..labels)).collect();
            let regions = trace_regions(&raster, w as u32, u32::MAX);
            let mut total = 0;
            for region in &regions {
                for polygon in &region.polygons {
                    assert!(area(polygon) > 0, "holes inside their outer rings");
                    for hole in &polygon[1..] {
                        assert!(twice_area(hole) < 0);
                    }
                    total += area(polygon);
                }
                // Each pixel centre lies in one polygon of its own label, and
                // in none of another's.
                for (p, &label) in raster.iter().enumerate() {
                    let at = ((p % w) as i64, (p / w) as i64);
                    let count = region
                        .polygons
                        .iter()
                        .filter(|poly| inside(poly, at))
                        .count();
                    assert_eq!(
                        count,
                        usize::from(label == region.label),
                        "{w}x{h} pixel {p}"
                    );
                }
            }
            assert_eq!(total, (w * h) as i64);
        }
    }

    #[test]
    fn rings_keep_their_corners_and_holes_their_hosts() {
        // A 4x4 ring of label 1 around label 2, with label 0 outside it.
        let mut raster = vec![0u32; 6 * 6];
        for y in 1..5 {
            for x in 1..5 {
                raster[y * 6 + x] = if (2..4).contains(&x) && (2..4).contains(&y) {
                    2
                } else {
                    1
                };
            }
        }
        let regions = trace_regions(&raster, 6, 0);
        assert_eq!(regions.len(), 2);
        let ring = &regions[0];
        assert_eq!(ring.label, 1);
        assert_eq!(ring.polygons.len(), 1);
        assert_eq!(ring.polygons[0].len(), 2, "an outer ring and a hole");
        assert_eq!(ring.polygons[0][0].len(), 4, "a square keeps 4 corners");
        assert_eq!(area(&ring.polygons[0]), 12);
        // Two pixels meeting at a corner are two rings.
        let diagonal = [5, 0, 0, 5];
        let regions = trace_regions(&diagonal, 2, 0);
        assert_eq!(regions[0].polygons.len(), 2);
    }
}
