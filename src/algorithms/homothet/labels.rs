//! The envelope a homothet is found on, as each pixel's site.

use super::*;
use crate::memory::Gather;

/// Which envelope a picture shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Envelope {
    /// The regions of the furthest sites (or of the k-th nearest), as `enclose`
    /// draws them.
    Enclosing { k: usize },
    /// The nearest-site regions, outside the region darkened, as `empty` draws them.
    Empty,
}

/// The envelope behind `answer`, like the thesis's Figs. 4.1 and 5.1: each
/// pixel's site (the region it lies in), on the answer's frame for `empty` and
/// on one holding the sites and the whole homothet for `enclose`.
#[derive(Clone, Debug)]
pub struct EnvelopeLabels {
    pub frame: Frame,
    /// Each pixel's site, row-major.
    pub labels: Vec<u32>,
}

/// The envelope behind `answer` (see [`EnvelopeLabels`]).
pub fn envelope_labels(
    machine: &Machine,
    shapes: &[Site],
    unit: Unit,
    answer: &HomothetAnswer,
    envelope: Envelope,
) -> Result<EnvelopeLabels> {
    let metric = unit.cone_metric()?;
    let centre = DVec2::from(answer.exact.centre);
    let scale = answer.exact.scale;
    let frame = match envelope {
        Envelope::Empty => answer.frame,
        // The sites and the whole homothet, a little margin around them.
        Envelope::Enclosing { .. } => {
            let (qlo, qhi) = unit_box(unit);
            let (lo, hi) = shapes.iter().map(Site::bounds).fold(
                (centre + qlo * scale, centre + qhi * scale),
                |(a, b), (l, h)| (a.min(l), b.max(h)),
            );
            let pad = 0.03 * (hi - lo).max_element() + 1e-9;
            let side = answer.frame.width.max(answer.frame.height);
            Frame::fitting(side, lo - pad, hi + pad)?
        }
    };
    let sites: Vec<DVec2> = shapes
        .iter()
        .filter_map(|s| match s.shape {
            Shape::Point(p) => Some(p),
            _ => None,
        })
        .gather("sites")?;
    let sites = &sites[..];
    let labels = match envelope {
        Envelope::Enclosing { k } if k == 0 || k >= sites.len() => {
            crate::algorithms::higher_order::furthest(&machine.into(), sites, &frame, metric)?
                .labels
        }
        Envelope::Enclosing { k } => {
            kth_levels(machine, Checked::new(sites)?, frame, metric, k)?.level_labels(k as u32 - 1)
        }
        Envelope::Empty => {
            let options = VoronoiOptions {
                metric,
                distances: false,
                ..VoronoiOptions::exact(frame)
            };
            crate::algorithms::voronoi::voronoi(&machine.into(), shapes, &options)?.labels
        }
    };
    Ok(EnvelopeLabels { frame, labels })
}
