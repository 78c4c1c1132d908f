//! Distances between point sets (thesis §3.11).

use super::*;
use pixgeo::algorithms::distances::{self, Answer};

/// Two points, one of each set (indices into the sets as passed), and their exact
/// distance: the answer of the distance functions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoPair {
    pub from: u32,
    pub to: u32,
    pub distance: f64,
}

impl From<Answer> for PixgeoPair {
    fn from(answer: Answer) -> Self {
        Self {
            from: answer.pair.from,
            to: answer.pair.to,
            distance: answer.pair.distance,
        }
    }
}

/// Writes `answer` to `out`, which the caller guarantees is writable or null.
pub(super) fn answer_into(
    out: *mut PixgeoPair,
    answer: Answer,
) -> Result<(), (PixgeoStatus, String)> {
    // SAFETY: null or writable (caller contract of the public functions).
    match unsafe { out.as_mut() } {
        Some(slot) => {
            *slot = answer.into();
            Ok(())
        }
        None => Err(invalid("the answer pointer is null")),
    }
}

/// The Hausdorff distance between point sets `a` and `b` (thesis §3.11.1), both
/// directed distances, exact: `*a_to_b` gets the point of `a` farthest from its
/// nearest point of `b` (`from` in `a`, `to` in `b`), `*b_to_a` the converse.
/// The Hausdorff distance is the larger of the two.
///
/// # Safety
/// `ctx` is a live context; `a` holds `2 * a_count` doubles, `b` `2 * b_count`;
/// `a_to_b` and `b_to_a` point to writable pairs.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_hausdorff(
    ctx: *mut PixgeoContext,
    a: *const f64,
    a_count: usize,
    b: *const f64,
    b_count: usize,
    a_to_b: *mut PixgeoPair,
    b_to_a: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: sizes as documented (caller contract).
        let (a, b) = unsafe { (points(a, a_count)?, points(b, b_count)?) };
        let h = distances::hausdorff(
            &context.backend_for(Need::CpuUnlessGpu)?,
            &a,
            &b,
            &distances::HausdorffOptions::default(),
        )
        .map_err(failed)?;
        answer_into(a_to_b, h.a_to_b)?;
        answer_into(b_to_a, h.b_to_a)
    })
}

/// The diameter of a point set: the two points farthest apart (thesis §3.11.2),
/// exact.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `out` points to a
/// writable pair.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_diameter(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    out: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: size as documented (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let d =
            distances::diameter(context.machine("the diameter")?, &sites, None).map_err(failed)?;
        answer_into(out, d)
    })
}

/// The largest distance between a point of `a` and a point of `b` (thesis
/// §3.11.3), exact; `from` indexes `a`, `to` indexes `b`.
///
/// # Safety
/// As [`pixgeo_hausdorff`], with one writable pair `out`.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_max_distance(
    ctx: *mut PixgeoContext,
    a: *const f64,
    a_count: usize,
    b: *const f64,
    b_count: usize,
    out: *mut PixgeoPair,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        // SAFETY: sizes as documented (caller contract).
        let (a, b) = unsafe { (points(a, a_count)?, points(b, b_count)?) };
        let d = distances::max_distance(context.machine("the largest distance")?, &a, &b, None)
            .map_err(failed)?;
        answer_into(out, d)
    })
}
