//! Higher-order Voronoi diagrams (thesis §3.7): for every pixel its k nearest sites
//! in order (the degree 1..k diagrams at once), the set of its k nearest (the
//! order-k diagram), and the furthest site (§3.7.1).
//!
//! The thesis peels the arrangement of cones level by level with two depth buffers
//! and a stencil that counts equal distances, 2k passes for k levels. pixgeo draws
//! the cones once: each fragment inserts its key (squared distance, site id) into
//! the pixel's sorted list of the k smallest keys with 64-bit atomic min
//! (`glsl/cone_knearest.frag`). Equal distances are distinct keys, so
//! multiplicities come out right, and ties are ordered by site id.
//!
//! The furthest-site diagram is the lower envelope of cones turned upside down:
//! one pass with the depth test GREATER. Only the vertices of the convex hull own
//! furthest regions, so only their cones are drawn.

use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;
use serde::Serialize;

use crate::{
    error::{Error, Result},
    geometry::{
        cone::{fan_distance_error, unit_fan, unit_footprint, FanShape},
        frame::check_sites,
        radius, Frame,
    },
    machine::{
        Clear, ClearColor, Compare, ConeDraw, ConePush, DepthTest, DrawParams, Format, Machine,
        Program, RasterState, Target,
    },
};

use super::voronoi::{Accuracy, Speedup};

/// Corners of the polygon drawn around each cone's disc.
const FOOTPRINT_CORNERS: u32 = 8;

/// Largest number of levels kept per pixel.
pub const MAX_LEVELS: u32 = 256;

/// Keys kept per pixel take 8 bytes each; beyond this many bytes in all, a picture
/// is refused rather than exhausting memory.
const MAX_KEY_BYTES: u64 = 4 << 30;

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KNearestOptions {
    pub frame: Frame,
    /// Levels per pixel: the 1st to the k-th nearest site.
    pub k: u32,
    /// Exact squared distances per fragment, or the thesis's triangle fans (one
    /// triangle count for all cones: the largest cone's for `epsilon`, or the
    /// given one).
    pub accuracy: Accuracy,
    /// How far cones reach: [`Speedup::Quadtree`] is thesis Theorem 3.3 (cells with
    /// at least k sites bound the cone height), [`Speedup::Local`] a radius per site
    /// from the k-th nearest sites around it.
    pub speedup: Speedup,
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
pub fn k_nearest(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    check_sites(sites)?;
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
    let key_bytes = frame.len() as u64 * k as u64 * 8;
    if key_bytes > MAX_KEY_BYTES {
        return Err(Error::InvalidInput(format!(
            "{k} levels of {}x{} pixels need {} MiB of keys; use fewer levels or a smaller picture",
            frame.width,
            frame.height,
            key_bytes >> 20
        )));
    }
    if !machine.has_fragment_atomics64() {
        return Err(Error::InvalidInput(format!(
            "{} has no 64-bit atomics in fragment shaders, which the k nearest sites need; use --device cpu",
            machine.device_name()
        )));
    }
    let mut stats = KNearestStats {
        device: machine.device_name().to_string(),
        sites: sites.len(),
        levels: k,
        ..Default::default()
    };

    let started = Instant::now();
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let radii = k_radii(&pixels, &frame, k as usize, options.speedup);
    let cones: Vec<(u32, DVec2, f64)> = pixels
        .iter()
        .zip(&radii)
        .enumerate()
        .filter(|(_, (p, r))| **r > 0.0 && frame.distance_to_pixels(**p) <= **r)
        .map(|(i, (p, r))| (i as u32, *p, *r))
        .collect();
    stats.cones = cones.len();
    if !cones.is_empty() {
        stats.radius_min = cones.iter().map(|c| c.2).fold(f64::INFINITY, f64::min);
        stats.radius_max = cones.iter().map(|c| c.2).fold(0.0, f64::max);
        stats.radius_mean = cones.iter().map(|c| c.2).sum::<f64>() / cones.len() as f64;
    }
    // The mesh, each cone's outer radius, and the fan's error bound.
    let (program, mesh, outer) = match options.accuracy {
        Accuracy::Exact => (
            Program::ConeKNearest,
            unit_footprint(FOOTPRINT_CORNERS),
            Rim::Circumscribed(FOOTPRINT_CORNERS),
        ),
        Accuracy::Fan {
            epsilon,
            triangles: None,
        } => {
            if !(epsilon > 0.0 && epsilon.is_finite()) {
                return Err(Error::InvalidInput(format!(
                    "fan epsilon {epsilon} must be positive"
                )));
            }
            let t = FanShape::for_distance_error(stats.radius_max, epsilon).triangles;
            stats.triangles = t;
            stats.distance_error_bound = epsilon / frame.scale;
            (Program::ConeKNearestFan, unit_fan(t), Rim::Beyond(epsilon))
        }
        Accuracy::Fan {
            triangles: Some(t), ..
        } => {
            if t < 3 {
                return Err(Error::InvalidInput(
                    "a fan needs at least 3 triangles".into(),
                ));
            }
            stats.triangles = t;
            stats.distance_error_bound = fan_distance_error(stats.radius_max, t) / frame.scale;
            (Program::ConeKNearestFan, unit_fan(t), Rim::Circumscribed(t))
        }
    };
    let instances: Vec<[u32; 5]> = cones
        .iter()
        .map(|&(i, p, r)| {
            [
                (p.x as f32).to_bits(),
                (p.y as f32).to_bits(),
                (outer.radius(r) as f32).to_bits(),
                (r as f32).to_bits(),
                i,
            ]
        })
        .collect();
    // Fan heights map into the depth range by a power of two, which keeps them
    // exact; exact keys hold squared distances as they are.
    let reach = instances
        .iter()
        .map(|c| f32::from_bits(c[2]) as f64)
        .fold(1.0, f64::max)
        * 1.001;
    let vertex_scale = reach.log2().ceil().exp2().recip();
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let mut keys = machine.readback_buffer(key_bytes)?;
    keys.fill(0xFF);
    if !instances.is_empty() {
        let depth = machine.image(Format::Depth, frame.width, frame.height)?;
        let mesh_buffer = machine.vertex_buffer(&mesh)?;
        let instance_buffer = machine.vertex_buffer(&instances)?;
        let push = ConePush {
            picture_size: [frame.width as f32, frame.height as f32],
            offset: [0.0, 0.0],
            vertex_depth_scale: vertex_scale as f32,
            fragment_depth_scale: 0.0,
            levels: k,
        };
        machine.with_fragment_buffer(&keys, |set| {
            machine.run(|pass| {
                // The depth buffer only gives the pass its size.
                pass.begin(
                    Target {
                        color: None,
                        depth_stencil: Some(&depth),
                    },
                    Clear {
                        color: None,
                        depth: Some(1.0),
                        stencil: None,
                    },
                )?;
                pass.bind_fragment_buffer(set);
                pass.draw_cones(
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
                )?;
                pass.end()
            })
        })?;
    }
    stats.render_ms = ms(started);

    let started = Instant::now();
    let raw: &[u64] = bytemuck::cast_slice(&keys.mapped()[..key_bytes as usize]);
    let to_world = (1.0 / frame.scale) as f32;
    let unscale = (1.0 / vertex_scale) as f32;
    let exact = options.accuracy == Accuracy::Exact;
    let (labels, distances): (Vec<u32>, Vec<f32>) = raw
        .par_iter()
        .map(|&key| {
            if key == u64::MAX {
                return (u32::MAX, f32::INFINITY);
            }
            let value = f32::from_bits((key >> 32) as u32);
            let distance = if exact { value.sqrt() } else { value * unscale };
            (key as u32, distance * to_world)
        })
        .unzip();
    stats.readback_ms = ms(started);
    Ok(KNearest {
        width: frame.width,
        height: frame.height,
        k,
        labels,
        distances,
        stats,
    })
}

/// Where a cone's rim vertices lie for a cone that must reach radius r.
#[derive(Clone, Copy)]
enum Rim {
    /// A polygon of this many corners around the disc.
    Circumscribed(u32),
    /// A fan whose height error stays below epsilon out to r (thesis §3.3).
    Beyond(f64),
}

impl Rim {
    fn radius(self, r: f64) -> f64 {
        match self {
            Rim::Circumscribed(corners) => FanShape::with_triangles(r, corners).outer_radius,
            Rim::Beyond(epsilon) => r + epsilon,
        }
    }
}

/// Cone radii (pixels) that keep the k lowest layers of the arrangement over the
/// picture, plus half a pixel so that rasterization never drops a rim pixel.
fn k_radii(pixels: &[DVec2], frame: &Frame, k: usize, speedup: Speedup) -> Vec<f64> {
    let picture_wide = |p: &DVec2| frame.farthest_pixel(*p) + 0.5;
    match speedup {
        Speedup::None => pixels.iter().map(picture_wide).collect(),
        Speedup::Quadtree => {
            let e = radius::quadtree_k_radius(pixels, frame, k);
            pixels
                .iter()
                .map(|p| e.map_or(f64::INFINITY, |e| e + 0.5).min(picture_wide(p)))
                .collect()
        }
        Speedup::Local => {
            let (cell, bin) = radius::k_cell_and_bin(frame, pixels.len(), k);
            radius::k_local_radii(pixels, frame, k, cell, bin)
                .into_iter()
                .zip(pixels)
                .map(|(r, p)| (r + 0.5).min(picture_wide(p)))
                .collect()
        }
    }
}

/// The furthest-site diagram (thesis §3.7.1) with its distances.
#[derive(Clone, Debug)]
pub struct Furthest {
    pub width: u32,
    pub height: u32,
    /// Furthest site per pixel, row-major.
    pub labels: Vec<u32>,
    /// Distance to it in world units.
    pub distances: Vec<f32>,
    /// Indices of the sites drawn: the vertices of the convex hull.
    pub hull: Vec<u32>,
}

/// Computes the furthest-site diagram of `sites` (world coordinates) on `frame`.
pub fn furthest(machine: &Machine, sites: &[DVec2], frame: &Frame) -> Result<Furthest> {
    check_sites(sites)?;
    frame.check()?;
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::InvalidInput(format!(
            "furthest-site diagrams are drawn in one image of at most {side}x{side} pixels on this device"
        )));
    }
    let hull = convex_hull(sites);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    // Upside-down cones reach every pixel: a site's furthest region may lie
    // anywhere in the picture.
    let instances: Vec<[u32; 5]> = hull
        .iter()
        .map(|&i| {
            let p = pixels[i as usize];
            let r = frame.farthest_pixel(p) + 0.5;
            let outer = FanShape::with_triangles(r, FOOTPRINT_CORNERS).outer_radius;
            [
                (p.x as f32).to_bits(),
                (p.y as f32).to_bits(),
                (outer as f32).to_bits(),
                (r as f32).to_bits(),
                i,
            ]
        })
        .collect();
    let reach = instances
        .iter()
        .map(|c| f32::from_bits(c[3]) as f64)
        .fold(1.0, f64::max)
        * 1.001;
    // A power of two keeps squared distances exact in the depth buffer.
    let scale = (reach * reach).log2().ceil().exp2().recip();
    let ids = machine.image(Format::R32Uint, frame.width, frame.height)?;
    let depth = machine.image(Format::Depth, frame.width, frame.height)?;
    let mesh = machine.vertex_buffer(&unit_footprint(FOOTPRINT_CORNERS))?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    let push = ConePush {
        picture_size: [frame.width as f32, frame.height as f32],
        offset: [0.0, 0.0],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: scale as f32,
        levels: 1,
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
                color: Some(&ids),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(0.0),
                stencil: None,
            },
        )?;
        pass.draw_cones(
            Program::ConeExact,
            &state,
            &DrawParams::default(),
            &push,
            &ConeDraw {
                mesh: &mesh,
                first_vertex: 0,
                vertex_count: FOOTPRINT_CORNERS,
                instances: &instance_buffer,
                first_instance: 0,
                instance_count: instances.len() as u32,
            },
        )?;
        pass.end()
    })?;
    let rect = crate::machine::PixelRect::of(&ids);
    let labels = machine.read_u32(&ids, rect)?;
    let depths = machine.read_f32(&depth, rect)?;
    let unscale = (1.0 / scale) as f32;
    let to_world = (1.0 / frame.scale) as f32;
    let distances = depths
        .par_iter()
        .zip(&labels)
        .map(|(z, id)| {
            if *id == u32::MAX {
                f32::INFINITY
            } else {
                (z * unscale).sqrt() * to_world
            }
        })
        .collect();
    Ok(Furthest {
        width: frame.width,
        height: frame.height,
        labels,
        distances,
        hull,
    })
}

/// Indices of the convex hull's vertices, counter-clockwise, points on its edges
/// left out (Andrew's monotone chain with exact orientation tests). Duplicates
/// appear once; one or two distinct points are their own hull.
pub fn convex_hull(points: &[DVec2]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (points[a as usize], points[b as usize]);
        p.x.total_cmp(&q.x)
            .then(p.y.total_cmp(&q.y))
            .then(a.cmp(&b))
    });
    order.dedup_by(|a, b| points[*a as usize] == points[*b as usize]);
    if order.len() < 3 {
        return order;
    }
    let turn = |o: u32, a: u32, b: u32| {
        let c = |i: u32| robust::Coord {
            x: points[i as usize].x,
            y: points[i as usize].y,
        };
        robust::orient2d(c(o), c(a), c(b))
    };
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

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}
