//! Exact scaling by powers of two, so that the exact predicates (`robust`'s
//! orientation and incircle tests) see coordinates whose products neither
//! overflow (coordinates past about 1e154) nor underflow (below about 1e-154).
//! Orientation and incircle signs, and so every triangulation, are the same for
//! points scaled by a power of two. Sets whose nonzero coordinates span more
//! than 2^400 in ratio (2^170 for incircle tests) are refused: products of
//! their differences would underflow.

use glam::DVec2;

use crate::error::{Error, Result};

/// `x · 2^k`, exact where the result is a normal number; two steps, since 2^k
/// alone may not be one.
pub(crate) fn times_power_of_two(x: f64, k: i32) -> f64 {
    x * 2f64.powi(k / 2) * 2f64.powi(k - k / 2)
}

/// The power of two that brings the points' largest coordinate near 1 (0 when
/// it is within 2^±16), for predicates of degree 2: orientations and squared
/// distances. Refuses coordinates spanning more than 2^400 in ratio, where
/// products of their differences would underflow and lose the sign.
pub(crate) fn predicate_exponent(points: &[DVec2]) -> Result<i32> {
    exponent_within(&[points], 400)
}

/// [`predicate_exponent`] of several sets together, as if one, without
/// joining them.
pub(crate) fn common_predicate_exponent(sets: &[&[DVec2]]) -> Result<i32> {
    exponent_within(sets, 400)
}

/// [`predicate_exponent`] for the degree-4 incircle test: coordinates may span
/// at most 2^170 in ratio.
pub(crate) fn incircle_exponent(points: &[DVec2]) -> Result<i32> {
    exponent_within(&[points], 170)
}

/// With the largest coordinate within 2^±16 and none below 2^-(16 + span),
/// differences are at least 2^-(68 + span) and products of four of them stay
/// above 2^-969, where the predicates' expansions are exact.
fn exponent_within(sets: &[&[DVec2]], span_bits: i32) -> Result<i32> {
    let points = || sets.iter().flat_map(|set| set.iter());
    let largest = points().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    if largest == 0.0 {
        return Ok(0);
    }
    let floor = largest * 2f64.powi(-span_bits);
    let too_small = |x: f64| x != 0.0 && x.abs() < floor;
    if let Some((i, p)) = points()
        .enumerate()
        .find(|(_, p)| too_small(p.x) || too_small(p.y))
    {
        return Err(Error::out_of_range(format!(
            "point {i} ({:?}, {:?}) is too small beside the largest coordinate {largest:e}: \
             exact predicates take coordinates spanning at most 2^{span_bits} (about {:.0e}) in \
             ratio; round the small ones to 0 or drop the far points",
            p.x,
            p.y,
            2f64.powi(span_bits)
        )));
    }
    if (2f64.powi(-16)..2f64.powi(16)).contains(&largest) {
        return Ok(0);
    }
    let k = -(largest.log2().floor() as i32);
    let exact = |x: f64| times_power_of_two(times_power_of_two(x, k), -k) == x;
    match points()
        .enumerate()
        .find(|(_, p)| !exact(p.x) || !exact(p.y))
    {
        None => Ok(k),
        Some((i, p)) => Err(Error::out_of_range(format!(
            "point {i} ({:?}, {:?}) cannot be scaled exactly beside the largest coordinate \
             {largest:e}",
            p.x, p.y
        ))),
    }
}

/// The points scaled by `2^k`.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub fn scaled(points: &[DVec2], k: i32) -> Vec<DVec2> {
    points
        .iter()
        .map(|p| DVec2::new(times_power_of_two(p.x, k), times_power_of_two(p.y, k)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_is_exact_or_refused() {
        let tiny = [DVec2::new(1e-310, 3e-310), DVec2::new(5e-324, 0.0)];
        let k = predicate_exponent(&tiny).unwrap();
        assert!(k > 1000);
        let up = scaled(&tiny, k);
        assert_eq!(scaled(&up, -k), tiny);
        let huge = [DVec2::new(1e300, -1.7e308), DVec2::new(3e200, 0.5e190)];
        let k = predicate_exponent(&huge).unwrap();
        assert_eq!(scaled(&scaled(&huge, k), -k), huge);
        assert_eq!(predicate_exponent(&[DVec2::new(1.0, 2.0)]).unwrap(), 0);
        // Products of differences would underflow: refused.
        assert!(predicate_exponent(&[DVec2::new(1e300, 0.0), DVec2::new(1e-300, 0.0)]).is_err());
        assert!(predicate_exponent(&[DVec2::new(1e308, 1e155), DVec2::new(3.0, 0.5)]).is_err());
        assert!(incircle_exponent(&[DVec2::new(1e60, 0.0), DVec2::new(3.0, 0.0)]).is_err());
        assert!(predicate_exponent(&[DVec2::new(1e60, 0.0), DVec2::new(3.0, 0.0)]).is_ok());
    }
}
