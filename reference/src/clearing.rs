//! The largest circle inside a box that holds none of some points and crosses
//! none of some axis-aligned segments, exactly. Axis-aligned lines have
//! rational normals, so every candidate centre (three pieces among the points
//! and the segments' and the box's lines) solves one quadratic over the
//! rationals: its coordinates and radius are w + u √d, compared exactly.

use std::cmp::Ordering;

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

type Q = BigRational;

fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite")
}

fn int(i: i64) -> Q {
    Q::from_integer(BigInt::from(i))
}

/// w + u √d for rationals w, u and d >= 0.
#[derive(Clone, Debug)]
pub struct Surd {
    pub w: Q,
    pub u: Q,
    pub d: Q,
}

impl Surd {
    fn rational(w: Q) -> Self {
        Surd {
            w,
            u: Q::zero(),
            d: Q::zero(),
        }
    }

    /// self + k · o, for o in the same field.
    fn plus_times(&self, k: &Q, o: &Surd) -> Surd {
        Surd {
            w: &self.w + k * &o.w,
            u: &self.u + k * &o.u,
            d: if o.u.is_zero() {
                self.d.clone()
            } else {
                o.d.clone()
            },
        }
    }

    fn minus_rational(&self, r: &Q) -> Surd {
        Surd {
            w: &self.w - r,
            ..self.clone()
        }
    }

    /// The square, in the same field.
    fn square(&self) -> Surd {
        Surd {
            w: &self.w * &self.w + &self.u * &self.u * &self.d,
            u: int(2) * &self.w * &self.u,
            d: self.d.clone(),
        }
    }

    fn minus(&self, o: &Surd) -> Surd {
        self.plus_times(&int(-1), o)
    }

    pub fn sign(&self) -> Ordering {
        let (w, u) = (self.w.cmp(&Q::zero()), self.u.cmp(&Q::zero()));
        let u = if self.d.is_zero() { Ordering::Equal } else { u };
        match (w, u) {
            (a, b) if a != Ordering::Less && b != Ordering::Less => a.max(b),
            (a, b) if a != Ordering::Greater && b != Ordering::Greater => a.min(b),
            // Opposite signs: the larger square wins.
            (a, _) => {
                let by = (&self.w * &self.w).cmp(&(&self.u * &self.u * &self.d));
                if a == Ordering::Greater {
                    by
                } else {
                    by.reverse()
                }
            }
        }
    }

    /// self against o, from another field.
    pub fn compare(&self, o: &Surd) -> Ordering {
        // (w1 − w2 + u1 √d1) − u2 √d2: compare P with R.
        let p = Surd {
            w: &self.w - &o.w,
            ..self.clone()
        };
        let r = Surd {
            w: Q::zero(),
            ..o.clone()
        };
        let (sp, sr) = (p.sign(), r.sign());
        if sp != sr || sp == Ordering::Equal {
            return sp.cmp(&sr);
        }
        let by = p.square().minus_rational(&(&o.u * &o.u * &o.d)).sign();
        if sp == Ordering::Greater {
            by
        } else {
            by.reverse()
        }
    }

    pub fn approximate(&self) -> f64 {
        use num_traits::ToPrimitive;
        self.w.to_f64().unwrap() + self.u.to_f64().unwrap() * self.d.to_f64().unwrap().sqrt()
    }
}

/// One condition on (x, y, r).
#[derive(Clone)]
enum Piece {
    /// |c − p| = r.
    Point([Q; 2]),
    /// side · (c[axis] − at) = r.
    Line { axis: usize, at: Q, side: i64 },
}

/// `a · (x, y, r) = g`.
type Row = ([Q; 3], Q);

/// The exact largest empty circle: its radius and every centre that reaches
/// it. Segments are axis-aligned (a == b makes a point); the box is
/// `[lo, hi]`, and the circle stays inside it.
pub fn largest_empty_in_box(
    points: &[DVec2],
    segments: &[(DVec2, DVec2)],
    lo: DVec2,
    hi: DVec2,
) -> (Surd, Vec<[Surd; 2]>) {
    let mut dots: Vec<DVec2> = points.to_vec();
    let mut pieces: Vec<Piece> = Vec::new();
    let mut bars: Vec<(usize, Q, Q, Q)> = Vec::new();
    for &(a, b) in segments {
        dots.extend([a, b]);
        if a == b {
            continue;
        }
        // Along `axis`, at `other`'s fixed coordinate.
        let axis = if a.y == b.y { 1 } else { 0 };
        assert!(a[axis] == b[axis], "axis-aligned segments only");
        let along = 1 - axis;
        let (s, e) = (a[along].min(b[along]), a[along].max(b[along]));
        bars.push((axis, q(a[axis]), q(s), q(e)));
        for side in [1, -1] {
            pieces.push(Piece::Line {
                axis,
                at: q(a[axis]),
                side,
            });
        }
    }
    for axis in 0..2 {
        pieces.push(Piece::Line {
            axis,
            at: q(lo[axis]),
            side: 1,
        });
        pieces.push(Piece::Line {
            axis,
            at: q(hi[axis]),
            side: -1,
        });
    }
    let dots: Vec<[Q; 2]> = dots.iter().map(|p| [q(p.x), q(p.y)]).collect();
    pieces.extend(dots.iter().cloned().map(Piece::Point));
    let (lo, hi) = ([q(lo.x), q(lo.y)], [q(hi.x), q(hi.y)]);
    let empty = |c: &[Surd; 3]| {
        let r2 = c[2].square();
        let clear_of = |p: &[Q; 2]| {
            let d2 = Surd::rational(Q::zero())
                .plus_times(&int(1), &c[0].minus_rational(&p[0]).square())
                .plus_times(&int(1), &c[1].minus_rational(&p[1]).square());
            d2.minus(&r2).sign() != Ordering::Less
        };
        c[2].sign() != Ordering::Less
            && (0..2).all(|a| {
                c[a].minus_rational(&lo[a]).minus(&c[2]).sign() != Ordering::Less
                    && Surd::rational(hi[a].clone())
                        .minus(&c[a])
                        .minus(&c[2])
                        .sign()
                        != Ordering::Less
            })
            && dots.iter().all(clear_of)
            && bars.iter().all(|(axis, at, s, e)| {
                let along = &c[1 - axis];
                let within = along.minus_rational(s).sign() != Ordering::Less
                    && Surd::rational(e.clone()).minus(along).sign() != Ordering::Less;
                !within || c[*axis].minus_rational(at).square().minus(&r2).sign() != Ordering::Less
            })
    };
    let mut best: Option<(Surd, Vec<[Surd; 2]>)> = None;
    let n = pieces.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                for c in solve(&[&pieces[i], &pieces[j], &pieces[k]]) {
                    if !empty(&c) {
                        continue;
                    }
                    let [x, y, r] = c;
                    match best.as_mut() {
                        Some(b) => match r.compare(&b.0) {
                            Ordering::Greater => best = Some((r, vec![[x, y]])),
                            Ordering::Equal => b.1.push([x, y]),
                            Ordering::Less => {}
                        },
                        None => best = Some((r, vec![[x, y]])),
                    }
                }
            }
        }
    }
    best.expect("a box holds a circle")
}

/// The largest circle holding none of `points` with its centre in the box
/// `[lo, hi]`, exactly: its squared radius and every centre that reaches it.
/// The candidates are rational: circumcentres, the points of the box's sides
/// equidistant from two points, and the corners.
pub fn largest_empty_centre_in_box(points: &[DVec2], lo: DVec2, hi: DVec2) -> (Q, Vec<[Q; 2]>) {
    let ps: Vec<[Q; 2]> = points.iter().map(|p| [q(p.x), q(p.y)]).collect();
    let (lo, hi) = ([q(lo.x), q(lo.y)], [q(hi.x), q(hi.y)]);
    let mut centres: Vec<[Q; 2]> = Vec::new();
    for x in [&lo[0], &hi[0]] {
        for y in [&lo[1], &hi[1]] {
            centres.push([x.clone(), y.clone()]);
        }
    }
    let n = ps.len();
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = (&ps[i], &ps[j]);
            // On a side c[axis] = at: 2 (b − a)·c = |b|² − |a|², the other
            // coordinate free.
            let rhs = &b[0] * &b[0] + &b[1] * &b[1] - &a[0] * &a[0] - &a[1] * &a[1];
            for axis in 0..2 {
                let other = 1 - axis;
                let slope = int(2) * (&b[other] - &a[other]);
                if slope.is_zero() {
                    continue;
                }
                for at in [&lo[axis], &hi[axis]] {
                    let free = (&rhs - int(2) * (&b[axis] - &a[axis]) * at) / &slope;
                    let mut c = [Q::zero(), Q::zero()];
                    c[axis] = at.clone();
                    c[other] = free;
                    centres.push(c);
                }
            }
            for c in &ps[j + 1..] {
                let (bx, by) = (&b[0] - &a[0], &b[1] - &a[1]);
                let (cx, cy) = (&c[0] - &a[0], &c[1] - &a[1]);
                let d = int(2) * (&bx * &cy - &by * &cx);
                if d.is_zero() {
                    continue;
                }
                let (b2, c2) = (&bx * &bx + &by * &by, &cx * &cx + &cy * &cy);
                centres.push([
                    &a[0] + (&cy * &b2 - &by * &c2) / &d,
                    &a[1] + (&bx * &c2 - &cx * &b2) / &d,
                ]);
            }
        }
    }
    let inside = |c: &[Q; 2]| (0..2).all(|a| c[a] >= lo[a] && c[a] <= hi[a]);
    let clearance = |c: &[Q; 2]| {
        ps.iter()
            .map(|p| {
                let d = [&c[0] - &p[0], &c[1] - &p[1]];
                &d[0] * &d[0] + &d[1] * &d[1]
            })
            .min()
            .expect("points")
    };
    let scored: Vec<(Q, [Q; 2])> = centres
        .into_iter()
        .filter(inside)
        .map(|c| (clearance(&c), c))
        .collect();
    let best = scored.iter().map(|s| s.0.clone()).max().expect("corners");
    let at = scored
        .into_iter()
        .filter(|s| s.0 == best)
        .map(|s| s.1)
        .collect();
    (best, at)
}

/// Whether the circle of radius `r` around the point `c` lies in the box and
/// clear of the points and segments (exactly).
pub fn is_clear(
    points: &[DVec2],
    segments: &[(DVec2, DVec2)],
    (lo, hi): (DVec2, DVec2),
    c: DVec2,
    r: &Surd,
) -> bool {
    let c = [q(c.x), q(c.y)];
    let at_least = |d2: Q| {
        r.sign() != Ordering::Greater || r.square().minus_rational(&d2).sign() != Ordering::Greater
    };
    let to_point = |p: DVec2| {
        let d = [&c[0] - q(p.x), &c[1] - q(p.y)];
        &d[0] * &d[0] + &d[1] * &d[1]
    };
    let in_box = (0..2).all(|a| {
        let room = [&c[a] - q(lo[a]), q(hi[a]) - &c[a]];
        room.into_iter()
            .all(|x| !x.is_negative() && at_least(&x * &x))
    });
    in_box
        && points.iter().all(|p| at_least(to_point(*p)))
        && segments.iter().all(|&(a, b)| {
            let axis = if a.y == b.y { 1 } else { 0 };
            let along = 1 - axis;
            let (s, e) = (q(a[along].min(b[along])), q(a[along].max(b[along])));
            let foot = c[along] >= s && c[along] <= e;
            let off = &c[axis] - q(a[axis]);
            at_least(to_point(a)) && at_least(to_point(b)) && (!foot || at_least(&off * &off))
        })
}

/// Every (x, y, r) where the three pieces meet.
fn solve(pieces: &[&Piece; 3]) -> Vec<[Surd; 3]> {
    let mut rows: Vec<Row> = Vec::new();
    let mut first: Option<&[Q; 2]> = None;
    for piece in pieces {
        match piece {
            Piece::Line { axis, at, side } => {
                let mut a = [Q::zero(), Q::zero(), int(-1)];
                a[*axis] = int(*side);
                rows.push((a, int(*side) * at));
            }
            Piece::Point(p) => match first {
                None => first = Some(p),
                // |c − f|² = |c − p|²: 2 (f − p)·c = |f|² − |p|².
                Some(f) => rows.push((
                    [
                        int(2) * (&f[0] - &p[0]),
                        int(2) * (&f[1] - &p[1]),
                        Q::zero(),
                    ],
                    &f[0] * &f[0] + &f[1] * &f[1] - &p[0] * &p[0] - &p[1] * &p[1],
                )),
            },
        }
    }
    let Some(f) = first else {
        return cramer(&rows).into_iter().collect();
    };
    let (a, b) = (&rows[0], &rows[1]);
    let dir = [
        &a.0[1] * &b.0[2] - &a.0[2] * &b.0[1],
        &a.0[2] * &b.0[0] - &a.0[0] * &b.0[2],
        &a.0[0] * &b.0[1] - &a.0[1] * &b.0[0],
    ];
    let Some(z) = (0..3).find(|&z| !dir[z].is_zero()) else {
        return Vec::new();
    };
    // The point of the line with unknown z at 0.
    let (i, j) = ((z + 1) % 3, (z + 2) % 3);
    let det = &a.0[i] * &b.0[j] - &a.0[j] * &b.0[i];
    let mut base = [Q::zero(), Q::zero(), Q::zero()];
    base[i] = (&a.1 * &b.0[j] - &b.1 * &a.0[j]) / &det;
    base[j] = (&a.0[i] * &b.1 - &b.0[i] * &a.1) / &det;
    // |base + t dir − f|² (in x, y) = (base_r + t dir_r)².
    let w = [&base[0] - &f[0], &base[1] - &f[1]];
    let qa = &dir[0] * &dir[0] + &dir[1] * &dir[1] - &dir[2] * &dir[2];
    let qb = int(2) * (&dir[0] * &w[0] + &dir[1] * &w[1] - &dir[2] * &base[2]);
    let qc = &w[0] * &w[0] + &w[1] * &w[1] - &base[2] * &base[2];
    let ts: Vec<Surd> = if qa.is_zero() {
        if qb.is_zero() {
            return Vec::new();
        }
        vec![Surd::rational(-qc / qb)]
    } else {
        let disc = &qb * &qb - int(4) * &qa * &qc;
        if disc.is_negative() {
            return Vec::new();
        }
        let two_a = int(2) * &qa;
        [1, -1]
            .map(|s| Surd {
                w: -&qb / &two_a,
                u: int(s) / &two_a,
                d: disc.clone(),
            })
            .into()
    };
    ts.into_iter()
        .map(|t| {
            [0, 1, 2].map(|k| Surd {
                w: &base[k] + &dir[k] * &t.w,
                u: &dir[k] * &t.u,
                d: t.d.clone(),
            })
        })
        .collect()
}

/// The one solution of three linear equations, if one.
fn cramer(rows: &[Row]) -> Option<[Surd; 3]> {
    let m = |r: usize, c: usize, with: Option<usize>| {
        if with == Some(c) {
            rows[r].1.clone()
        } else {
            rows[r].0[c].clone()
        }
    };
    let det = |with: Option<usize>| {
        let e = |r, c| m(r, c, with);
        e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1))
            - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
            + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0))
    };
    let d = det(None);
    if d.is_zero() {
        return None;
    }
    Some([0, 1, 2].map(|c| Surd::rational(det(Some(c)) / &d)))
}
