//! Items binned to the screen tiles of a target, and the records image of
//! sites per screen tile that [`crate::algorithms::cones::NEAREST_TILES`]
//! reads.

use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use crate::{
    geometry::{
        metric::{DepthKey, Metric},
        radius::TileCandidates,
    },
    Result,
};

use super::{
    render::{Draws, TileView},
    SCREEN_TILE_SIDE,
};

/// Items binned to the screen tiles of a target: tile `t` (row-major, tiles of
/// [`SCREEN_TILE_SIDE`] pixels) holds `items[start[t]..start[t + 1]]`.
struct ScreenTiles {
    start: Vec<u32>,
    items: Vec<u32>,
    across: usize,
    /// The target's last pixel centre.
    last: DVec2,
}

impl ScreenTiles {
    /// The tiles of a `width` x `height` target whose pixel (0, 0) is picture
    /// pixel `origin`, each `(id, lo, hi)` of `boxes` going to every tile with a
    /// pixel centre in `[lo, hi]` (picture pixels). `None` where the tiles would
    /// hold more items than the target has pixels (64 per pixel): drawing them
    /// costs less then.
    fn bin(
        origin: DVec2,
        width: u32,
        height: u32,
        boxes: impl Iterator<Item = (u32, DVec2, DVec2)>,
    ) -> Result<Option<Self>> {
        let side = SCREEN_TILE_SIDE as usize;
        let across = (width as usize).div_ceil(side);
        let tiles = across * (height as usize).div_ceil(side);
        let last = DVec2::new(width as f64 - 1.0, height as f64 - 1.0);
        // Each item's tiles: first and last column and row.
        let spans: Vec<(u32, [usize; 4])> = boxes
            .filter_map(|(id, lo, hi)| {
                let first = (lo - origin).ceil().max(DVec2::ZERO);
                let end = (hi - origin).floor().min(last);
                (first.x <= end.x && first.y <= end.y).then(|| {
                    (
                        id,
                        [first.x, first.y, end.x, end.y].map(|v| v as usize / side),
                    )
                })
            })
            .gather("tile spans")?;
        let rows = |[x0, y0, x1, y1]: [usize; 4]| {
            (y0..=y1).map(move |y| y * across + x0..=y * across + x1)
        };
        let mut start = crate::memory::filled(tiles + 1, 0u32, "tile starts")?;
        for &(_, span) in &spans {
            for row in rows(span) {
                for t in row {
                    start[t + 1] += 1;
                }
            }
        }
        for t in 0..tiles {
            start[t + 1] += start[t];
        }
        if start[tiles] as u64 > width as u64 * height as u64 {
            return Ok(None);
        }
        let mut next = start[..tiles].to_vec();
        let mut items = crate::memory::filled(start[tiles] as usize, 0u32, "tile lists")?;
        for (id, span) in spans {
            for row in rows(span) {
                for t in row {
                    items[next[t] as usize] = id;
                    next[t] += 1;
                }
            }
        }
        Ok(Some(Self {
            start,
            items,
            across,
            last,
        }))
    }

    /// The tiles of a `width` x `height` target whose pixel (0, 0) is picture
    /// pixel `origin` (a multiple of the tile side), holding the `candidates`
    /// of the picture's tiles; `None` where they would hold more items than the
    /// target has pixels.
    fn of_candidates(
        candidates: &TileCandidates,
        origin: DVec2,
        width: u32,
        height: u32,
    ) -> Result<Option<Self>> {
        debug_assert_eq!(candidates.side, SCREEN_TILE_SIDE);
        let side = SCREEN_TILE_SIDE as usize;
        let across = (width as usize).div_ceil(side);
        let down = (height as usize).div_ceil(side);
        let (x0, y0) = (origin.x as usize / side, origin.y as usize / side);
        let picture_down = (candidates.start.len() - 1) / candidates.across;
        let list = |t: usize| {
            let (tx, ty) = (x0 + t % across, y0 + t / across);
            if tx < candidates.across && ty < picture_down {
                let k = ty * candidates.across + tx;
                &candidates.items[candidates.start[k] as usize..candidates.start[k + 1] as usize]
            } else {
                &[]
            }
        };
        let mut start = crate::memory::room(across * down + 1, "tile starts")?;
        start.push(0u32);
        for t in 0..across * down {
            start.push(start[t] + list(t).len() as u32);
        }
        if start[across * down] as u64 > width as u64 * height as u64 {
            return Ok(None);
        }
        let items = (0..across * down).flat_map(list).copied().gather("items")?;
        Ok(Some(Self {
            start,
            items,
            across,
            last: DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
        }))
    }

    /// The first and last pixel centre of tile `t` (target pixels).
    fn centres(&self, t: usize) -> (DVec2, DVec2) {
        let side = SCREEN_TILE_SIDE as f64;
        let lo = DVec2::new((t % self.across) as f64, (t / self.across) as f64) * side;
        (lo, (lo + side - 1.0).min(self.last))
    }

    fn tiles(&self) -> usize {
        self.start.len() - 1
    }

    /// The first item of tile `t` and the number of its items.
    fn range(&self, t: usize) -> (u32, u32) {
        (self.start[t], self.start[t + 1] - self.start[t])
    }
}

/// The records of [`crate::algorithms::cones::NEAREST_TILES`] for `view`: one texel per screen
/// tile (its first site texel and its number of sites), then its sites, a site
/// going to every tile with a pixel centre in its box. Where keys take powers,
/// each tile's sites come by the smallest key of a pixel of the tile from them,
/// so that a fragment can stop at the first that cannot beat its nearest: a
/// texel per site (x, y as float bits, that key as float bits, id). Other keys
/// cost less than the ordering, and their sites come by id, so that a fragment
/// needs ids only for its nearest: two texels per pair of sites (x, y, x, y as
/// float bits; 0, 0, id, id), a tile with an odd number repeating its last.
/// `None` where the lists would be too long.
pub(super) fn tile_records(view: &TileView, draws: &Draws<'_>) -> Result<Option<Vec<[u32; 4]>>> {
    let key = draws.key;
    let ordered = !matches!(
        key,
        DepthKey::Metric(Metric::L2 | Metric::L1 | Metric::LInf)
    );
    let bins = match draws.candidates {
        Some(candidates) => {
            ScreenTiles::of_candidates(candidates, view.origin, view.width, view.height)?
        }
        None => {
            let boxes = draws.cones.iter().map(|s| {
                let (lo, hi) = s.cone.clip();
                (s.cone.id, lo, hi)
            });
            ScreenTiles::bin(view.origin, view.width, view.height, boxes)?
        }
    };
    let Some(bins) = bins else {
        return Ok(None);
    };
    let tiles = bins.tiles();
    let site_texels = |t: usize| {
        let count = bins.range(t).1 as usize;
        if ordered {
            count
        } else {
            2 * count.div_ceil(2)
        }
    };
    let mut texels: Vec<[u32; 4]> =
        crate::memory::room(tiles + bins.items.len() + tiles, "tile records")?;
    let mut next = tiles;
    texels.extend((0..tiles).map(|t| {
        let first = next as u32;
        next += site_texels(t);
        [first, bins.range(t).1, 0, 0]
    }));
    texels.resize(next, [0; 4]);
    let mut sites = &mut texels[tiles..];
    let mut lists = crate::memory::room(tiles, "tiles' records")?;
    for t in 0..tiles {
        let (list, rest) = sites.split_at_mut(site_texels(t));
        lists.push(list);
        sites = rest;
    }
    lists
        .into_par_iter()
        .enumerate()
        .for_each_init(Vec::new, |entries, (t, list)| {
            let (first, count) = bins.range(t);
            let (lo, hi) = bins.centres(t);
            let (lo, hi) = (lo + view.origin, hi + view.origin);
            entries.clear();
            entries.extend(
                bins.items[first as usize..(first + count) as usize]
                    .iter()
                    .map(|&id| {
                        // The device's coordinates, and a margin for its rounding.
                        let site = draws.sites[id as usize].as_vec2();
                        let least = match ordered {
                            true => {
                                let site = site.as_dvec2();
                                (key.of_offset(site - site.clamp(lo, hi)) * (1.0 - 1e-4)) as f32
                            }
                            false => 0.0,
                        };
                        (least, id, site)
                    }),
            );
            entries.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            if ordered {
                for (&(least, id, site), texel) in entries.iter().zip(list) {
                    *texel = [site.x.to_bits(), site.y.to_bits(), least.to_bits(), id];
                }
            } else {
                for (pair, texels) in entries.chunks(2).zip(list.chunks_exact_mut(2)) {
                    let (a, b) = (pair[0], pair[pair.len() - 1]);
                    texels[0] = [a.2.x, a.2.y, b.2.x, b.2.y].map(f32::to_bits);
                    texels[1] = [0, 0, a.1, b.1];
                }
            }
        });
    Ok(Some(texels))
}
