//! Great circles on the pixel machine, for a longitude-latitude grid of
//! places: the device is a filter with a proven error bound and the host
//! decides what is within it.
//!
//! The host lists for every tile (a square of pixels sized to hold about one
//! site, [`tile_side`]) the sites that can
//! be nearest to one of its pixels: those within `d + 2ρ` (chords) of the
//! tile's centre, where `d` is the centre's nearest site and `ρ` the tile's
//! reach from its centre. A pixel's nearest site is within `d + ρ` of it, so
//! within `d + 2ρ` of the centre. `glsl/great_circle.comp` then measures, per
//! pixel, the squared chords to its tile's list in float32 and marks the
//! pixels whose runner-up is within the error bound; those the host decides
//! as [`super::great_circle_nearest`] does, in doubles and then in rational
//! intervals. Distances are computed on the host in doubles from the label,
//! so both paths give the same labels and distances bit for bit.

use crate::memory::Gather;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::{angle, check, nearest, GreatCircle, Tree, EARTH_RADIUS};
use crate::{
    cancel::Watch,
    machine::{shaders, ComputeProgram, Extent, Machine, MAX_GROUPS},
    Error, Result,
};

/// The per-pixel search (push `[width, pixels, tile side, tiles across,
/// start of the ids]`, one invocation per pixel of a band).
static GREAT_CIRCLE: ComputeProgram = ComputeProgram::new(
    "GreatCircle",
    shaders::GREAT_CIRCLE_COMP,
    std::mem::size_of::<[u32; 5]>(),
    &[
        // Each column's cosine and sine, then each band row's.
        Extent::Push(|p| 8 * (p[0] as u64 + p[1].div_ceil(p[0].max(1)) as u64)),
        // The sites and their lists, indexed by the lists.
        Extent::ByData,
        Extent::ByData,
        // A label per pixel.
        Extent::Push(|p| 4 * p[1] as u64),
    ],
);

/// Pixels along a side of the tiles that share a list of sites: about one
/// site's share of the grid, between 4 and 16 (`docs/benchmarks.md`).
fn tile_side(pixels: usize, sites: usize) -> usize {
    ((pixels as f64 / sites as f64).sqrt() as usize).clamp(4, 16)
}

/// The largest band of pixels computed at once: one dispatch's limit.
const BAND_PIXELS: usize = MAX_GROUPS as usize * 64;

/// The label bit the device sets where the host must decide.
const UNSURE: u32 = 1 << 31;

/// [`super::great_circle_grid`] on `machine`: the answer is
/// [`super::great_circle_nearest`]'s for the same places, with
/// [`GreatCircle::decided_on_host`] counting the pixels the device left to
/// the host.
#[expect(
    clippy::disallowed_methods,
    reason = "one angle per grid line of a picture whose room was reserved where it was placed"
)]
pub(super) fn grid(
    machine: &Machine,
    sites: &[DVec2],
    lons: &[f64],
    lats: &[f64],
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<GreatCircle> {
    if sites.is_empty() {
        return Err(Error::too_few(1, 0, "no sites".into()));
    }
    if sites.len() >= UNSURE as usize {
        return Err(Error::out_of_range("too many sites".into()));
    }
    check(sites, "site")?;
    let corners: Vec<DVec2> = lons.iter().map(|&x| DVec2::new(x, 0.0)).gather("corners")?;
    check(&corners, "column")?;
    let corners: Vec<DVec2> = lats.iter().map(|&y| DVec2::new(0.0, y)).gather("corners")?;
    check(&corners, "row")?;
    let width = lons.len();
    if width == 0 || lats.is_empty() {
        return Ok(GreatCircle::default());
    }
    let side = tile_side(width * lats.len(), sites.len());
    if width * side > BAND_PIXELS {
        return Err(Error::out_of_range(format!(
            "a grid {width} pixels wide: great circles on the device take at most {} \
             columns",
            BAND_PIXELS / side
        )));
    }
    let tree = Tree::new(
        sites
            .iter()
            .map(|&p| super::unit_vector(p))
            .gather("tree")?,
    );
    let angles = |degrees: &[f64]| -> Vec<(f64, f64)> {
        degrees
            .iter()
            .map(|d| (d.to_radians().cos(), d.to_radians().sin()))
            .collect()
    };
    let (columns, rows) = (angles(lons), angles(lats));
    let mut site_buffer = machine.storage_buffer(16 * sites.len() as u64)?;
    let vectors: Vec<[f32; 4]> = tree
        .points
        .iter()
        .map(|v| [v.x as f32, v.y as f32, v.z as f32, 0.0])
        .gather("vectors")?;
    site_buffer.write(&vectors);
    let band_rows = (BAND_PIXELS / width) / side * side;
    let watch = Watch::current();
    let total = (width * lats.len()) as u64;
    let mut answer = GreatCircle::default();
    for first_row in (0..lats.len()).step_by(band_rows) {
        watch.check()?;
        let band = first_row..lats.len().min(first_row + band_rows);
        let grid = Grid {
            side,
            lons,
            lats: &lats[band.clone()],
            columns: &columns,
            rows: &rows[band.clone()],
        };
        let flagged = grid.search(machine, &tree, &site_buffer)?;
        // The host's part, row by row: unsure pixels decided, distances.
        let decided: Vec<(Vec<u32>, Vec<f64>, usize, usize)> = flagged
            .par_chunks(width)
            .zip(band.clone())
            .map(|(labels, j)| {
                let mut row = (
                    crate::memory::room(width, "a row's labels")?,
                    crate::memory::room(width, "a row's distances")?,
                    0,
                    0,
                );
                for (i, &flag) in labels.iter().enumerate() {
                    let u = grid_vector(columns[i], rows[j]);
                    let mut label = flag & !UNSURE;
                    if flag & UNSURE != 0 {
                        let (winner, tied) = nearest(&tree, sites, DVec2::new(lons[i], lats[j]), u);
                        label = winner;
                        row.2 += usize::from(tied);
                        row.3 += 1;
                    }
                    row.0.push(label);
                    row.1
                        .push(angle(u, tree.points[label as usize]) * EARTH_RADIUS);
                }
                Ok(row)
            })
            .collect::<Result<_>>()?;
        for (labels, distances, tied, on_host) in decided {
            answer.labels.extend(labels);
            answer.distances.extend(distances);
            answer.equidistant += tied;
            answer.decided_on_host += on_host;
        }
        progress(answer.labels.len() as u64, total);
    }
    Ok(answer)
}

/// A band of the grid: its columns' and rows' degrees, cosines and sines.
struct Grid<'a> {
    /// The tiles' side in pixels.
    side: usize,
    lons: &'a [f64],
    lats: &'a [f64],
    columns: &'a [(f64, f64)],
    rows: &'a [(f64, f64)],
}

impl Grid<'_> {
    /// Each pixel's nearest listed site from the device, [`UNSURE`] marking
    /// those the host must decide.
    fn search(
        &self,
        machine: &Machine,
        tree: &Tree,
        sites: &crate::machine::Buffer,
    ) -> Result<Vec<u32>> {
        let (width, height) = (self.lons.len(), self.lats.len());
        let across = width.div_ceil(self.side);
        let tiles = across * height.div_ceil(self.side);
        let lists: Vec<Vec<u32>> = (0..tiles)
            .into_par_iter()
            .map(|t| self.candidates(tree, t % across, t / across))
            .collect();
        let mut words = crate::memory::room(
            tiles + 1 + lists.iter().map(Vec::len).sum::<usize>(),
            "words",
        )?;
        let mut start = 0u32;
        for list in &lists {
            words.push(start);
            start += list.len() as u32;
        }
        words.push(start);
        words.extend(lists.into_iter().flatten());
        let mut list_buffer = machine.storage_buffer(4 * words.len() as u64)?;
        list_buffer.write(&words);
        let cosines: Vec<[f32; 2]> = self
            .columns
            .iter()
            .chain(self.rows)
            .map(|&(c, s)| [c as f32, s as f32])
            .gather("cosines")?;
        let mut grid_buffer = machine.storage_buffer(8 * cosines.len() as u64)?;
        grid_buffer.write(&cosines);
        let pixels = width * height;
        let labels = machine.storage_buffer(4 * pixels as u64)?;
        let push = [
            width as u32,
            pixels as u32,
            self.side as u32,
            across as u32,
            tiles as u32 + 1,
        ];
        machine.run(|pass| {
            pass.dispatch(
                &GREAT_CIRCLE,
                &[&grid_buffer, sites, &list_buffer, &labels],
                pixels as u32,
                bytemuck::bytes_of(&push),
            )
        })?;
        Ok(labels.read(pixels))
    }

    /// The sites that can be nearest to a pixel of tile (`tx`, `ty`).
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    fn candidates(&self, tree: &Tree, tx: usize, ty: usize) -> Vec<u32> {
        let side = self.side;
        let last = |n: usize, t: usize| (t * side, ((t + 1) * side).min(n) - 1);
        let (i0, i1) = last(self.lons.len(), tx);
        let (j0, j1) = last(self.lats.len(), ty);
        let (lon0, lon1) = (self.lons[i0], self.lons[i1]);
        let (lat0, lat1) = (self.lats[j0], self.lats[j1]);
        // A tile's farthest points from its centre are its corners while it
        // spans at most half a turn of longitude; wider ones list every site.
        if (lon1 - lon0).abs() > 180.0 {
            return (0..tree.points.len() as u32).collect();
        }
        let centre = super::unit_vector(DVec2::new(
            lon0 + (lon1 - lon0) / 2.0,
            lat0 + (lat1 - lat0) / 2.0,
        ));
        let reach = [(i0, j0), (i1, j0), (i0, j1), (i1, j1)]
            .iter()
            .map(|&(i, j)| (grid_vector(self.columns[i], self.rows[j]) - centre).length())
            .fold(0.0, f64::max);
        let nearest = tree.two_nearest(centre)[0].0.sqrt();
        // Room for the doubles' errors in the vectors and chords.
        tree.within(centre, nearest + 2.0 * reach + 1e-9)
    }
}

/// The unit vector of a grid point from its column's and row's cosine and
/// sine: [`super::unit_vector`]'s products, bit for bit.
fn grid_vector((cos_lon, sin_lon): (f64, f64), (cos_lat, sin_lat): (f64, f64)) -> DVec3 {
    DVec3::new(cos_lat * cos_lon, cos_lat * sin_lon, sin_lat)
}
