//! The Voronoi diagram of general sites on the CPU, for machines without a
//! GPU driver: exact, as the drawn route's certified labels are.

use super::{check_exact_metric, SiteCertifier};
use crate::{
    algorithms::higher_order::cpu::nearest_by_blocks,
    error::Result,
    geometry::{
        metric::Metric,
        site::{check_general_sites, Site},
        Frame,
    },
};

/// The Voronoi diagram of sites of any shape and weight on the CPU: every pixel
/// labelled with a site of smallest weighted distance (ties to the lower index),
/// and that distance (world units), row-major. Exact.
///
/// The thesis's growth through one offset table (§3.12.1) assumes sites that are
/// unweighted points (`k_nearest_checked`); here each 32² block of pixels orders the
/// sites by a lower bound of their weighted distance over the block (from the
/// Euclidean gap between the block and the shape's box) and every pixel stops at
/// the first site whose bound exceeds its best.
pub(crate) fn voronoi_sites(
    sites: &[Site],
    frame: &Frame,
    metric: Metric,
) -> Result<(Vec<u32>, Vec<f32>)> {
    check_general_sites(sites)?;
    check_exact_metric(sites, metric)?;
    let (mut labels, mut distances) = nearest_by_blocks(sites, frame, metric)?;
    SiteCertifier::new(sites, frame, metric)?.certify(&mut labels, Some(&mut distances))?;
    Ok((labels, distances))
}
