//! Homotopic thinning: pixels are taken away from a shape, nearest the
//! boundary first, only where taking one changes no topology (a simple
//! pixel: the shape keeps its 8-connected pieces and its 4-connected holes),
//! and never the anchors. What stays is the anchors joined along the middle
//! of the shape, one pixel thin, with every piece and every loop around a
//! hole kept.

use rayon::prelude::*;

/// The eight neighbours, counter-clockwise from the right (x, y offsets).
const AROUND: [(i64, i64); 8] = [
    (1, 0),
    (1, -1),
    (0, -1),
    (-1, -1),
    (-1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Whether a pixel whose neighbours in [`AROUND`] order are set as the bits
/// of `around` is simple: its set neighbours form one 8-connected piece and
/// its clear ones one 4-connected piece that touches it along an edge.
fn is_simple(around: u8) -> bool {
    let set = |k: usize| around & (1 << k) != 0;
    let pieces = |of: bool, edge_adjacent_only: bool| {
        let mut seen = [false; 8];
        let mut count = 0;
        for start in (0..8).filter(|&k| set(k) == of) {
            if seen[start] {
                continue;
            }
            // Those of the piece of `start`; it counts if one of them
            // touches the pixel as the connectivity asks.
            let mut stack = Vec::from([start]);
            seen[start] = true;
            let mut touches = false;
            while let Some(k) = stack.pop() {
                touches |= !edge_adjacent_only || k % 2 == 0;
                for j in 0..8 {
                    if set(j) != of || seen[j] {
                        continue;
                    }
                    let (a, b) = (AROUND[k], AROUND[j]);
                    let (dx, dy) = ((a.0 - b.0).abs(), (a.1 - b.1).abs());
                    let adjacent = match edge_adjacent_only {
                        false => dx <= 1 && dy <= 1,
                        true => dx + dy == 1,
                    };
                    if adjacent {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
            count += touches as u32;
        }
        count
    };
    pieces(true, false) == 1 && pieces(false, true) == 1
}

/// Thins `shape` (row-major, `width` wide) in the order of `depth` (smaller
/// first, to float precision, then the smaller index), keeping every pixel of `anchors`: passes
/// in that order over the pixels still there, until one takes none.
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
pub(super) fn thin(shape: &[bool], anchors: &[bool], depth: &[f64], width: usize) -> Vec<bool> {
    let simple: Vec<bool> = (0..=255u8).map(is_simple).collect();
    let height = shape.len() / width.max(1);
    let mut kept = shape.to_vec();
    // Depths are at least 0, so their bits order them; to float precision,
    // which only orders the thinning, with the index in the low half.
    let mut keyed: Vec<u64> = (0..shape.len() as u32)
        .filter(|&p| shape[p as usize] && !anchors[p as usize])
        .map(|p| u64::from((depth[p as usize] as f32).to_bits()) << 32 | u64::from(p))
        .collect();
    keyed.par_sort_unstable();
    let mut order: Vec<u32> = keyed.into_iter().map(|k| k as u32).collect();
    loop {
        let before = order.len();
        order.retain(|&p| {
            let p = p as usize;
            let (x, y) = ((p % width) as i64, (p / width) as i64);
            let around = AROUND
                .iter()
                .enumerate()
                .filter(|&(_, &(dx, dy))| {
                    let (u, v) = (x + dx, y + dy);
                    u >= 0
                        && v >= 0
                        && u < width as i64
                        && v < height as i64
                        && kept[v as usize * width + u as usize]
                })
                .fold(0u8, |bits, (k, _)| bits | 1 << k);
            if simple[around as usize] {
                kept[p] = false;
            }
            kept[p]
        });
        if order.len() == before {
            return kept;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_pixels() {
        // An end of a line, and a pixel of a straight edge.
        assert!(is_simple(0b0000_0001));
        assert!(is_simple(0b1111_1000));
        // A lone pixel, an inner pixel, a bridge between two pieces.
        assert!(!is_simple(0));
        assert!(!is_simple(0xff));
        assert!(!is_simple(0b0001_0001));
    }

    #[test]
    fn a_ring_stays_a_ring_and_a_blob_a_pixel() {
        // A 7x7 square with a hole in its middle, and no anchors.
        let w = 9;
        let shape: Vec<bool> = (0..w * w)
            .map(|p| {
                let (x, y) = (p % w, p / w);
                (1..8).contains(&x) && (1..8).contains(&y) && (x, y) != (4, 4)
            })
            .collect();
        let none = vec![false; w * w];
        let depth = vec![1.0; w * w];
        let ring = thin(&shape, &none, &depth, w);
        assert!(!ring[4 * w + 4]);
        // Every pixel next to the hole stays: it closes the loop.
        let around = ring.iter().filter(|&&k| k).count();
        assert!((4..=8).contains(&around), "{around}");
        let mut solid = shape.clone();
        solid[4 * w + 4] = true;
        let blob = thin(&solid, &none, &depth, w);
        assert_eq!(blob.iter().filter(|&&k| k).count(), 1);
        // An anchor stays.
        let mut anchors = none.clone();
        anchors[2 * w + 2] = true;
        assert!(thin(&solid, &anchors, &depth, w)[2 * w + 2]);
    }
}
