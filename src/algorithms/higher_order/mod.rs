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

use super::ms;
use crate::memory::Gather;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::{
        chain::{unit_fan_over, MetricFan},
        cone::{fan_distance_error, unit_fan, unit_footprint, FanShape},
        exact::predicates::convex_hull,
        frame::{distance2_to_rect, first_of_each, Checked},
        metric::Metric,
        radius, Frame,
    },
    machine::{
        Buffer, Clear, ClearColor, Compare, DepthTest, DrawParams, Format, Image, Machine, Pass,
        PixelRect, RasterState, Target,
    },
    Backend, Control,
};

use super::cones::{
    draw_cones, draw_k_nearest_tiles, ConeDraw, ConeInstance, ConePush, CONE_EXACT, CONE_FAN,
    CONE_K_NEAREST, CONE_K_NEAREST_FAN, CONE_PEEL,
};

use super::certify::{Certifier, Region};
use super::envelope::{drawn_accuracy, metric_fan, Accuracy, Speedup};

pub(crate) mod cpu;
mod furthest;
mod levels;
mod peeled;
mod repeats;
mod tiled;

pub use furthest::*;
use levels::*;
pub use peeled::*;
pub(crate) use repeats::with_repeats;
use tiled::*;

/// Corners of the polygon drawn around each cone's disc.
const FOOTPRINT_CORNERS: u32 = 8;

/// Largest number of levels kept per pixel.
pub(crate) const MAX_LEVELS: u32 = 256;

/// Keys kept per pixel take 8 bytes each; beyond this many bytes in all, a picture
/// is refused rather than exhausting memory.
const MAX_KEY_BYTES: u64 = 4 << 30;

/// What to compute: start from [`KNearestOptions::exact`] and change what
/// differs, by field or by setter.
#[derive(Clone, Debug, PartialEq)]
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
    /// Progress (the CPU's growing rings) and cancellation.
    pub control: Control,
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
            control: Control::new(),
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

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

impl Default for KNearestOptions {
    /// The 3 nearest sites, exact, on 1024 x 1024 pixels.
    fn default() -> Self {
        Self::exact(Frame::pixels(1024, 1024).expect("a valid picture"), 3)
    }
}

/// How the diagram was made.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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
    /// Pixels whose proposed sites the exact check replaced (exact mode).
    pub mended: usize,
    /// Milliseconds the exact check took.
    pub certify_ms: f64,
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
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a picture whose room was reserved where it was placed"
    )]
    pub fn level_labels(&self, l: u32) -> Vec<u32> {
        self.labels
            .chunks_exact(self.k as usize)
            .map(|keys| keys[l as usize])
            .collect()
    }

    /// Level `l` (0 = nearest) as a row-major picture of distances.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a picture whose room was reserved where it was placed"
    )]
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

/// Computes every pixel's k nearest sites (world coordinates): on a device by
/// cones and the depth test, on the CPU by growing the sites (thesis
/// §3.12.2); in exact mode both proved, the same labels and distances. The
/// CPU takes no drawing options: its answer is always the exact one.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::higher_order::{k_nearest, KNearestOptions}, geometry::{metric::Metric, Frame}};
///
/// let sites = [DVec2::new(1.0, 1.0), DVec2::new(7.0, 1.0), DVec2::new(4.0, 6.0)];
/// let options = KNearestOptions::exact(Frame::pixels(8, 8)?, 3).metric(Metric::LInf);
/// let near = k_nearest(&pixgeo::Backend::Cpu, &sites, &options)?;
/// assert_eq!(near.level_labels(2)[0], 1); // the farthest of pixel (0, 0)
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn k_nearest(
    backend: &Backend,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    options.control.run(|| {
        let sites = Checked::new(sites)?;
        match backend {
            Backend::Device(machine) => k_nearest_checked(machine, sites, options),
            Backend::Cpu => {
                let (frame, k, metric) = (&options.frame, options.k, options.metric);
                let progress = &mut |done, total| options.control.report(done, total);
                cpu::k_nearest_checked(sites, frame, k, metric, progress)
            }
        }
    })
}

/// [`k_nearest`] on a device, of sites checked where they entered.
pub(crate) fn k_nearest_checked(
    machine: &Machine,
    sites: Checked<'_>,
    options: &KNearestOptions,
) -> Result<KNearest> {
    with_repeats(
        sites,
        &options.frame,
        options.metric,
        options.k,
        |sites, k| {
            let options = &KNearestOptions {
                k,
                ..options.clone()
            };
            let mut near = proposed_k_nearest(machine, sites, options)?;
            if options.accuracy == Accuracy::Exact {
                certify_levels(&mut near, sites, options.metric)?;
            }
            Ok(near)
        },
    )
}

/// [`k_nearest`] as the device draws it, before the exact check.
fn proposed_k_nearest(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    let options = &KNearestOptions {
        accuracy: drawn_accuracy(options.metric, options.accuracy),
        ..options.clone()
    };
    let frame = options.frame;
    let k = options.k;
    check_levels(machine, options)?;
    let key_bytes = frame.len() as u64 * k as u64 * 8;
    if key_bytes > MAX_KEY_BYTES {
        return Err(Error::out_of_range(format!(
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
        return Err(Error::unsupported_option(format!(
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
        .gather("instances")?;
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

/// Proves a k-nearest diagram of the whole frame in place (exact cones, fans
/// of a polygon, or the CPU's pixel algorithm), counting the mended pixels in
/// its stats.
pub(crate) fn certify_levels(near: &mut KNearest, sites: &[DVec2], metric: Metric) -> Result<()> {
    let region = Region {
        x0: 0,
        y0: 0,
        width: near.width,
        height: near.height,
        stride: near.width as usize,
        k: near.k as usize,
    };
    let started = std::time::Instant::now();
    let certifier = Certifier::new(sites, &near.frame, metric)?;
    near.stats.mended =
        certifier.certify(region, &mut near.labels, Some(&mut near.distances), None)?;
    // Every route computes the distances from the labels alike.
    certifier.label_distances(region, &near.labels, &mut near.distances);
    near.stats.certify_ms = started.elapsed().as_secs_f64() * 1e3;
    Ok(())
}
