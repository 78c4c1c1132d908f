//! Great-circle distances decided exactly: positions in degrees become unit
//! vectors in rational intervals (π bracketed by 100 digits, the cosine and
//! sine by their Taylor series), and the largest dot product is the nearest
//! site, refined until one remains or the finest precision leaves a tie.

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;

use super::precise::{cos_sin_of, Interval};

/// The nearest of the `candidates` (site indices) to `place` by great circle,
/// decided in rational intervals; and whether two or more stay equidistant
/// at the finest precision (the lowest index among them wins).
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn nearest_on_sphere(place: DVec2, sites: &[DVec2], candidates: &[u32]) -> (u32, bool) {
    let mut order = candidates.to_vec();
    order.sort_unstable();
    let mut tied = order.clone();
    for bits in [64, 160, 320] {
        let Some(u) = vector_interval(place, bits) else {
            break;
        };
        let dots: Vec<Option<Interval>> = order
            .iter()
            .map(|&i| vector_interval(sites[i as usize], bits).map(|v| dot(&u, &v)))
            .collect();
        let Some(highest) = dots.iter().flatten().map(|d| d.lo.clone()).max() else {
            break;
        };
        // Sites whose dot may reach the highest lower bound.
        tied = order
            .iter()
            .zip(&dots)
            .filter(|(_, d)| d.as_ref().is_some_and(|d| d.hi >= highest))
            .map(|(&i, _)| i)
            .collect();
        if tied.len() == 1 {
            return (tied[0], false);
        }
    }
    (tied[0], tied.len() > 1)
}

fn dot(u: &[Interval; 3], v: &[Interval; 3]) -> Interval {
    u[0].times(&v[0])
        .plus(&u[1].times(&v[1]))
        .plus(&u[2].times(&v[2]))
}

/// The unit vector of a position (degrees) as rational intervals, each
/// within about 2^-bits.
fn vector_interval(p: DVec2, bits: u64) -> Option<[Interval; 3]> {
    let [lon, lat] = [cos_sin_degrees(p.x, bits)?, cos_sin_degrees(p.y, bits)?];
    let (cos_lat, sin_lat) = lat;
    let (cos_lon, sin_lon) = lon;
    Some([cos_lat.times(&cos_lon), cos_lat.times(&sin_lon), sin_lat])
}

/// The cosine and sine of `degrees` (reduced to [-180, 180] exactly) as
/// intervals: π/180 bracketed by a 100-digit π, the argument's spread added
/// to the Taylor series' bracket (both functions move no faster than it).
pub(crate) fn cos_sin_degrees(degrees: f64, bits: u64) -> Option<(Interval, Interval)> {
    let d = super::rational(degrees);
    let turns = (&d / BigRational::from_integer(360.into())).round();
    let reduced = d - turns * BigRational::from_integer(360.into());
    let scale = BigInt::from(10).pow(100);
    let pi = BigRational::new(PI_DIGITS.parse::<BigInt>().ok()?, scale.clone());
    let degree = BigRational::from_integer(180.into());
    let low = &reduced * &pi / &degree;
    // π's truncation is below 10^-100, times at most 180/180.
    let spread = BigRational::new(BigInt::from(1), scale);
    let (cos, sin) = cos_sin_of(&low, bits)?;
    let widen = |i: Interval| Interval {
        lo: i.lo - &spread,
        hi: i.hi + &spread,
    };
    Some((widen(cos), widen(sin)))
}

/// π truncated to 100 decimals, as the integer π·10^100.
const PI_DIGITS: &str = "31415926535897932384626433832795028841971693993751\
                         058209749445923078164062862089986280348253421170679";
