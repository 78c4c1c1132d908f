//! The predicates' signs against rationals on near-degenerate doubles:
//! points a few ulps off a line or a circle, weights a few ulps off a tie
//! or a lifted plane, at magnitudes from 1e-150 to 1e300. Each case's
//! double-precision evaluation gets some signs wrong (checked here), so a
//! predicate whose filter trusted doubles too far would fail.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::Zero;
use pixgeo::geometry::{
    power::{compare_power, power_test, Weighted},
    predicates::{incircle, orient},
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::ulps;

type Q = BigRational;

fn q(x: f64) -> Q {
    Q::from_float(x).unwrap()
}

fn sign(x: &Q) -> Ordering {
    x.cmp(&Q::zero())
}

fn sign_of(x: f64) -> Ordering {
    x.partial_cmp(&0.0).unwrap()
}

/// The 3 x 3 determinant of rows (x, y, lift), relative to the fourth point.
fn det3(r: [[Q; 3]; 3]) -> Q {
    let [[ax, ay, al], [bx, by, bl], [cx, cy, cl]] = r;
    al * (&bx * &cy - &by * &cx) - bl * (&ax * &cy - &ay * &cx) + cl * (&ax * &by - &ay * &bx)
}

/// A point `steps` ulps off `p` in one coordinate.
fn nudge(rng: &mut ChaCha8Rng, p: DVec2) -> DVec2 {
    let steps = rng.gen_range(-2..=2);
    match rng.gen_bool(0.5) {
        true => DVec2::new(ulps(p.x, steps), p.y),
        false => DVec2::new(p.x, ulps(p.y, steps)),
    }
}

/// Scales and shifts of the unit square, from tiny to huge.
const PLACES: [(f64, f64); 5] = [
    (1.0, 0.0),
    (1e-150, 0.0),
    (1e150, 0.0),
    (1.0, 1e15),
    (1e300, 0.0),
];

/// Counts how often `naive` (the predicate in doubles) is wrong and checks
/// that `pixgeo`'s sign is always the exact one.
struct Tally {
    naive_wrong: usize,
    cases: usize,
}

impl Tally {
    fn new() -> Self {
        Self {
            naive_wrong: 0,
            cases: 0,
        }
    }

    fn check(&mut self, name: &str, exact: Ordering, pixgeo: Ordering, naive: f64) {
        assert_eq!(pixgeo, exact, "{name}");
        self.cases += 1;
        self.naive_wrong += usize::from(naive.is_nan() || sign_of(naive) != exact);
    }

    fn done(self, what: &str) {
        assert!(
            self.naive_wrong > self.cases / 50,
            "{what}: doubles were wrong in only {} of {} cases: too easy",
            self.naive_wrong,
            self.cases
        );
    }
}

#[test]
fn orientation_and_incircle_signs_are_exact_near_degeneracy() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let (mut lines, mut circles) = (Tally::new(), Tally::new());
    for k in 0..4000 {
        let (scale, shift) = PLACES[k % PLACES.len()];
        let place = |p: DVec2| p * scale + DVec2::splat(shift);
        // A point a few ulps off the line through two others.
        let (a, b) = (
            DVec2::new(rng.gen(), rng.gen()),
            DVec2::new(rng.gen(), rng.gen()),
        );
        let c = a + (b - a) * rng.gen_range(-1.0..2.0);
        let [a, b, c] = [place(a), place(b), nudge(&mut rng, place(c))];
        let exact = (q(b.x) - q(a.x)) * (q(c.y) - q(a.y)) - (q(b.y) - q(a.y)) * (q(c.x) - q(a.x));
        let naive = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        lines.check(
            &format!("orient {a} {b} {c}"),
            sign(&exact),
            sign_of(orient(a, b, c)),
            naive,
        );
        // A point a few ulps off the circle through three others.
        let (o, r) = (DVec2::new(rng.gen(), rng.gen()), rng.gen_range(0.1..1.0));
        let on = |t: f64| o + DVec2::new(t.cos(), t.sin()) * r;
        let mut angles: Vec<f64> = (0..4)
            .map(|_| rng.gen_range(0.0..std::f64::consts::TAU))
            .collect();
        angles[..3].sort_by(f64::total_cmp);
        let [a, b, c, d] = [0, 1, 2, 3].map(|i| place(on(angles[i])));
        let d = nudge(&mut rng, d);
        let rows = [a, b, c].map(|p| {
            let (x, y) = (q(p.x) - q(d.x), q(p.y) - q(d.y));
            let lift = &x * &x + &y * &y;
            [x, y, lift]
        });
        let naive = {
            let [a, b, c] = [a - d, b - d, c - d];
            let l = |p: DVec2| p.length_squared();
            l(a) * b.perp_dot(c) + l(b) * c.perp_dot(a) + l(c) * a.perp_dot(b)
        };
        circles.check(
            &format!("incircle {a} {b} {c} {d}"),
            sign(&det3(rows)),
            sign_of(incircle(a, b, c, d)),
            naive,
        );
    }
    lines.done("orient");
    circles.done("incircle");
}

#[test]
fn power_signs_are_exact_near_degeneracy() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut ties, mut planes) = (Tally::new(), Tally::new());
    for k in 0..4000 {
        // 1e300 points would have 1e600 weights: the power cases stop at 1e150.
        let (scale, shift) = PLACES[k % (PLACES.len() - 1)];
        let place = |p: DVec2| p * scale + DVec2::splat(shift);
        let weight = |w: f64| w * scale * scale;
        let site = |at: DVec2, w: f64| Weighted { at, weight: w };
        // A point of about equal power from two sites, their weights a few
        // ulps off the tie.
        let p = place(DVec2::new(rng.gen(), rng.gen()));
        let (s, t) = (
            place(DVec2::new(rng.gen(), rng.gen())),
            place(DVec2::new(rng.gen(), rng.gen())),
        );
        let ws = weight(rng.gen_range(0.0..0.5));
        let wt = ulps(
            ws + (p - t).length_squared() - (p - s).length_squared(),
            rng.gen_range(-2..=2),
        );
        let exact = |s: Weighted| {
            let (x, y) = (q(p.x) - q(s.at.x), q(p.y) - q(s.at.y));
            &x * &x + &y * &y - q(s.weight)
        };
        let (a, b) = (site(s, ws), site(t, wt));
        let naive = ((p - s).length_squared() - ws) - ((p - t).length_squared() - wt);
        ties.check(
            &format!("compare_power {p} {a:?} {b:?}"),
            exact(a).cmp(&exact(b)),
            compare_power(p, a, b),
            naive,
        );
        // A fourth lifted point a few ulps off the plane through three.
        let [pa, pb, pc, pd] = [0; 4].map(|_| place(DVec2::new(rng.gen(), rng.gen())));
        let [wa, wb, wc] = [0; 3].map(|_| weight(rng.gen_range(0.0..0.5)));
        let (pa, pb) = match orient(pa, pb, pc) > 0.0 {
            true => (pa, pb),
            false => (pb, pa),
        };
        // The plane z = l(x, y) through the lifted three, in doubles.
        let lift = |p: DVec2, w: f64| p.length_squared() - w;
        let (za, zb, zc) = (lift(pa, wa), lift(pb, wb), lift(pc, wc));
        let (u, v) = (pb - pa, pc - pa);
        let area = u.perp_dot(v);
        let (du, dv) = (zb - za, zc - za);
        let gx = (du * v.y - dv * u.y) / area;
        let gy = (dv * u.x - du * v.x) / area;
        let zd = za + gx * (pd.x - pa.x) + gy * (pd.y - pa.y);
        let wd = ulps(pd.length_squared() - zd, rng.gen_range(-2..=2));
        if !wd.is_finite() {
            continue;
        }
        let sites = [site(pa, wa), site(pb, wb), site(pc, wc)];
        let d = site(pd, wd);
        let rows = sites.map(|s| {
            let (x, y) = (q(s.at.x) - q(d.at.x), q(s.at.y) - q(d.at.y));
            let lift = &x * &x + &y * &y - (q(s.weight) - q(d.weight));
            [x, y, lift]
        });
        let naive = {
            let r = sites.map(|s| {
                let (x, y) = (s.at.x - d.at.x, s.at.y - d.at.y);
                (x, y, x * x + y * y - (s.weight - d.weight))
            });
            let [(ax, ay, al), (bx, by, bl), (cx, cy, cl)] = r;
            al * (bx * cy - by * cx) - bl * (ax * cy - ay * cx) + cl * (ax * by - ay * bx)
        };
        planes.check(
            &format!("power_test {sites:?} {d:?}"),
            sign(&det3(rows)),
            power_test(sites[0], sites[1], sites[2], d),
            naive,
        );
    }
    ties.done("compare_power");
    planes.done("power_test");
}
