//! Higher-order Voronoi diagrams (thesis §3.7): for every pixel its k nearest sites
//! in order (the degree 1..k diagrams at once), the set of its k nearest (the
//! order-k diagram), and the furthest site (§3.7.1).
//!
//! The thesis peels the arrangement of cones level by level with two depth buffers
//! ([`k_nearest_peeled`], one cone pass a level, ties between equally far sites
//! peeled in the order of their ids). pixgeo draws the cones once ([`k_nearest`]): exact
//! cones are binned to screen tiles, and each tile's rectangle keeps, per
//! fragment, the ids of the k nearest of its cones (`glsl/cone_tiles.frag`),
//! whose distances the host computes; fan cones, or more levels than a tile
//! keeps, insert keys (squared distance, site id) into per-pixel sorted lists
//! with 64-bit atomic min (`glsl/cone_knearest.frag`). Equidistant sites each
//! keep their own level, so multiplicities come out right, and the levels are
//! ordered by distance, ties by site id. Where several sites are equally far at
//! the k-th level, which of them is kept is fixed but not the lowest id in the
//! tiled path: comparing ids there cost a fifth of its rendering.
//!
//! The furthest-site diagram is the lower envelope of cones turned upside down:
//! one pass with the depth test GREATER. Only the vertices of the convex hull own
//! furthest regions, so only their cones are drawn.
//!
//! The file is long because it holds the three routes to the k nearest (peeling,
//! screen tiles, per-pixel lists) and the furthest-site diagram, which share tile
//! lists, keys and readback.

use super::ms;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;
use serde::Serialize;

use crate::{
    error::{Error, Result},
    geometry::{
        chain::{unit_fan_over, MetricFan},
        cone::{fan_distance_error, unit_fan, unit_footprint, FanShape},
        frame::{check_sites, distance2_to_rect, distinct_by, lexicographic},
        metric::Metric,
        radius, Frame,
    },
    machine::{
        Buffer, Clear, ClearColor, Compare, DepthTest, DrawParams, Format, Image, Machine, Pass,
        PixelRect, RasterState, Target,
    },
};

use super::cones::{
    draw_cones, draw_k_nearest_tiles, ConeDraw, ConeInstance, ConePush, CONE_EXACT, CONE_FAN,
    CONE_K_NEAREST, CONE_K_NEAREST_FAN, CONE_PEEL,
};

use super::envelope::distances_of;
use super::envelope::{drawn_accuracy, metric_fan, Accuracy, Speedup};

/// Corners of the polygon drawn around each cone's disc.
const FOOTPRINT_CORNERS: u32 = 8;

/// Largest number of levels kept per pixel.
pub const MAX_LEVELS: u32 = 256;

/// Keys kept per pixel take 8 bytes each; beyond this many bytes in all, a picture
/// is refused rather than exhausting memory.
const MAX_KEY_BYTES: u64 = 4 << 30;

/// What to compute: start from [`KNearestOptions::exact`] and change what
/// differs, by field or by setter.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct KNearestOptions {
    pub frame: Frame,
    /// Levels per pixel: the 1st to the k-th nearest site.
    pub k: u32,
    /// The distance function (thesis §3.6); others than L2 need exact mode.
    pub metric: Metric,
    /// Exact squared distances per fragment, or the thesis's triangle fans (one
    /// triangle count for all cones: the largest cone's for `epsilon`, or the
    /// given one).
    pub accuracy: Accuracy,
    /// How far cones reach: [`Speedup::Quadtree`] is thesis Theorem 3.3 (cells with
    /// at least k sites bound the cone height), [`Speedup::Local`] a radius per site
    /// from the k-th nearest sites around it.
    pub speedup: Speedup,
}

impl KNearestOptions {
    /// `k` levels of exact Euclidean distances on `frame`, with local radii.
    pub fn exact(frame: Frame, k: u32) -> Self {
        Self {
            frame,
            k,
            metric: Metric::L2,
            accuracy: Accuracy::Exact,
            speedup: Speedup::Local,
        }
    }

    pub fn frame(self, frame: Frame) -> Self {
        Self { frame, ..self }
    }

    pub fn k(self, k: u32) -> Self {
        Self { k, ..self }
    }

    pub fn metric(self, metric: Metric) -> Self {
        Self { metric, ..self }
    }

    pub fn accuracy(self, accuracy: Accuracy) -> Self {
        Self { accuracy, ..self }
    }

    pub fn speedup(self, speedup: Speedup) -> Self {
        Self { speedup, ..self }
    }
}

impl Default for KNearestOptions {
    /// The 3 nearest sites, exact, on 1024 x 1024 pixels.
    fn default() -> Self {
        Self::exact(Frame::pixels(1024, 1024).expect("a valid picture"), 3)
    }
}

/// How the diagram was made.
#[derive(Clone, Debug, Default, Serialize)]
pub struct KNearestStats {
    pub device: String,
    pub sites: usize,
    pub levels: u32,
    /// Cones drawn (sites whose cone reaches the picture).
    pub cones: usize,
    /// Triangles per fan cone (0 in exact mode).
    pub triangles: u32,
    /// Guaranteed bound on the distance overestimate (world units); 0 when exact.
    pub distance_error_bound: f64,
    /// Cone radii in pixels: smallest, mean, largest.
    pub radius_min: f64,
    pub radius_mean: f64,
    pub radius_max: f64,
    /// Milliseconds: cone sizing on the CPU, rendering, reading the lists back.
    pub bounds_ms: f64,
    pub render_ms: f64,
    pub readback_ms: f64,
}

/// The k nearest sites of every pixel.
#[derive(Clone, Debug)]
pub struct KNearest {
    pub width: u32,
    pub height: u32,
    /// The picture: [`Frame::to_world`] maps its pixels to world points.
    pub frame: Frame,
    pub k: u32,
    /// `labels[(j * width + i) * k + l]`: the (l+1)-th nearest site of pixel (i, j);
    /// `u32::MAX` where fewer than l+1 sites exist.
    pub labels: Vec<u32>,
    /// Distances in world units, same layout; infinite where no site is.
    pub distances: Vec<f32>,
    pub stats: KNearestStats,
}

impl KNearest {
    /// Level `l` (0 = nearest) as a row-major picture of labels.
    pub fn level_labels(&self, l: u32) -> Vec<u32> {
        self.labels
            .chunks_exact(self.k as usize)
            .map(|keys| keys[l as usize])
            .collect()
    }

    /// Level `l` (0 = nearest) as a row-major picture of distances.
    pub fn level_distances(&self, l: u32) -> Vec<f32> {
        self.distances
            .chunks_exact(self.k as usize)
            .map(|keys| keys[l as usize])
            .collect()
    }

    /// The order-k diagram: each pixel's set of k nearest sites, sorted by id
    /// (`u32::MAX` last, where fewer than k sites exist).
    pub fn order_sets(&self) -> Vec<u32> {
        let mut sets = self.labels.clone();
        sets.par_chunks_mut(self.k as usize)
            .for_each(|set| set.sort_unstable());
        sets
    }
}

/// Computes every pixel's k nearest sites (world coordinates).
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::higher_order::{k_nearest, KNearestOptions}, geometry::{metric::Metric, Frame}};
///
/// let sites = [DVec2::new(1.0, 1.0), DVec2::new(7.0, 1.0), DVec2::new(4.0, 6.0)];
/// let options = KNearestOptions::exact(Frame::pixels(8, 8)?, 3).metric(Metric::LInf);
/// let near = pixgeo::with_default_machine(|m| k_nearest(m, &sites, &options))?;
/// assert_eq!(near.level_labels(2)[0], 1); // the farthest of pixel (0, 0)
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn k_nearest(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    let options = &KNearestOptions {
        accuracy: drawn_accuracy(options.metric, options.accuracy),
        ..*options
    };
    let frame = options.frame;
    let k = options.k;
    check_levels(machine, sites, options)?;
    let key_bytes = frame.len() as u64 * k as u64 * 8;
    if key_bytes > MAX_KEY_BYTES {
        return Err(Error::InvalidInput(format!(
            "{k} levels of {}x{} pixels need {} MiB of keys; use fewer levels or a smaller picture",
            frame.width,
            frame.height,
            key_bytes >> 20
        )));
    }
    // Exact cones binned to screen tiles need only storage writes; fans are
    // rasterized and insert with 64-bit atomics.
    let tiled = options.accuracy == Accuracy::Exact && k <= TILE_LEVELS;
    let supported = if tiled {
        machine.has_fragment_stores()
    } else {
        machine.has_fragment_atomics64()
    };
    if !supported {
        return Err(Error::InvalidInput(format!(
            "{} cannot write storage buffers (with 64-bit atomics for fans or more than \
             {TILE_LEVELS} levels) from fragment shaders, which the k nearest sites need; \
             use --device cpu",
            machine.device_name()
        )));
    }
    let started = Instant::now();
    if tiled {
        return k_nearest_tiled(machine, sites, options, started);
    }
    let (cones, mut stats) = level_cones(machine, sites, options);
    // The mesh, each cone's outer radius, and the fan's error bound.
    let (program, mesh, outer) = match options.accuracy {
        Accuracy::Exact => (
            &CONE_K_NEAREST,
            unit_footprint(FOOTPRINT_CORNERS),
            Rim::Circumscribed(FOOTPRINT_CORNERS),
        ),
        Accuracy::Fan {
            epsilon,
            triangles: None,
        } => {
            crate::geometry::cone::check_fan_size(stats.radius_max, epsilon)?;
            let t = FanShape::for_distance_error(stats.radius_max, epsilon).triangles;
            stats.triangles = t;
            stats.distance_error_bound = epsilon / frame.scale;
            (&CONE_K_NEAREST_FAN, unit_fan(t), Rim::Beyond(epsilon))
        }
        Accuracy::Fan {
            triangles: Some(t), ..
        } => {
            stats.triangles = t;
            stats.distance_error_bound = fan_distance_error(stats.radius_max, t) / frame.scale;
            (&CONE_K_NEAREST_FAN, unit_fan(t), Rim::Circumscribed(t))
        }
    };
    // Other metrics' fans: one mesh over the chain (or sample) of the widest cone.
    let (mesh, outer) = match options.accuracy {
        Accuracy::Fan { .. } if options.metric != Metric::L2 => {
            let fan = metric_fan(options.accuracy);
            let widest = fan.outer_radius(options.metric, stats.radius_max);
            let mesh = fan.unit_mesh(options.metric, widest);
            stats.triangles = mesh.len() as u32 - 2;
            stats.distance_error_bound =
                fan.error_bound(options.metric, stats.radius_max) / frame.scale;
            (mesh, Rim::Metric(fan, options.metric))
        }
        _ => (mesh, outer),
    };
    let instances: Vec<ConeInstance> = cones
        .iter()
        .map(|&(i, p, r)| ConeInstance::new(i, p.into(), outer.radius(r), r))
        .collect();
    // Fan heights map into the depth range by a power of two, which keeps them
    // exact; exact keys hold squared distances as they are.
    let reach = instances
        .iter()
        .map(|c| c.site[2] as f64)
        .fold(1.0, f64::max)
        * 1.001;
    let vertex_scale = reach.log2().ceil().exp2().recip();
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let mut keys = machine.readback_buffer(key_bytes)?;
    keys.fill(0xFF);
    if !instances.is_empty() {
        let mesh_buffer = machine.vertex_buffer(&mesh)?;
        let instance_buffer = machine.vertex_buffer(&instances)?;
        let push = ConePush {
            vertex_depth_scale: vertex_scale as f32,
            ..picture_push(&frame, k, options.metric)
        };
        let depth = machine.image(Format::Depth, frame.width, frame.height)?;
        draw_to_buffers(machine, &depth, &[&keys], None, |pass| {
            draw_cones(
                pass,
                program,
                &RasterState::OVERWRITE,
                &DrawParams::default(),
                &push,
                &ConeDraw {
                    mesh: &mesh_buffer,
                    first_vertex: 0,
                    vertex_count: mesh.len() as u32,
                    instances: &instance_buffer,
                    first_instance: 0,
                    instance_count: instances.len() as u32,
                },
            )
        })?;
    }
    stats.render_ms = ms(started);

    let fan_scale = (options.accuracy != Accuracy::Exact).then_some(1.0 / vertex_scale);
    Ok(read_keys(&keys, options, fan_scale, stats))
}

/// Where a cone's rim vertices lie for a cone that must reach radius r.
#[derive(Clone, Copy)]
enum Rim {
    /// A polygon of this many corners around the disc.
    Circumscribed(u32),
    /// A fan whose height error stays below epsilon out to r (thesis §3.3).
    Beyond(f64),
    /// A fan of another metric (thesis §3.6.1–3.6.2).
    Metric(MetricFan, Metric),
}

impl Rim {
    fn radius(self, r: f64) -> f64 {
        match self {
            Rim::Circumscribed(corners) => FanShape::with_triangles(r, corners).outer_radius,
            Rim::Beyond(epsilon) => r + epsilon,
            Rim::Metric(fan, metric) => fan.outer_radius(metric, r),
        }
    }
}

/// Most levels a tile fragment keeps (`glsl/cone_tiles.frag`: MAX_LEVELS).
const TILE_LEVELS: u32 = 32;

/// Texels per row of the image that holds the tiles' cones
/// (`glsl/cone_tiles.frag`: RECORD_ROW); every device has images this wide.
const RECORD_ROW: usize = 4096;

/// Side of a screen tile in pixels. Smaller tiles hold fewer cones per fragment
/// but cost more rectangles and more binning.
const TILE_SIDE: u32 = 16;

/// The k nearest sites of exact cones, by screen tiles: each tile is one
/// rectangle whose fragments keep the k lowest layers of the tile's cones in
/// registers and store them once, so no pixel is written twice and no atomics
/// are needed. A tile's cones come in order of distance from its centre, so
/// that the lists mostly fill nearest first. With per-site radii the lists come
/// from the cells' bound directly ([`radius::k_tile_lists`]); otherwise a cone
/// goes to every tile its disc meets.
fn k_nearest_tiled(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
    started: Instant,
) -> Result<KNearest> {
    let (frame, k) = (options.frame, options.k);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let tiles = if options.speedup == Speedup::Local {
        let mut tiles = radius::k_tile_lists(
            &pixels,
            &frame,
            k as usize,
            TILE_SIDE,
            options.metric.stretch(),
        );
        for (r, p) in tiles.radii.iter_mut().zip(&pixels) {
            *r = (*r + 0.5).min(frame.farthest_pixel(*p) + 0.5);
        }
        tiles
    } else {
        let radii = k_radii(&pixels, &frame, k as usize, options.speedup, options.metric);
        bin_to_tiles(&pixels, &frame, radii)
    };
    let cones = drawn_cones(&pixels, &tiles.radii, &frame);
    let mut stats = cone_stats(machine, sites.len(), options.k, cones);
    let binned = &tiles.lists;
    // Tile records (six words each) for the vertex shader; the cones (one texel
    // each) for the fragment shader, rows of RECORD_ROW texels. Every tile is
    // drawn, those without cones too: its fragments write "no site", so the keys
    // need no filling first.
    let mut words: Vec<u32> = Vec::with_capacity(6 * binned.len());
    let mut next = 0u32;
    for (t, list) in binned.iter().enumerate() {
        let (lo, hi) = tiles.rect(t, &frame);
        words.extend([lo.x, lo.y, hi.x, hi.y].map(|v| (v as f32).to_bits()));
        words.extend([next, list.len() as u32]);
        next += list.len() as u32;
    }
    let rows = (next as usize).div_ceil(RECORD_ROW).max(1);
    let most = machine.max_picture_side() as usize;
    if rows > most {
        return Err(Error::InvalidInput(format!(
            "the cones of {k} levels meet screen tiles {next} times, more than this device \
             holds ({}); use the speedup, fewer levels or a smaller picture",
            most * RECORD_ROW
        )));
    }
    let mut texels: Vec<[u32; 4]> = Vec::with_capacity(rows * RECORD_ROW);
    let lower = options.metric.euclidean_bounds().0;
    for (t, list) in binned.iter().enumerate() {
        let (lo, hi) = tiles.rect(t, &frame);
        let (centre, half_diagonal) = ((lo + hi) / 2.0, (hi - lo).length() / 2.0);
        texels.extend(list.iter().map(|&i| {
            let p = pixels[i as usize];
            // The smallest key any pixel of the tile can have for this site, a
            // little less for the device's rounding.
            let reach = ((p.distance(centre) - half_diagonal) * lower).max(0.0);
            let reach_key = options.metric.key_of_distance(reach) * (1.0 - 1e-5);
            [
                (p.x as f32).to_bits(),
                (p.y as f32).to_bits(),
                (reach_key as f32).to_bits(),
                i,
            ]
        }));
    }
    let width = if rows == 1 {
        texels.len().max(1)
    } else {
        RECORD_ROW
    };
    texels.resize(rows * width, [0; 4]);
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let labels = machine.readback_buffer(frame.len() as u64 * k as u64 * 4)?;
    let mut tiles = machine.readback_buffer(4 * words.len() as u64)?;
    tiles.write(&words);
    let mut upload = machine.readback_buffer(16 * texels.len() as u64)?;
    upload.write(&texels);
    let records = machine.image(Format::Rgba32Uint, width as u32, rows as u32)?;
    let depth = machine.image(Format::Depth, frame.width, frame.height)?;
    draw_to_buffers(
        machine,
        &depth,
        &[&labels, &tiles],
        Some((&upload, &records)),
        |pass| {
            draw_k_nearest_tiles(
                pass,
                &RasterState::OVERWRITE,
                &DrawParams::default(),
                &picture_push(&frame, k, options.metric),
                binned.len() as u32,
            )
        },
    )?;
    stats.render_ms = ms(started);
    Ok(read_labels(&labels, &pixels, options, stats))
}

/// Push constants for drawing on the whole `frame` with `levels` per pixel.
fn picture_push(frame: &Frame, levels: u32, metric: Metric) -> ConePush {
    ConePush {
        picture_size: [frame.width as f32, frame.height as f32],
        offset: [0.0, 0.0],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: 0.0,
        levels,
        // Exact programs never see a polygon (drawn as fans instead).
        metric: metric.shader_code().unwrap_or((0, 2.0)).into(),
    }
}

/// Runs `draw` in a rendering pass over the picture of `depth` (which just
/// gives the pass its size) whose fragments write only the storage `buffers`,
/// with `records` (an upload and the image it fills) for the fragments to read.
fn draw_to_buffers<'r>(
    machine: &Machine,
    depth: &'r Image,
    buffers: &[&'r Buffer],
    records: Option<(&'r Buffer, &'r Image)>,
    draw: impl FnOnce(&mut Pass<'_, 'r>) -> Result<()>,
) -> Result<()> {
    machine.run(|pass| {
        if let Some((upload, image)) = records {
            pass.upload_for_fragments(upload, image)?;
        }
        pass.bind_fragment_buffers(buffers, records.map(|(_, image)| image))?;
        pass.begin(
            Target {
                color: None,
                depth_stencil: Some(depth),
            },
            Clear {
                color: None,
                depth: Some(1.0),
                stencil: None,
            },
        )?;
        draw(pass)?;
        pass.end()
    })
}

/// The k nearest sites from the pixels' keys (distance bits above the site id):
/// metric keys when `fan_scale` is `None`, else fan heights times it.
fn read_keys(
    keys: &Buffer,
    options: &KNearestOptions,
    fan_scale: Option<f64>,
    mut stats: KNearestStats,
) -> KNearest {
    let started = Instant::now();
    let (frame, k, metric) = (options.frame, options.k, options.metric);
    let key_bytes = frame.len() * k as usize * 8;
    let raw: &[u64] = bytemuck::cast_slice(&keys.mapped()[..key_bytes]);
    let to_world = (1.0 / frame.scale) as f32;
    let (labels, distances) = raw
        .par_iter()
        .map(|&key| {
            if key == u64::MAX {
                return (u32::MAX, f32::INFINITY);
            }
            let value = f32::from_bits((key >> 32) as u32);
            let distance = match fan_scale {
                None => metric.distance_of_key(value as f64) as f32,
                Some(unscale) => value * unscale as f32,
            };
            (key as u32, distance * to_world)
        })
        .unzip();
    stats.readback_ms = ms(started);
    KNearest {
        width: frame.width,
        height: frame.height,
        frame,
        k,
        labels,
        distances,
        stats,
    }
}

/// The levels from a buffer of `k` ids per pixel (nearest first, `u32::MAX` for
/// none), with the distances computed from the sites' `pixels` positions (keys
/// in double precision, rounded to float32) and each pixel's levels ordered by
/// them, ties by id.
fn read_labels(
    ids: &Buffer,
    pixels: &[DVec2],
    options: &KNearestOptions,
    mut stats: KNearestStats,
) -> KNearest {
    let started = Instant::now();
    let (frame, k, metric) = (options.frame, options.k as usize, options.metric);
    let width = frame.width as usize;
    let ids: &[u32] = bytemuck::cast_slice(&ids.mapped()[..frame.len() * k * 4]);
    let mut labels = vec![0u32; ids.len()];
    let mut distances = vec![0f32; ids.len()];
    let to_world = (1.0 / frame.scale) as f32;
    let row = k * width;
    ids.par_chunks(row)
        .zip(labels.par_chunks_mut(row))
        .zip(distances.par_chunks_mut(row))
        .enumerate()
        .for_each(|(j, ((ids, labels), distances))| {
            labels.copy_from_slice(ids);
            // L2 on its own: the metric's match out of the innermost loops.
            let at = (pixels, j);
            match metric {
                Metric::L2 => {
                    level_distances(labels, distances, k, at, DVec2::length_squared, |key| {
                        key.sqrt() * to_world
                    })
                }
                _ => level_distances(
                    labels,
                    distances,
                    k,
                    at,
                    |d| metric.key(d),
                    |key| metric.distance_of_key(key as f64) as f32 * to_world,
                ),
            }
        });
    stats.readback_ms = ms(started);
    KNearest {
        width: frame.width,
        height: frame.height,
        frame,
        k: options.k,
        labels,
        distances,
        stats,
    }
}

/// The distances in world units of row `j`'s levels (`k` per pixel), each
/// pixel's levels ordered by them: first the metric's keys, by which the levels
/// are ordered, then their distances in one pass over the row, which the
/// compiler vectorizes (a square root per level cost as much as all else).
fn level_distances(
    labels: &mut [u32],
    distances: &mut [f32],
    k: usize,
    (pixels, j): (&[DVec2], usize),
    key: impl Fn(DVec2) -> f64,
    distance_of_key: impl Fn(f32) -> f32,
) {
    let levels = labels
        .chunks_exact_mut(k)
        .zip(distances.chunks_exact_mut(k));
    for (i, (labels, keys)) in levels.enumerate() {
        let q = DVec2::new(i as f64, j as f64);
        // Keys are not negative, so their bits order as integers.
        let (mut sorted, mut last) = (true, 0u64);
        for (d, &id) in keys.iter_mut().zip(labels.iter()) {
            *d = pixels
                .get(id as usize)
                .map_or(f32::INFINITY, |&p| key(p - q) as f32);
            let key = (d.to_bits() as u64) << 32 | id as u64;
            sorted &= last <= key;
            last = key;
        }
        if !sorted {
            sort_levels(labels, keys);
        }
    }
    for d in distances {
        *d = distance_of_key(*d);
    }
}

/// Orders one pixel's levels by key, ties by id: the device's order but for its
/// rounding and the order of equal keys, so an insertion sort that mostly only
/// looks.
fn sort_levels(labels: &mut [u32], distances: &mut [f32]) {
    for l in 1..labels.len() {
        let (id, d) = (labels[l], distances[l]);
        let mut m = l;
        while m > 0 && (distances[m - 1], labels[m - 1]) > (d, id) {
            labels[m] = labels[m - 1];
            distances[m] = distances[m - 1];
            m -= 1;
        }
        labels[m] = id;
        distances[m] = d;
    }
}

/// The checks every way of computing levels shares.
fn check_levels(machine: &Machine, sites: &[DVec2], options: &KNearestOptions) -> Result<()> {
    check_sites(sites)?;
    options.accuracy.check()?;
    let frame = options.frame;
    frame.check()?;
    let k = options.k;
    if k == 0 || k > MAX_LEVELS {
        return Err(Error::InvalidInput(format!(
            "the number of levels must be 1 to {MAX_LEVELS}, not {k}"
        )));
    }
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::InvalidInput(format!(
            "higher-order diagrams are drawn in one image of at most {side}x{side} pixels on this device"
        )));
    }
    Ok(())
}

/// The cones (site index, pixel position, radius) that reach the picture, and the
/// statistics that describe them.
fn level_cones(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> (Vec<(u32, DVec2, f64)>, KNearestStats) {
    let frame = options.frame;
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let radii = k_radii(
        &pixels,
        &frame,
        options.k as usize,
        options.speedup,
        options.metric,
    );
    let cones: Vec<(u32, DVec2, f64)> = drawn_cones(&pixels, &radii, &frame).collect();
    let stats = cone_stats(machine, sites.len(), options.k, cones.iter().copied());
    (cones, stats)
}

/// The cones (site index, pixel position, radius) of these radii that reach
/// the picture.
fn drawn_cones<'a>(
    pixels: &'a [DVec2],
    radii: &'a [f64],
    frame: &'a Frame,
) -> impl Iterator<Item = (u32, DVec2, f64)> + 'a {
    pixels
        .iter()
        .zip(radii)
        .enumerate()
        .filter(|(_, (p, r))| **r > 0.0 && frame.distance_to_pixels(**p) <= **r)
        .map(|(i, (p, r))| (i as u32, *p, *r))
}

/// The statistics of the cones that are drawn.
fn cone_stats(
    machine: &Machine,
    sites: usize,
    levels: u32,
    cones: impl Iterator<Item = (u32, DVec2, f64)>,
) -> KNearestStats {
    let mut stats = KNearestStats {
        device: machine.device_name().to_string(),
        sites,
        levels,
        radius_min: f64::INFINITY,
        ..Default::default()
    };
    for (_, _, r) in cones {
        stats.cones += 1;
        stats.radius_min = stats.radius_min.min(r);
        stats.radius_max = stats.radius_max.max(r);
        stats.radius_mean += r;
    }
    if stats.cones == 0 {
        stats.radius_min = 0.0;
    } else {
        stats.radius_mean /= stats.cones as f64;
    }
    stats
}

/// Site indices per screen tile for cones of the given radii: a cone goes to
/// every tile its disc meets, nearest to the tile's centre first.
fn bin_to_tiles(pixels: &[DVec2], frame: &Frame, radii: Vec<f64>) -> radius::TileLists {
    let mut tiles = radius::TileLists {
        across: frame.width.div_ceil(TILE_SIDE) as usize,
        side: TILE_SIDE,
        ..Default::default()
    };
    let down = frame.height.div_ceil(TILE_SIDE) as usize;
    let mut binned: Vec<Vec<(f64, u32)>> = vec![Vec::new(); tiles.across * down];
    for (i, p, r) in drawn_cones(pixels, &radii, frame) {
        let cell = |v: f64, n: usize| ((v / TILE_SIDE as f64).floor().max(0.0) as usize).min(n - 1);
        for y in cell(p.y - r, down)..=cell(p.y + r, down) {
            for x in cell(p.x - r, tiles.across)..=cell(p.x + r, tiles.across) {
                let t = y * tiles.across + x;
                let (lo, hi) = tiles.rect(t, frame);
                if distance2_to_rect(p, lo, hi) <= r * r {
                    binned[t].push((p.distance_squared((lo + hi) * 0.5), i));
                }
            }
        }
    }
    tiles.lists = binned
        .into_par_iter()
        .map(|mut list| {
            list.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            list.into_iter().map(|(_, i)| i).collect()
        })
        .collect();
    tiles.radii = radii;
    tiles
}

/// Computes every pixel's k nearest sites by the thesis's peeling (§3.7): level
/// by level, the cones are drawn against the previous level's depth z and site,
/// held in a storage buffer, and only fragments after that level in the order
/// (distance, site id) take part, so that the depth test LESS, over cones drawn
/// in the order of their ids, finds the next layer.
///
/// The thesis's second depth test keeps fragments strictly deeper than z and
/// counts equally far sites with the stencil, repeating the first one's site on
/// each of their levels; ordering ties by id instead names every equally far
/// site on a level of its own, so that the sets of the order-k diagram hold k
/// distinct sites. The levels equal [`k_nearest`]'s, ties included up to the
/// k-th level's choice among equally far sites.
///
/// Exact cones only.
pub fn k_nearest_peeled(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    check_levels(machine, sites, options)?;
    if options.accuracy != Accuracy::Exact || matches!(options.metric, Metric::Polygon(_)) {
        return Err(Error::InvalidInput(
            "peeling draws exact cones of the L_p metrics; use the default level method for fans and polygons".into(),
        ));
    }
    let (frame, k) = (options.frame, options.k);
    let started = Instant::now();
    let (cones, mut stats) = level_cones(machine, sites, options);
    let instances: Vec<ConeInstance> = cones
        .iter()
        .map(|&(i, p, r)| {
            ConeInstance::new(
                i,
                p.into(),
                FanShape::with_triangles(r, FOOTPRINT_CORNERS).outer_radius,
                r,
            )
        })
        .chain(std::iter::once(bytemuck::Zeroable::zeroed()))
        .collect();
    let reach = cones.iter().map(|c| c.2).fold(1.0, f64::max) * 1.001;
    let metric = options.metric;
    let scale = metric.key_scale(reach);
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let (w, h) = (frame.width, frame.height);
    let pixels = frame.len();
    let ids = machine.image(Format::R32Uint, w, h)?;
    let depth = machine.image(Format::DepthStencil, w, h)?;
    let octagon = machine.vertex_buffer(&unit_footprint(FOOTPRINT_CORNERS))?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    // The previous level: depth -1 (below every cone) and no site.
    let mut previous = machine.readback_buffer(8 * pixels as u64)?;
    let mut words = vec![(-1.0f32).to_bits(); pixels];
    words.resize(2 * pixels, u32::MAX);
    previous.write(&words);
    let push = ConePush {
        fragment_depth_scale: scale as f32,
        ..picture_push(&frame, k, metric)
    };
    let register = RasterState {
        depth: DepthTest {
            compare: Compare::Less,
            write: true,
        },
        ..RasterState::OVERWRITE
    };
    let draw = |buffer, vertices, instances, count| ConeDraw {
        mesh: buffer,
        first_vertex: 0,
        vertex_count: vertices,
        instances,
        first_instance: 0,
        instance_count: count,
    };
    let cones_draw = draw(
        &octagon,
        FOOTPRINT_CORNERS,
        &instance_buffer,
        cones.len() as u32,
    );
    let target = Target {
        color: Some(&ids),
        depth_stencil: Some(&depth),
    };
    let params = DrawParams::default();
    let mut labels = vec![u32::MAX; pixels * k as usize];
    let mut distances = vec![f32::INFINITY; pixels * k as usize];
    let to_world = (1.0 / frame.scale) as f32;
    let unscale = (1.0 / scale) as f32;
    for level in 0..k as usize {
        machine.run(|pass| {
            let fresh = Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: None,
            };
            pass.bind_fragment_buffers(&[&previous], None)?;
            pass.begin(target, fresh)?;
            draw_cones(pass, &CONE_PEEL, &register, &params, &push, &cones_draw)?;
            pass.end()?;
            // This level becomes the next one's z and sites.
            pass.feed_fragment_buffer(&depth, &previous, 0)?;
            pass.feed_fragment_buffer(&ids, &previous, 4 * pixels as u64)
        })?;
        let rect = PixelRect::of(&ids);
        let level_ids = machine.read_u32(&ids, rect)?;
        let level_depths = machine.read_f32(&depth, rect)?;
        for (p, (id, z)) in level_ids.iter().zip(&level_depths).enumerate() {
            let at = p * k as usize + level;
            labels[at] = *id;
            if *id != u32::MAX {
                distances[at] = metric.distance_of_key((z * unscale) as f64) as f32 * to_world;
            }
        }
    }
    stats.render_ms = ms(started);
    Ok(KNearest {
        width: w,
        height: h,
        frame,
        k,
        labels,
        distances,
        stats,
    })
}

/// Cone radii (pixels) that keep the k lowest layers of the arrangement over the
/// picture, plus half a pixel so that rasterization never drops a rim pixel.
fn k_radii(
    pixels: &[DVec2],
    frame: &Frame,
    k: usize,
    speedup: Speedup,
    metric: Metric,
) -> Vec<f64> {
    let picture_wide = |p: &DVec2| frame.farthest_pixel(*p) + 0.5;
    // Euclidean bounds, stretched for other metrics (see radius::k_local_radii).
    let stretch = metric.stretch();
    match speedup {
        Speedup::None => pixels.iter().map(picture_wide).collect(),
        Speedup::Quadtree => {
            let e = radius::quadtree_k_radius(pixels, frame, k);
            pixels
                .iter()
                .map(|p| {
                    e.map_or(f64::INFINITY, |e| e * stretch + 0.5)
                        .min(picture_wide(p))
                })
                .collect()
        }
        Speedup::Local => {
            let (cell, bin) = radius::k_cell_and_bin(frame, pixels.len(), k);
            radius::k_local_radii(pixels, frame, k, cell, bin, stretch)
                .into_iter()
                .zip(pixels)
                .map(|(r, p)| (r + 0.5).min(picture_wide(p)))
                .collect()
        }
    }
}

/// The sites that may own furthest regions: for a convex unit ball (L_p with
/// p >= 1, convex polygons) a distance is a convex function, largest over the
/// sites at a corner of their convex hull; otherwise every site may.
pub(crate) fn furthest_candidates(sites: &[DVec2], hull: &[u32], metric: Metric) -> Vec<u32> {
    if metric.is_convex() {
        hull.to_vec()
    } else {
        (0..sites.len() as u32).collect()
    }
}

/// The furthest-site diagram (thesis §3.7.1) with its distances.
#[derive(Clone, Debug)]
pub struct Furthest {
    pub width: u32,
    pub height: u32,
    /// The picture: [`Frame::to_world`] maps its pixels to world points.
    pub frame: Frame,
    /// Furthest site per pixel, row-major.
    pub labels: Vec<u32>,
    /// Distance to it in world units.
    pub distances: Vec<f32>,
    /// Indices of the sites drawn: the vertices of the convex hull (every site
    /// for metrics whose balls are not convex: L_p with p < 1, star polygons).
    pub hull: Vec<u32>,
}

/// Computes the furthest-site diagram of `sites` (world coordinates) on `frame`.
pub fn furthest(
    machine: &Machine,
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Result<Furthest> {
    let drawn = draw_furthest(machine, sites, frame, metric, true)?;
    let ids = drawn.ids.as_ref().expect("labels were asked for");
    let rect = PixelRect::of(ids);
    let labels = machine.read_u32(ids, rect)?;
    let depths = machine.read_f32(&drawn.depth, rect)?;
    let (metric, scale) = (drawn.metric, drawn.scale);
    let distances = distances_of(&depths, &labels, |z| {
        distance_of_depth(metric, scale, z, frame)
    });
    Ok(Furthest {
        width: frame.width,
        height: frame.height,
        frame: *frame,
        labels,
        distances,
        hull: drawn.owners,
    })
}

/// The upper envelope of the sites' cones, still on the device.
pub(crate) struct DrawnFurthest {
    /// Furthest site per pixel, when asked for.
    pub ids: Option<Image>,
    /// The envelope's keys times `scale`.
    pub depth: Image,
    pub scale: f64,
    pub metric: Metric,
    /// The sites drawn.
    pub owners: Vec<u32>,
}

/// The distance (world units) a depth of keys times `scale` stands for.
pub(crate) fn distance_of_depth(metric: Metric, scale: f64, z: f32, frame: &Frame) -> f64 {
    metric.distance_of_key(z as f64 / scale) / frame.scale
}

/// Draws the upper envelope of the cones of `sites` under `metric` (only the
/// sites that can own a region).
pub(crate) fn draw_furthest(
    machine: &Machine,
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
    labels: bool,
) -> Result<DrawnFurthest> {
    check_sites(sites)?;
    frame.check()?;
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::InvalidInput(format!(
            "the upper envelope is drawn in one image of at most {side}x{side} pixels on this device"
        )));
    }
    let owners = furthest_candidates(sites, &convex_hull(sites), metric);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    // A polygon's distance is drawn exactly by the fan over the polygon; the other
    // metrics' cones evaluate the distance per fragment.
    let (program, unit) = match metric {
        Metric::Polygon(g) => (&CONE_FAN, unit_fan_over(&g.vertices, 1.0)),
        _ => (&CONE_EXACT, unit_footprint(FOOTPRINT_CORNERS)),
    };
    // Upside-down cones reach every pixel: a site's furthest region may lie
    // anywhere in the picture.
    let instances: Vec<ConeInstance> = owners
        .iter()
        .map(|&i| {
            let p = pixels[i as usize];
            let r = frame.farthest_pixel(p) + 0.5;
            let outer = match metric {
                // The polygon's inscribed ball must hold the disc of radius r.
                Metric::Polygon(_) => metric.euclidean_bounds().1 * r,
                _ => FanShape::with_triangles(r, FOOTPRINT_CORNERS).outer_radius,
            };
            ConeInstance::new(i, p.into(), outer, r)
        })
        .collect();
    let reach = instances
        .iter()
        .map(|c| c.site[3] as f64)
        .fold(1.0, f64::max)
        * 1.001;
    let scale = metric.key_scale(reach);
    let ids = labels
        .then(|| machine.image(Format::R32Uint, frame.width, frame.height))
        .transpose()?;
    let depth = machine.image(Format::Depth, frame.width, frame.height)?;
    let mesh = machine.vertex_buffer(&unit)?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    // Polygon keys are distances, so one scale serves fan heights and keys.
    let push = ConePush {
        vertex_depth_scale: scale as f32,
        fragment_depth_scale: scale as f32,
        ..picture_push(frame, 1, metric)
    };
    // Euclidean furthest regions are convex: each cone is drawn only inside the
    // bounding box of a region that holds its own (one draw per cone with a
    // scissor), instead of over the whole picture.
    let scissors: Vec<Option<[u32; 4]>> = if metric == Metric::L2 && owners.len() >= 3 {
        let owned: Vec<DVec2> = owners.iter().map(|&i| pixels[i as usize]).collect();
        (0..owned.len())
            .map(|k| Some(furthest_region_box(&owned, k, frame.width, frame.height)))
            .collect()
    } else {
        vec![None]
    };
    // The upper envelope: the furthest fragment wins, ties the last drawn (or-equal,
    // so that a lone site's own pixel at distance 0 still gets it).
    let state = RasterState {
        depth: DepthTest {
            compare: Compare::GreaterOrEqual,
            write: true,
        },
        ..RasterState::OVERWRITE
    };
    machine.run(|pass| {
        pass.begin(
            Target {
                color: ids.as_ref(),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: ids.as_ref().map(|_| ClearColor::Uint([u32::MAX; 4])),
                depth: Some(0.0),
                stencil: None,
            },
        )?;
        for (k, scissor) in scissors.iter().enumerate() {
            if scissor.is_some_and(|r| r[2] == 0 || r[3] == 0) {
                continue;
            }
            draw_cones(
                pass,
                program,
                &state,
                &DrawParams {
                    scissor: *scissor,
                    ..DrawParams::default()
                },
                &push,
                &ConeDraw {
                    mesh: &mesh,
                    first_vertex: 0,
                    vertex_count: unit.len() as u32,
                    instances: &instance_buffer,
                    first_instance: if scissors.len() == 1 { 0 } else { k as u32 },
                    instance_count: if scissors.len() == 1 {
                        instances.len() as u32
                    } else {
                        1
                    },
                },
            )?;
        }
        pass.end()
    })?;
    Ok(DrawnFurthest {
        ids,
        depth,
        scale,
        metric,
        owners,
    })
}

/// The pixel rectangle `(x, y, width, height)` around the part of the picture
/// where `sites[k]` is at least as far as each of the other sites (up to 64 of
/// them: its neighbours first, so that fewer still bound a superset), with a
/// pixel to spare; zero-sized when that part misses the picture.
fn furthest_region_box(sites: &[DVec2], k: usize, width: u32, height: u32) -> [u32; 4] {
    let (w, h) = (width as f64 - 0.5, height as f64 - 0.5);
    let mut polygon = vec![
        DVec2::new(-0.5, -0.5),
        DVec2::new(w, -0.5),
        DVec2::new(w, h),
        DVec2::new(-0.5, h),
    ];
    let n = sites.len();
    let others = (1..n).map(|d| (k + if d % 2 == 1 { d / 2 + 1 } else { n - d / 2 }) % n);
    let p = sites[k];
    for j in others.take(64) {
        let q = sites[j];
        // |x − p| ≥ |x − q|  ⇔  2 x·(q − p) ≥ |q|² − |p|².
        let (a, b) = (2.0 * (q - p), q.length_squared() - p.length_squared());
        let keep = |x: DVec2| a.dot(x) - b >= -1e-6 * (1.0 + b.abs());
        let mut clipped = Vec::new();
        for e in 0..polygon.len() {
            let (u, v) = (polygon[e], polygon[(e + 1) % polygon.len()]);
            if keep(u) {
                clipped.push(u);
            }
            if keep(u) != keep(v) {
                let (fu, fv) = (a.dot(u) - b, a.dot(v) - b);
                clipped.push(u + (v - u) * (fu / (fu - fv)));
            }
        }
        polygon = clipped;
        if polygon.is_empty() {
            return [0; 4];
        }
    }
    let lo = polygon.iter().fold(DVec2::INFINITY, |a, p| a.min(*p)) - 1.0;
    let hi = polygon.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p)) + 1.0;
    let x0 = lo.x.floor().clamp(0.0, width as f64) as u32;
    let y0 = lo.y.floor().clamp(0.0, height as f64) as u32;
    let x1 = hi.x.ceil().clamp(0.0, width as f64) as u32;
    let y1 = hi.y.ceil().clamp(0.0, height as f64) as u32;
    [x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0)]
}

/// Indices of the convex hull's vertices, counter-clockwise, points on its edges
/// left out (Andrew's monotone chain with exact orientation tests). Duplicates
/// appear once; one or two distinct points are their own hull.
pub fn convex_hull(points: &[DVec2]) -> Vec<u32> {
    let turn = |o: DVec2, a: DVec2, b: DVec2| {
        let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
        robust::orient2d(c(o), c(a), c(b))
    };
    // Akl–Toussaint: points strictly inside the octagon of the extreme points in
    // eight directions are no hull vertices; only the others are sorted.
    let mut octagon: Vec<DVec2> = Vec::new();
    if !points.is_empty() {
        let directions = [
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(-1.0, 1.0),
            DVec2::new(-1.0, 0.0),
            DVec2::new(-1.0, -1.0),
            DVec2::new(0.0, -1.0),
            DVec2::new(1.0, -1.0),
        ];
        for d in directions {
            let p = points
                .iter()
                .copied()
                .max_by(|a, b| a.dot(d).total_cmp(&b.dot(d)))
                .expect("points exist");
            if octagon.last() != Some(&p) && octagon.first() != Some(&p) {
                octagon.push(p);
            }
        }
    }
    let strictly_inside = |p: DVec2| {
        octagon.len() >= 3
            && (0..octagon.len())
                .all(|k| turn(octagon[k], octagon[(k + 1) % octagon.len()], p) > 0.0)
    };
    let outside = (0..points.len() as u32).filter(|&i| !strictly_inside(points[i as usize]));
    let order = distinct_by(points, outside, lexicographic).0;
    if order.len() < 3 {
        return order;
    }
    let turn =
        |o: u32, a: u32, b: u32| turn(points[o as usize], points[a as usize], points[b as usize]);
    let mut hull: Vec<u32> = Vec::with_capacity(2 * order.len());
    for pass in [
        &order[..],
        &order.iter().rev().copied().collect::<Vec<_>>()[..],
    ] {
        let start = hull.len();
        for &i in pass {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], i) <= 0.0
            {
                hull.pop();
            }
            hull.push(i);
        }
        // The last point of each chain starts the other.
        hull.pop();
    }
    hull
}
