//! Triangle areas with exact signs.

use glam::DVec2;

use super::predicates::orient;

/// The area of triangle (a, b, c).
pub fn triangle_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    0.5 * orient(a, b, c).abs()
}

/// The best site strictly on each side of the line p → q (left, right): the
/// nearest (`largest` false) or farthest, with its triangle's area.
pub fn sides_of(sites: &[DVec2], p: usize, q: usize, largest: bool) -> [Option<(u32, f64)>; 2] {
    let mut best = [None, None];
    for (s, &x) in sites.iter().enumerate() {
        let c = orient(sites[p], sites[q], x);
        if c == 0.0 {
            continue;
        }
        let side = usize::from(c < 0.0);
        let area = 0.5 * c.abs();
        let better = match best[side] {
            None => true,
            Some((_, b)) => {
                if largest {
                    area > b
                } else {
                    area < b
                }
            }
        };
        if better {
            best[side] = Some((s as u32, area));
        }
    }
    best
}
