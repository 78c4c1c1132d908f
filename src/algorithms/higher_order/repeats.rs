//! Repeated sites in the k nearest: computed once per position, then spread
//! back over every input site at that position. A million copies of one point
//! would otherwise be a million cones at every pixel.

use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use super::KNearest;
use crate::{
    algorithms::certify::Certifier,
    error::Result,
    geometry::{
        frame::{distinct_by, Checked},
        metric::Metric,
        Frame,
    },
};

/// The k nearest of `sites` by `compute`, which is given each position once
/// (in the order of its first site) and at most k levels. Each pixel's levels
/// are then spread over the sites at each position: equally near positions
/// (consecutive levels, compared exactly) give their sites in index order, as
/// the diagram of all sites orders ties.
pub(crate) fn with_repeats(
    sites: Checked<'_>,
    frame: &Frame,
    metric: Metric,
    k: u32,
    compute: impl FnOnce(&[DVec2], u32) -> Result<KNearest>,
) -> Result<KNearest> {
    let sites = sites.sites();
    let (mut kept, repeats) = distinct_by(sites, 0..sites.len() as u32, |_| ());
    if repeats.is_empty() {
        return compute(sites, k);
    }
    kept.sort_unstable();
    // The sites at each position, ascending (the kept one is the smallest).
    let mut position = crate::memory::filled(sites.len(), 0u32, "the sites' positions")?;
    for (d, &i) in kept.iter().enumerate() {
        position[i as usize] = d as u32;
    }
    for &[repeat, first] in &repeats {
        position[repeat as usize] = position[first as usize];
    }
    let mut members: Vec<Vec<u32>> =
        crate::memory::filled(kept.len(), Vec::new(), "repeated sites")?;
    for (i, &d) in position.iter().enumerate() {
        members[d as usize].push(i as u32);
    }
    let distinct: Vec<DVec2> = kept.iter().map(|&i| sites[i as usize]).gather("distinct")?;
    let levels = k.min(distinct.len() as u32);
    let near = compute(&distinct, levels)?;
    let certifier = Certifier::new(&distinct, frame, metric)?;
    let tied = |a: u32, b: u32, pixel: [i64; 2]| {
        certifier.no_farther(a, &certifier, b, pixel)
            && certifier.no_farther(b, &certifier, a, pixel)
    };
    let (w, kd, ku) = (frame.width as usize, levels as usize, k as usize);
    let mut labels = crate::memory::filled(frame.len() * ku, u32::MAX, "labels")?;
    let mut distances = crate::memory::filled(frame.len() * ku, f32::INFINITY, "distances")?;
    labels
        .par_chunks_mut(ku)
        .zip(distances.par_chunks_mut(ku))
        .enumerate()
        .for_each(|(p, (labels, distances))| {
            let pixel = [(p % w) as i64, (p / w) as i64];
            let found = &near.labels[p * kd..][..kd];
            let far = &near.distances[p * kd..][..kd];
            let mut spread: Vec<(u32, f32)> = Vec::new();
            let mut run: Vec<(u32, f32)> = Vec::new();
            let mut l = 0;
            while l < kd && found[l] != u32::MAX && spread.len() < ku {
                // The levels tied with level l, their sites merged by index.
                let mut end = l + 1;
                while end < kd && found[end] != u32::MAX && tied(found[l], found[end], pixel) {
                    end += 1;
                }
                // Each position's sites are ascending: only the first few of
                // each can be among the k.
                let need = ku - spread.len();
                run.clear();
                for m in l..end {
                    let first = members[found[m] as usize].iter().take(need);
                    run.extend(first.map(|&i| (i, far[m])));
                }
                run.sort_unstable_by_key(|&(i, _)| i);
                spread.extend(run.iter().take(ku - spread.len()));
                l = end;
            }
            for (slot, (i, d)) in spread.into_iter().enumerate() {
                labels[slot] = i;
                distances[slot] = d;
            }
        });
    let mut stats = near.stats;
    stats.sites = sites.len();
    Ok(KNearest {
        k,
        labels,
        distances,
        stats,
        ..near
    })
}
