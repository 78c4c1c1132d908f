//! Digital Voronoi diagrams of seed pixels (Cao, Edelsbrunner and Tan 2015):
//! the Euclidean colouring E_i, flooding F_i by the paper's priority queue,
//! the properties its lemmas prove, and the dual digital Delaunay
//! triangulation.
//!
//! Pixels are (x, y) with x the column and y the row, centred at world (x, y);
//! a picture is row-major. Two pixels are neighbours if they share a side or a
//! corner. Ties are broken by one total order on (pixel, seed) pairs that is
//! consistent with distance: the squared distance, then the pixel's and then
//! the seed's coordinates, lexicographically.

use std::{cmp::Reverse, collections::BinaryHeap};

use pixgeo::{Error, Result};

/// No seed: a pixel with no colour.
pub const NONE: u32 = u32::MAX;

/// The dual triangulation's vertex outside the texture.
pub const DUMMY: u32 = u32::MAX;

/// A seed pixel: its column and row.
pub type Seed = [i32; 2];

/// A (pixel, seed) pair's place in the total order: squared distance, then
/// the pixel's and the seed's coordinates.
pub type Priority = (i64, i32, i32, i32, i32);

/// The priority of colouring pixel `a` with the seed at `s`: smaller first.
pub fn priority(a: [i32; 2], s: Seed) -> Priority {
    let (dx, dy) = (i64::from(a[0] - s[0]), i64::from(a[1] - s[1]));
    (dx * dx + dy * dy, a[0], a[1], s[0], s[1])
}

/// Refuses an empty texture, and a seed outside it or on another's pixel.
pub fn check_seeds(width: u32, height: u32, seeds: &[Seed]) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::malformed("no pixels".into()));
    }
    let inside = |s: &Seed| s[0] >= 0 && s[1] >= 0 && s[0] < width as i32 && s[1] < height as i32;
    let mut sorted = seeds.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    match seeds.iter().all(inside) && sorted.len() == seeds.len() {
        true => Ok(()),
        false => Err(Error::malformed(
            "a seed outside the texture, or repeated".into(),
        )),
    }
}

/// The up to eight pixels sharing a side or a corner with (x, y), inside
/// the texture.
pub fn neighbours(x: i32, y: i32, width: u32, height: u32) -> impl Iterator<Item = [i32; 2]> {
    let around = [
        (-1, -1),
        (0, -1),
        (1, -1),
        (-1, 0),
        (1, 0),
        (-1, 1),
        (0, 1),
        (1, 1),
    ];
    around
        .into_iter()
        .map(move |(dx, dy)| [x + dx, y + dy])
        .filter(move |&[a, b]| a >= 0 && b >= 0 && a < width as i32 && b < height as i32)
}

/// The Euclidean colouring: every pixel the colour of its nearest seed.
pub fn euclidean(width: u32, height: u32, seeds: &[Seed]) -> Result<Vec<u32>> {
    check_seeds(width, height, seeds)?;
    let mut labels = vec![NONE; (width * height) as usize];
    for y in 0..height as i32 {
        for x in 0..width as i32 {
            labels[(y as u32 * width + x as u32) as usize] = seeds
                .iter()
                .enumerate()
                .min_by_key(|(_, s)| priority([x, y], **s))
                .map_or(NONE, |(i, _)| i as u32);
        }
    }
    Ok(labels)
}

/// Flooding (§2): the pair (pixel, colour) of highest priority is taken from
/// the queue; an uncoloured pixel gets the colour, and its neighbours become
/// eligible for it.
pub fn flood(width: u32, height: u32, seeds: &[Seed]) -> Result<Vec<u32>> {
    check_seeds(width, height, seeds)?;
    let mut labels = vec![NONE; (width * height) as usize];
    let mut queue: BinaryHeap<Reverse<(Priority, u32)>> = seeds
        .iter()
        .enumerate()
        .map(|(i, s)| Reverse((priority(*s, *s), i as u32)))
        .collect();
    while let Some(Reverse(((_, x, y, _, _), i))) = queue.pop() {
        let at = (y as u32 * width + x as u32) as usize;
        if labels[at] != NONE {
            continue;
        }
        labels[at] = i;
        for b in neighbours(x, y, width, height) {
            if labels[(b[1] as u32 * width + b[0] as u32) as usize] == NONE {
                queue.push(Reverse((priority(b, seeds[i as usize]), i)));
            }
        }
    }
    Ok(labels)
}

/// The pixels of colour `i` connected to its seed (neighbours by side or
/// corner): the bulk of E_i, or all of F_i when flooding connected it.
pub fn component(labels: &[u32], width: u32, height: u32, seed: Seed, i: u32) -> Vec<bool> {
    let mut inside = vec![false; labels.len()];
    let at = |p: [i32; 2]| (p[1] as u32 * width + p[0] as u32) as usize;
    if labels[at(seed)] != i {
        return inside;
    }
    let mut stack = vec![seed];
    inside[at(seed)] = true;
    while let Some([x, y]) = stack.pop() {
        for b in neighbours(x, y, width, height) {
            if !inside[at(b)] && labels[at(b)] == i {
                inside[at(b)] = true;
                stack.push(b);
            }
        }
    }
    inside
}

/// Whether region `i` has a hole: pixels of other colours that cannot reach
/// the texture's border through side-neighbours of other colours.
pub fn has_hole(labels: &[u32], width: u32, height: u32, i: u32) -> bool {
    let (w, h) = (width as i32, height as i32);
    let at = |x: i32, y: i32| (y * w + x) as usize;
    let mut reached = vec![false; labels.len()];
    let mut stack: Vec<[i32; 2]> = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let border = x == 0 || y == 0 || x == w - 1 || y == h - 1;
            if border && labels[at(x, y)] != i {
                reached[at(x, y)] = true;
                stack.push([x, y]);
            }
        }
    }
    while let Some([x, y]) = stack.pop() {
        for [a, b] in [[x + 1, y], [x - 1, y], [x, y + 1], [x, y - 1]] {
            if a >= 0 && b >= 0 && a < w && b < h && !reached[at(a, b)] && labels[at(a, b)] != i {
                reached[at(a, b)] = true;
                stack.push([a, b]);
            }
        }
    }
    (0..labels.len()).any(|k| labels[k] != i && !reached[k])
}

/// The first 2-by-2 square with two necks (Fig. 2's fourth type: each
/// diagonal pair one colour, the colours different), if any.
pub fn double_neck(labels: &[u32], width: u32, height: u32) -> Option<[u32; 2]> {
    for y in 0..height.saturating_sub(1) {
        for x in 0..width.saturating_sub(1) {
            let c = |dx: u32, dy: u32| labels[((y + dy) * width + x + dx) as usize];
            let (a, b, u, v) = (c(0, 0), c(1, 1), c(1, 0), c(0, 1));
            if a == b && u == v && a != u {
                return Some([x, y]);
            }
        }
    }
    None
}

/// The dual of a colouring (§2): a triangle for every digital Voronoi vertex,
/// a corner where four colours meet, or three with the repeated colour on two
/// side-neighbours; four colours give two triangles. Pixels beyond the
/// texture have the dummy vertex's colour [`DUMMY`], which makes the triangles
/// at infinity. Vertices are counter-clockwise (x right, y up).
pub fn dualize(labels: &[u32], width: u32, height: u32) -> Vec<[u32; 3]> {
    let (w, h) = (width as i32, height as i32);
    let colour = |x: i32, y: i32| {
        if x < 0 || y < 0 || x >= w || y >= h {
            DUMMY
        } else {
            labels[(y * w + x) as usize]
        }
    };
    let mut triangles = Vec::new();
    for y in -1..h {
        for x in -1..w {
            // Counter-clockwise around the corner at (x + 1/2, y + 1/2).
            let c = [
                colour(x, y),
                colour(x + 1, y),
                colour(x + 1, y + 1),
                colour(x, y + 1),
            ];
            let mut distinct = c.to_vec();
            distinct.sort_unstable();
            distinct.dedup();
            match distinct.len() {
                4 => {
                    triangles.push([c[0], c[1], c[2]]);
                    triangles.push([c[0], c[2], c[3]]);
                }
                3 => {
                    // The repeat must be on side-neighbours (k, k + 1); on a
                    // diagonal it is a neck.
                    if let Some(k) = (0..4).find(|&k| c[k] == c[(k + 1) % 4]) {
                        let t: Vec<u32> = (1..4).map(|d| c[(k + d) % 4]).collect();
                        triangles.push([t[0], t[1], t[2]]);
                    }
                }
                _ => {}
            }
        }
    }
    triangles
}
