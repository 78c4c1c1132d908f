//! The best of the candidate centres of the largest circle clearing points
//! and segments (found in doubles by the homothets' `clearing`), decided
//! exactly. The vertices are algebraic (segment normals are square roots, and a vertex
//! by a point is a root of a quadratic in them), so each is solved from its
//! three pieces in rational intervals, its clearance bracketed against the
//! sites near it, and the precision doubled until the best clearance rounds
//! to one double: the radius printed is the correctly rounded exact one.

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::{nearest_double, precise::Interval, rational};

/// A condition on a clearing circle of centre c and radius r.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Piece {
    /// |c − p| = r.
    Point(DVec2),
    /// side · (n̂·(c − a)) = r for the unit normal n̂ = (b − a)⊥ / |b − a|
    /// of the line through a and b, side ±1.
    Line(DVec2, DVec2, f64),
    /// c on the line through a and b.
    Wall(DVec2, DVec2),
}

/// A candidate centre in doubles and what determines it exactly: three
/// pieces, or nothing where the centre is a given point (a site, a wall's end).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vertex {
    pub centre: DVec2,
    pub pieces: Option<[Piece; 3]>,
}

impl Vertex {
    pub fn at(centre: DVec2) -> Self {
        Self {
            centre,
            pieces: None,
        }
    }

    pub fn meeting(centre: DVec2, pieces: [Piece; 3]) -> Self {
        Self {
            centre,
            pieces: Some(pieces),
        }
    }
}

/// A site a clearing circle must not reach into.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Obstacle {
    Point(DVec2),
    Segment(DVec2, DVec2),
}

impl Obstacle {
    pub fn distance(&self, c: DVec2) -> f64 {
        match *self {
            Obstacle::Point(p) => p.distance(c),
            Obstacle::Segment(a, b) => crate::geometry::metric::segment_distance(c, a, b),
        }
    }
}

/// The exact answer in the user's coordinates: centre and radius rounded to
/// doubles, and the obstacles exactly on the circle.
#[derive(Debug)]
pub(crate) struct Certified {
    pub centre: DVec2,
    pub radius: f64,
    pub on: Vec<u32>,
}

/// Where the sites refined lie against the user's: theirs are these times
/// 2^k plus `origin`, both exact.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placement {
    pub k: i32,
    pub origin: DVec2,
}

/// Precisions tried, in bits below the local unit.
const PRECISIONS: [u64; 5] = [96, 192, 384, 768, 1536];

/// The best of `contenders` (candidate centres with their clearances in
/// doubles, best first, near enough to the best that rounding may reorder
/// them) by their exact clearance to `obstacles`; `near(c, r)` lists the
/// obstacles within r of c. Sites farther than `slack` beyond a contender's
/// clearance in doubles are taken to be clear of it.
/// The radius is correctly rounded, and so is the centre unless a coordinate
/// lies within 2^-1536 of the circle's size from a rounding boundary (0
/// included), where it is the double nearest to the middle of its bracket.
/// `None` where no precision decides (a contender whose pieces stay
/// degenerate), and the caller keeps its bound.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn certify(
    contenders: &[(Vertex, f64)],
    (obstacles, near): (&[Obstacle], &dyn Fn(DVec2, f64) -> Vec<u32>),
    slack: f64,
    placement: Placement,
) -> Option<Certified> {
    let &(first, value) = contenders.first()?;
    if value.is_nan() || value <= 0.0 {
        return None;
    }
    let local = Local::new(first.centre, value, placement);
    let near: Vec<Vec<u32>> = contenders
        .iter()
        .map(|(v, value)| near(v.centre, value + slack))
        .collect();
    let mut alive: Vec<usize> = (0..contenders.len()).collect();
    for (round, &bits) in PRECISIONS.iter().enumerate() {
        let judged: Vec<Judged> = alive
            .iter()
            .map(|&k| {
                let vertex = &contenders[k].0;
                let Some(e) = local.evaluate(vertex, obstacles, &near[k], bits) else {
                    return Judged::Undecided;
                };
                // A centre far from its double lies where other sites may be
                // nearer than the ones listed.
                let moved = DVec2::new(mid(&e.centre[0]), mid(&e.centre[1]));
                let guess = local.to_local_f64(vertex.centre);
                if moved.distance(guess) > local.to_local_length(slack) / 4.0 {
                    return Judged::Undecided;
                }
                match local.on_walls(vertex, &e.centre) {
                    Some(true) => Judged::Known(Box::new(e)),
                    Some(false) => Judged::Outside,
                    None => Judged::Undecided,
                }
            })
            .collect();
        let floor = judged
            .iter()
            .filter_map(|j| match j {
                Judged::Known(e) => Some(e.value.lo.clone()),
                _ => None,
            })
            .max()?;
        let kept: Vec<(usize, Option<Evaluation>)> = alive
            .iter()
            .copied()
            .zip(judged)
            .filter_map(|(k, j)| match j {
                Judged::Outside => None,
                Judged::Undecided => Some((k, None)),
                Judged::Known(e) => (e.value.hi >= floor).then_some((k, Some(*e))),
            })
            .collect();
        alive = kept.iter().map(|k| k.0).collect();
        let last = round + 1 == PRECISIONS.len();
        if kept.iter().any(|k| k.1.is_none()) {
            continue;
        }
        let radii: Vec<Option<f64>> = kept
            .iter()
            .map(|(_, e)| local.rounded_length(&e.as_ref().expect("evaluated").value))
            .collect();
        let radius = match radii[0] {
            Some(r) if radii.iter().all(|x| *x == Some(r)) => r,
            _ => continue,
        };
        let evaluations: Vec<&Evaluation> = kept.iter().flat_map(|k| k.1.as_ref()).collect();
        // Of the highest, where centres tie exactly, the lowest (x, then y):
        // the same answer whatever order the clusters came in.
        let best = evaluations
            .iter()
            .copied()
            .reduce(|a, b| {
                let key = |e: &Evaluation| (mid(&e.centre[0]), mid(&e.centre[1]));
                let tied = b.value.lo <= a.value.hi && a.value.lo <= b.value.hi;
                let lower = key(b)
                    .0
                    .total_cmp(&key(a).0)
                    .then(key(b).1.total_cmp(&key(a).1));
                match (tied && last, b.value.lo > a.value.lo) {
                    (true, _) if lower.is_lt() => b,
                    (true, _) => a,
                    (false, true) => b,
                    (false, false) => a,
                }
            })
            .expect("one kept");
        let centre = [0, 1].map(|axis| local.rounded_coordinate(&best.centre[axis], axis));
        // Distinct centres whose clearances no precision yet orders: more
        // bits, up to the last.
        let one_centre = evaluations
            .iter()
            .all(|e| [0, 1].map(|axis| local.rounded_coordinate(&e.centre[axis], axis)) == centre);
        if (centre.iter().any(Option::is_none) || !one_centre) && !last {
            continue;
        }
        let centre = DVec2::from([0, 1].map(|axis| {
            centre[axis].unwrap_or_else(|| local.middle_coordinate(&best.centre[axis], axis))
        }));
        let mut on: Vec<u32> = best
            .distances
            .iter()
            .filter(|(_, d)| d.lo <= best.value.hi && d.hi >= best.value.lo)
            .map(|(i, _)| *i)
            .collect();
        on.sort_unstable();
        return Some(Certified { centre, radius, on });
    }
    None
}

/// A contender at one precision: a centre off the walls it was solved on, one
/// whose pieces or walls that precision cannot decide, or its evaluation.
enum Judged {
    Outside,
    Undecided,
    Known(Box<Evaluation>),
}

/// A contender's centre and clearance in local units, and its distance to
/// each obstacle near it.
struct Evaluation {
    centre: [Interval; 2],
    value: Interval,
    distances: Vec<(u32, Interval)>,
}

/// The working frame: (p − origin) · 2^-k, exactly, so that the circle's size
/// is about 1 and a fixed number of bits below the unit is a relative
/// precision at every magnitude; and the way back to the user's coordinates,
/// x · back + shift.
struct Local {
    origin: DVec2,
    origin_exact: [BigRational; 2],
    k: i32,
    scale: BigRational,
    back: BigRational,
    shift: [BigRational; 2],
}

impl Local {
    fn new(origin: DVec2, size: f64, placement: Placement) -> Self {
        let k = size.log2().floor() as i32;
        let scale = power_of_two(-k);
        let user = power_of_two(-placement.k);
        let origin_exact = [rational(origin.x), rational(origin.y)];
        let shift = [0, 1].map(|a| &origin_exact[a] * &user + rational(placement.origin[a]));
        Self {
            origin,
            origin_exact,
            k,
            back: &user / &scale,
            scale,
            shift,
        }
    }

    fn point(&self, p: DVec2) -> [BigRational; 2] {
        [
            (rational(p.x) - &self.origin_exact[0]) * &self.scale,
            (rational(p.y) - &self.origin_exact[1]) * &self.scale,
        ]
    }

    fn to_local_f64(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(self.to_local_length(d.x), self.to_local_length(d.y))
    }

    fn to_local_length(&self, d: f64) -> f64 {
        crate::geometry::scale::times_power_of_two(d, -self.k)
    }

    /// A local length as the one double it rounds to, if one.
    fn rounded_length(&self, x: &Interval) -> Option<f64> {
        one_double(&x.affine(&self.back, &BigRational::zero()))
    }

    fn world(&self, x: &Interval, axis: usize) -> Interval {
        x.affine(&self.back, &self.shift[axis])
    }

    fn rounded_coordinate(&self, x: &Interval, axis: usize) -> Option<f64> {
        one_double(&self.world(x, axis))
    }

    /// The double nearest the middle of a bracket that straddles a rounding
    /// boundary; 0 where the bracket holds 0.
    fn middle_coordinate(&self, x: &Interval, axis: usize) -> f64 {
        let w = self.world(x, axis);
        if !w.lo.is_positive() && !w.hi.is_negative() {
            return 0.0;
        }
        nearest_double(&((&w.lo + &w.hi) / BigRational::from_integer(2.into())))
    }

    /// The vertex's centre, its exact clearance to the `near` obstacles, and
    /// the distances; `None` where its pieces are degenerate at `bits`.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    fn evaluate(
        &self,
        vertex: &Vertex,
        obstacles: &[Obstacle],
        near: &[u32],
        bits: u64,
    ) -> Option<Evaluation> {
        let centre = match vertex.pieces {
            None => self.point(vertex.centre).map(Interval::point),
            Some(pieces) => self.solve(&pieces, bits, self.to_local_f64(vertex.centre))?,
        };
        let distances: Vec<(u32, Interval)> = near
            .iter()
            .map(|&i| (i, self.distance(&centre, obstacles[i as usize], bits)))
            .collect();
        let value = distances
            .iter()
            .map(|(_, d)| d.clone())
            .reduce(Interval::min)?;
        Some(Evaluation {
            centre,
            value,
            distances,
        })
    }

    /// Whether the centre c, solved on the lines of the vertex's walls, lies on
    /// the walls themselves (between their ends); `None` where `c` does not
    /// decide.
    fn on_walls(&self, vertex: &Vertex, c: &[Interval; 2]) -> Option<bool> {
        let walls = vertex.pieces.iter().flatten().filter_map(|p| match *p {
            Piece::Wall(a, b) => Some((self.point(a), self.point(b))),
            _ => None,
        });
        let mut on = true;
        for (a, b) in walls {
            let e = [&b[0] - &a[0], &b[1] - &a[1]];
            let along = c[0]
                .affine(&e[0], &(-&a[0] * &e[0]))
                .plus(&c[1].affine(&e[1], &(-&a[1] * &e[1])));
            let length2 = norm2(&e);
            if along.hi.is_negative() || along.lo > length2 {
                return Some(false);
            }
            on &= !along.lo.is_negative() && along.hi <= length2;
        }
        on.then_some(true)
    }

    /// The distance from the centre c to an obstacle.
    fn distance(&self, c: &[Interval; 2], obstacle: Obstacle, bits: u64) -> Interval {
        let to_point = |p: &[BigRational; 2]| {
            let dx = c[0].subtracted_from(&p[0]);
            let dy = c[1].subtracted_from(&p[1]);
            dx.square().plus(&dy.square()).sqrt_of(bits)
        };
        match obstacle {
            Obstacle::Point(p) => to_point(&self.point(p)),
            Obstacle::Segment(a, b) if a == b => to_point(&self.point(a)),
            Obstacle::Segment(a, b) => {
                let (a, b) = (self.point(a), self.point(b));
                let e = [&b[0] - &a[0], &b[1] - &a[1]];
                let length2 = &e[0] * &e[0] + &e[1] * &e[1];
                let w = [
                    c[0].affine(&one(), &-a[0].clone()),
                    c[1].affine(&one(), &-a[1].clone()),
                ];
                let along = w[0]
                    .affine(&e[0], &BigRational::zero())
                    .plus(&w[1].affine(&e[1], &BigRational::zero()));
                let (to_a, to_b) = (to_point(&a), to_point(&b));
                if !along.hi.is_positive() {
                    return to_a;
                }
                if along.lo >= length2 {
                    return to_b;
                }
                let cross = w[1]
                    .affine(&e[0], &BigRational::zero())
                    .minus(&w[0].affine(&e[1], &BigRational::zero()));
                let length = Interval::sqrt(&length2, bits + 8);
                let line = cross
                    .abs()
                    .over(&length)
                    .expect("a segment of positive length");
                if !along.lo.is_negative() && along.hi <= length2 {
                    return line;
                }
                // The foot may be past an end: no nearer than the line, no
                // farther than either end.
                Interval {
                    lo: line.lo,
                    hi: to_a.hi.min(to_b.hi),
                }
            }
        }
    }

    /// A line's piece: side (n·c − n·a) / |n| = r for the normal n = (b − a)⊥,
    /// or c on the line (n·c = n·a) without a side.
    fn line(&self, a: DVec2, b: DVec2, side: Option<f64>, bits: u64) -> Linear {
        let (a, b) = (self.point(a), self.point(b));
        let n = [&a[1] - &b[1], &b[0] - &a[0]];
        let offset = &n[0] * &a[0] + &n[1] * &a[1];
        let (s, r) = match side {
            Some(side) => (
                BigRational::from_integer((side.signum() as i32).into()),
                Interval::sqrt(&norm2(&n), bits + 8).negated(),
            ),
            None => (one(), Interval::point(BigRational::zero())),
        };
        Linear {
            a: [0, 1].map(|i| Interval::point(&n[i] * &s)),
            b: r,
            g: Interval::point(offset * s),
        }
    }

    /// The centre where the three pieces meet, nearest `guess` of the
    /// solutions with a radius >= 0.
    fn solve(&self, pieces: &[Piece; 3], bits: u64, guess: DVec2) -> Option<[Interval; 2]> {
        let mut linear: Vec<Linear> = Vec::new();
        let mut circle: Option<[BigRational; 2]> = None;
        let zero = || Interval::point(BigRational::zero());
        for piece in pieces {
            match *piece {
                Piece::Point(p) => {
                    let p = self.point(p);
                    match &circle {
                        // |c − q|² = |c − p|²: 2 (q − p)·c = |q|² − |p|².
                        Some(q) => linear.push(Linear {
                            a: [0, 1].map(|i| Interval::point((&q[i] - &p[i]) * two())),
                            b: zero(),
                            g: Interval::point(norm2(q) - norm2(&p)),
                        }),
                        None => circle = Some(p),
                    }
                }
                Piece::Line(a, b, side) if a != b => linear.push(self.line(a, b, Some(side), bits)),
                Piece::Wall(a, b) if a != b => linear.push(self.line(a, b, None, bits)),
                _ => return None,
            }
        }
        let solutions = match (linear.as_slice(), circle) {
            ([p, q, r], None) => Vec::from([cramer(p, q, r, bits)?]),
            ([p, q], Some(centre)) => line_meets_circle(p, q, &centre, bits)?,
            _ => return None,
        };
        solutions
            .into_iter()
            .filter(|s| !s[2].hi.is_negative())
            .min_by(|a, b| {
                let d = |s: &[Interval; 3]| DVec2::new(mid(&s[0]), mid(&s[1])).distance(guess);
                d(a).total_cmp(&d(b))
            })
            .map(|[x, y, _]| [x, y])
    }
}

/// `a·c + b r = g` in the centre c and radius r.
struct Linear {
    a: [Interval; 2],
    b: Interval,
    g: Interval,
}

impl Linear {
    fn row(&self) -> [&Interval; 3] {
        [&self.a[0], &self.a[1], &self.b]
    }
}

/// The one (x, y, r) three linear equations hold.
fn cramer(p: &Linear, q: &Linear, r: &Linear, bits: u64) -> Option<[Interval; 3]> {
    let rows = [p.row(), q.row(), r.row()];
    let g = [&p.g, &q.g, &r.g];
    let det3 = |col: Option<usize>| {
        let m = |i: usize, j: usize| if col == Some(j) { g[i] } else { rows[i][j] };
        let minor = |j: usize, k: usize| m(1, j).times(m(2, k)).minus(&m(1, k).times(m(2, j)));
        m(0, 0)
            .times(&minor(1, 2))
            .minus(&m(0, 1).times(&minor(0, 2)))
            .plus(&m(0, 2).times(&minor(0, 1)))
    };
    let det = det3(None);
    let solve = |j: usize| Some(det3(Some(j)).over(&det)?.rounded_out(bits + 8));
    Some([solve(0)?, solve(1)?, solve(2)?])
}

/// The points (x, y, r) on the line two linear equations leave where
/// |c − centre| = r.
#[expect(clippy::disallowed_methods, reason = "a line's three coordinates")]
fn line_meets_circle(
    p: &Linear,
    q: &Linear,
    centre: &[BigRational; 2],
    bits: u64,
) -> Option<Vec<[Interval; 3]>> {
    let (u, v) = (p.row(), q.row());
    // The line's direction: the cross product of the two rows.
    let d = [
        u[1].times(v[2]).minus(&u[2].times(v[1])),
        u[2].times(v[0]).minus(&u[0].times(v[2])),
        u[0].times(v[1]).minus(&u[1].times(v[0])),
    ];
    // A point on it with its largest direction component's unknown at 0.
    let k = (0..3)
        .max_by(|&a, &b| mid(&d[a]).abs().total_cmp(&mid(&d[b]).abs()))
        .expect("three");
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let det = u[i].times(v[j]).minus(&u[j].times(v[i]));
    let at = |top: Interval| Some(top.over(&det)?.rounded_out(bits + 8));
    let mut base = [
        Interval::point(BigRational::zero()),
        Interval::point(BigRational::zero()),
        Interval::point(BigRational::zero()),
    ];
    base[i] = at(p.g.times(v[j]).minus(&q.g.times(u[j])))?;
    base[j] = at(u[i].times(&q.g).minus(&v[i].times(&p.g)))?;
    // |base_c + t d_c − centre|² = (base_r + t d_r)²: a t² + b t + c = 0.
    let w = [0, 1].map(|a| base[a].affine(&one(), &-centre[a].clone()));
    let a = d[0].square().plus(&d[1].square()).minus(&d[2].square());
    let b = d[0]
        .times(&w[0])
        .plus(&d[1].times(&w[1]))
        .minus(&base[2].times(&d[2]))
        .affine(&two(), &BigRational::zero());
    let c = w[0].square().plus(&w[1].square()).minus(&base[2].square());
    let four_ac = a
        .times(&c)
        .affine(&BigRational::from_integer(4.into()), &BigRational::zero());
    let root = b.square().minus(&four_ac).sqrt_of(bits + 8);
    let ts: Vec<Interval> = if a.is_nonzero() {
        let twice_a = a.affine(&two(), &BigRational::zero());
        Vec::from([
            root.minus(&b).over(&twice_a)?,
            root.plus(&b).negated().over(&twice_a)?,
        ])
    } else if b.is_nonzero() {
        // The near root, without cancellation: c / q for q = −(b ± √…)/2.
        let q = if b.lo.is_positive() {
            b.plus(&root)
        } else {
            b.minus(&root)
        }
        .affine(&-(one() / two()), &BigRational::zero());
        Vec::from([c.over(&q)?])
    } else {
        return None;
    };
    Some(
        ts.into_iter()
            .map(|t| {
                let t = t.rounded_out(bits + 8);
                [0, 1, 2].map(|a| base[a].plus(&t.times(&d[a])).rounded_out(bits + 8))
            })
            .collect(),
    )
}

/// The double that every number of the bracket rounds to, if one.
fn one_double(x: &Interval) -> Option<f64> {
    let lo = nearest_double(&x.lo);
    (lo == nearest_double(&x.hi) && lo.is_finite()).then_some(lo)
}

fn mid(x: &Interval) -> f64 {
    ((&x.lo + &x.hi) / two()).to_f64().unwrap_or(f64::NAN)
}

fn norm2(p: &[BigRational; 2]) -> BigRational {
    &p[0] * &p[0] + &p[1] * &p[1]
}

/// 2^k, exactly.
fn power_of_two(k: i32) -> BigRational {
    let power = BigRational::from_integer(BigInt::from(2).pow(k.unsigned_abs()));
    if k >= 0 {
        power
    } else {
        power.recip()
    }
}

fn one() -> BigRational {
    BigRational::from_integer(1.into())
}

fn two() -> BigRational {
    BigRational::from_integer(2.into())
}
