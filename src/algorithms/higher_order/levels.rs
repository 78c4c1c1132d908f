//! What the routes to the k nearest share: the cones of every level and their
//! radii, and the per-pixel keys and labels read back into ordered levels.

use super::*;

/// Where a cone's rim vertices lie for a cone that must reach radius r.
#[derive(Clone, Copy)]
pub(super) enum Rim {
    /// A polygon of this many corners around the disc.
    Circumscribed(u32),
    /// A fan whose height error stays below epsilon out to r (thesis §3.3).
    Beyond(f64),
    /// A fan of another metric (thesis §3.6.1–3.6.2).
    Metric(MetricFan, Metric),
}

impl Rim {
    pub(super) fn radius(self, r: f64) -> f64 {
        match self {
            Rim::Circumscribed(corners) => FanShape::with_triangles(r, corners).outer_radius,
            Rim::Beyond(epsilon) => r + epsilon,
            Rim::Metric(fan, metric) => fan.outer_radius(metric, r),
        }
    }
}

/// Push constants for drawing on the whole `frame` with `levels` per pixel.
pub(super) fn picture_push(frame: &Frame, levels: u32, metric: Metric) -> ConePush {
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
pub(super) fn draw_to_buffers<'r>(
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
pub(super) fn read_keys(
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
pub(super) fn read_labels(
    ids: &Buffer,
    pixels: &[DVec2],
    options: &KNearestOptions,
    mut stats: KNearestStats,
) -> Result<KNearest> {
    let started = Instant::now();
    let (frame, k, metric) = (options.frame, options.k as usize, options.metric);
    let width = frame.width as usize;
    let ids: &[u32] = bytemuck::cast_slice(&ids.mapped()[..frame.len() * k * 4]);
    let mut labels = crate::memory::filled(ids.len(), 0u32, "the levels' labels")?;
    let mut distances = crate::memory::filled(ids.len(), 0f32, "the levels' distances")?;
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
    Ok(KNearest {
        width: frame.width,
        height: frame.height,
        frame,
        k: options.k,
        labels,
        distances,
        stats,
    })
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
pub(super) fn check_levels(machine: &Machine, options: &KNearestOptions) -> Result<()> {
    options.accuracy.check_for(options.metric)?;
    let frame = options.frame;
    frame.check()?;
    let k = options.k;
    if k == 0 || k > MAX_LEVELS {
        return Err(Error::out_of_range(format!(
            "the number of levels must be 1 to {MAX_LEVELS}, not {k}"
        )));
    }
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::out_of_range(format!(
            "higher-order diagrams are drawn in one image of at most {side}x{side} pixels on this device"
        )));
    }
    Ok(())
}

/// The cones (site index, pixel position, radius) that reach the picture, and the
/// statistics that describe them.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn level_cones(
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
pub(super) fn drawn_cones<'a>(
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
pub(super) fn cone_stats(
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

/// Cone radii (pixels) that keep the k lowest layers of the arrangement over the
/// picture, plus half a pixel so that rasterization never drops a rim pixel.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn k_radii(
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
