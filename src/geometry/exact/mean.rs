//! The mean of pixel centres, correctly rounded: a region's centroid in
//! Lloyd's relaxation, `origin + sum / (weight · scale)` from whole sums.

use num_bigint::BigInt;
use num_rational::BigRational;

use super::{nearest_double, next_toward, rational, two_product, two_sum};

/// The double nearest to `origin + sum / (weight · scale)` (`weight` > 0):
/// double-double arithmetic where it proves the rounding, rationals where
/// not.
pub(crate) fn pixel_mean(origin: f64, sum: u128, weight: u128, scale: f64) -> f64 {
    certified_mean(origin, sum, weight, scale)
        .unwrap_or_else(|| exact_mean(origin, sum, weight, scale))
}

fn exact_mean(origin: f64, sum: u128, weight: u128, scale: f64) -> f64 {
    let d = BigRational::from_integer(BigInt::from(weight)) * rational(scale);
    nearest_double(&(rational(origin) + BigRational::from_integer(sum.into()) / d))
}

/// The double nearest to `origin + sum / (weight · scale)` where double-double
/// arithmetic proves it (about 100 bits against the 53 of the answer), or
/// `None` where the value lies too near a rounding boundary (or the sums
/// exceed 2^100) and exact arithmetic must decide.
fn certified_mean(origin: f64, sum: u128, weight: u128, scale: f64) -> Option<f64> {
    const LIMIT: u128 = 1 << 100;
    if sum >= LIMIT || weight >= LIMIT {
        return None;
    }
    // A whole number below 2^100 as an exact pair of doubles.
    let split = |n: u128| {
        let high = n as f64;
        (high, (n as i128 - high as i128) as f64)
    };
    let (s, w) = (split(sum), split(weight));
    // weight · scale, exact as a pair but for the low part's own product.
    let (dh, dl) = two_product(w.0, scale);
    let d = two_sum(dh, dl + w.1 * scale);
    // sum / d: a first quotient, then the remainder's.
    let q1 = s.0 / d.0;
    let (p, pe) = two_product(q1, d.0);
    let remainder = ((s.0 - p) - pe + s.1) - q1 * d.1;
    let q = two_sum(q1, remainder / d.0);
    let (x, xe) = two_sum(origin, q.0);
    let low = xe + q.1;
    // Each step errs by a few units of 2^-104 of the magnitudes.
    let error = (origin.abs() + q.0.abs()) * 2f64.powi(-96) + f64::MIN_POSITIVE;
    let toward = if low < 0.0 {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    };
    let neighbour = next_toward(x, toward);
    if !(x.is_finite() && neighbour.is_finite()) {
        return None;
    }
    // x is nearest unless the rest reaches halfway to the neighbour.
    (low.abs() + error < (neighbour - x).abs() / 2.0).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_double_double_mean_is_the_exact_one_or_declines() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let (mut certified, mut declined) = (0, 0);
        let origins = [-0.5, 0.0, 1e15, -123.456, 3.0e-7, 7.1e200];
        let scales = [1.0, 0.1, 1024.0 / 1000.0, 3.0, 1e-9, 2.5e100];
        for k in 0..20_000 {
            let weight = (next() % 1_000_000 + 1) as u128 * [1, 1 << 40][k % 2];
            let sum = weight * (next() % 4096) as u128 + (next() % 1000) as u128;
            let (origin, scale) = (origins[k % 6], scales[(k / 6) % 6]);
            match certified_mean(origin, sum, weight, scale) {
                Some(x) => {
                    certified += 1;
                    assert_eq!(
                        x,
                        exact_mean(origin, sum, weight, scale),
                        "{origin} {sum} {weight} {scale}"
                    );
                }
                None => declined += 1,
            }
        }
        // Halfway cases decline: 1 + 2^-53 lies midway between 1 and the next double.
        assert_eq!(certified_mean(1.0, 1, 1 << 53, 1.0), None);
        assert!(
            certified > 18_000,
            "{certified} certified, {declined} declined"
        );
    }
}
