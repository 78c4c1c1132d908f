//! Circles through points: the smallest enclosing circle (Welzl 1991), which
//! the homothet and α-hull algorithms start from.

use glam::DVec2;
use rand::seq::SliceRandom;
use rand_chacha::{rand_core::SeedableRng, ChaCha8Rng};

/// A circle and the indices (into the points given) of the points on it that
/// determine it.
#[derive(Clone, Debug, PartialEq)]
pub struct Circle {
    pub centre: DVec2,
    pub radius: f64,
    pub support: Vec<usize>,
}

impl Circle {
    fn holds(&self, p: DVec2) -> bool {
        p.distance(self.centre) <= self.radius * (1.0 + 1e-12) + 1e-300
    }
}

/// The circle on the segment between two points as diameter.
pub(crate) fn through_two(a: DVec2, b: DVec2, ia: usize, ib: usize) -> Circle {
    let centre = (a + b) / 2.0;
    Circle {
        centre,
        radius: a.distance(centre).max(b.distance(centre)),
        support: vec![ia, ib],
    }
}

/// The circle through three points (the two farthest apart when they are collinear).
pub fn through_three(p: [DVec2; 3], i: [usize; 3]) -> Circle {
    let (a, b, c) = (p[0], p[1] - p[0], p[2] - p[0]);
    let d = 2.0 * b.perp_dot(c);
    if d == 0.0 {
        // Collinear: the circle on the two farthest apart.
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let (x, y) = pairs
            .into_iter()
            .max_by(|u, v| p[u.0].distance(p[u.1]).total_cmp(&p[v.0].distance(p[v.1])))
            .expect("three pairs");
        return through_two(p[x], p[y], i[x], i[y]);
    }
    let (b2, c2) = (b.length_squared(), c.length_squared());
    let centre = a + DVec2::new(c.y * b2 - b.y * c2, b.x * c2 - c.x * b2) / d;
    let radius = p.iter().map(|q| q.distance(centre)).fold(0.0, f64::max);
    Circle {
        centre,
        radius,
        support: i.to_vec(),
    }
}

/// The smallest circle holding every point (Welzl 1991, iterative
/// move-to-front form, in a fixed random order). Empty input gives radius 0 at
/// the origin.
pub fn welzl(points: &[DVec2]) -> Circle {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(0x5e1f));
    let p = |k: usize| points[order[k]];
    let mut c = match order.first() {
        None => {
            return Circle {
                centre: DVec2::ZERO,
                radius: 0.0,
                support: Vec::new(),
            }
        }
        Some(&i) => Circle {
            centre: points[i],
            radius: 0.0,
            support: vec![i],
        },
    };
    for i in 1..order.len() {
        if c.holds(p(i)) {
            continue;
        }
        c = Circle {
            centre: p(i),
            radius: 0.0,
            support: vec![order[i]],
        };
        for j in 0..i {
            if c.holds(p(j)) {
                continue;
            }
            c = through_two(p(i), p(j), order[i], order[j]);
            for k in 0..j {
                if !c.holds(p(k)) {
                    c = through_three([p(i), p(j), p(k)], [order[i], order[j], order[k]]);
                }
            }
        }
    }
    c
}
