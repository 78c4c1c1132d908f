//! Pictures of the envelopes a homothet is found on.

use super::*;

/// Which envelope a picture shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Envelope {
    /// The regions of the furthest sites (or of the k-th nearest), as `enclose`
    /// draws them.
    Enclosing { k: usize },
    /// The nearest-site regions, outside the region darkened, as `empty` draws them.
    Empty,
}

/// A picture (RGB rows) of the envelope behind `answer`, like the thesis's
/// Figs. 4.1 and 5.1: the regions coloured by their site, the point sites as
/// dots, the exact homothet's outline in red and its centre in yellow; with its
/// width and height. Enclosing pictures show the sites and the whole homothet.
pub fn picture(
    machine: &Machine,
    shapes: &[Site],
    unit: Unit,
    answer: &HomothetAnswer,
    envelope: Envelope,
    region: &Region,
) -> Result<(Vec<u8>, u32, u32)> {
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
        .collect();
    let sites = &sites[..];
    let labels = match envelope {
        Envelope::Enclosing { k } if k == 0 || k >= sites.len() => {
            crate::algorithms::higher_order::furthest(machine, sites, &frame, metric)?.labels
        }
        Envelope::Enclosing { k } => {
            kth_levels(machine, sites, frame, metric, k)?.level_labels(k as u32 - 1)
        }
        Envelope::Empty => {
            let options = VoronoiOptions {
                metric,
                distances: false,
                ..VoronoiOptions::exact(frame)
            };
            crate::algorithms::sites::voronoi_sites(machine, shapes, &options)?.labels
        }
    };
    let marks: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let mut rgb = crate::io::picture::label_rows(&labels, frame.width, 0, &marks, None);
    // A band about a pixel wide around the outline, in gauge units.
    let band = 0.8 / frame.scale * unit.lipschitz();
    let w = frame.width as usize;
    for (at, px) in rgb.chunks_exact_mut(3).enumerate() {
        let q = frame.to_world(DVec2::new((at % w) as f64, (at / w) as f64));
        if envelope == Envelope::Empty && !region.rings.is_empty() && !region.contains(q) {
            px.iter_mut().for_each(|v| *v = (*v as f32 * 0.35) as u8);
        }
        let g = unit.gauge(q - centre);
        if (g - scale).abs() <= band {
            px.copy_from_slice(&[220, 20, 30]);
        } else if q.distance(centre) * frame.scale <= 2.5 {
            px.copy_from_slice(&[255, 220, 0]);
        }
    }
    Ok((rgb, frame.width, frame.height))
}
