//! The Voronoi diagram of point sites as the lower envelope of cones (thesis
//! §3.2–3.5): one cone per site, drawn with the depth test LESS, paints every pixel
//! with its nearest site.
//!
//! Two accuracy modes: [`Accuracy::Fan`] draws the thesis's triangle fans (a
//! distance diagram within ε; labels may deviate near bisectors as §3.4 analyses),
//! [`Accuracy::Exact`] writes the exact squared distance per fragment, so every
//! label is a nearest site. Three ways to size the cones: [`Speedup::None`]
//! (picture-wide cones, Hoff et al.), [`Speedup::Quadtree`] (the thesis's width
//! bounds with minmax-detected retries) and [`Speedup::Local`] (a radius per site).

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
        Clear, ClearColor, ConeDraw, ConePush, DrawParams, Format, Image, Machine, PixelRect,
        Program, RasterState, Target,
    },
};

/// How cones are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Accuracy {
    /// Triangle fans. With `triangles: None` each cone gets the fewest triangles for
    /// an ε distance diagram at its own radius; `Some(T)` fixes T for every cone.
    Fan {
        epsilon: f64,
        triangles: Option<u32>,
    },
    /// The exact distance per fragment.
    Exact,
}

impl Accuracy {
    /// Fans for a distance diagram within one pixel.
    pub const FAN: Self = Self::Fan {
        epsilon: 1.0,
        triangles: None,
    };
}

/// How far cones reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Speedup {
    /// Every cone covers the whole picture.
    None,
    /// One radius for all cones from the quadtree (thesis §3.5); uncovered pixels
    /// are found with minmax and the cones redrawn larger.
    Quadtree,
    /// A radius per site from the sites around it.
    Local,
}

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoronoiOptions {
    pub frame: Frame,
    pub accuracy: Accuracy,
    pub speedup: Speedup,
    /// Whether to read back the distance map (the z buffer) as well as the labels.
    pub distances: bool,
}

/// How the diagram was made.
#[derive(Clone, Debug, Default, Serialize)]
pub struct VoronoiStats {
    pub device: String,
    pub sites: usize,
    /// Cones drawn in the final pass (sites whose cone reaches the picture).
    pub cones: usize,
    /// Rendering passes (more than one when the quadtree's first radius was short).
    pub passes: u32,
    /// Cone radii (pixels) of the final pass: smallest, mean, largest.
    pub radius_min: f64,
    pub radius_mean: f64,
    pub radius_max: f64,
    /// Triangles per cone, as (T, number of cones), for fan mode.
    pub triangles: Vec<(u32, usize)>,
    /// Guaranteed bound on the distance overestimate (pixels); 0 in exact mode.
    pub distance_error_bound: f64,
    /// Radii tried by the quadtree retry loop.
    pub radii_tried: Vec<f64>,
    /// Milliseconds: cone sizing on the CPU, rendering (all passes, with coverage
    /// checks), reading the result back.
    pub bounds_ms: f64,
    pub render_ms: f64,
    pub readback_ms: f64,
}

/// A Voronoi diagram on a picture.
#[derive(Clone, Debug)]
pub struct VoronoiDiagram {
    pub width: u32,
    pub height: u32,
    /// Nearest site per pixel, row-major (`[j][i]`); `u32::MAX` where no site is.
    pub labels: Vec<u32>,
    /// Distance to that site in world units, row-major; empty unless
    /// [`VoronoiOptions::distances`].
    pub distances: Vec<f32>,
    pub stats: VoronoiStats,
}

/// One cone to draw, in pixel coordinates.
#[derive(Clone, Copy, Debug)]
struct Cone {
    site: DVec2,
    id: u32,
    /// Every owned pixel centre lies within this distance.
    radius: f64,
}

/// The GPU-side buffers of one diagram.
struct Picture {
    ids: Image,
    depth: Image,
}

/// Computes the Voronoi diagram of `sites` (world coordinates).
pub fn voronoi(
    machine: &Machine,
    sites: &[DVec2],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    check_sites(sites)?;
    if let Accuracy::Fan { epsilon, triangles } = options.accuracy {
        if !(epsilon > 0.0 && epsilon.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "fan epsilon {epsilon} must be positive"
            )));
        }
        if triangles.is_some_and(|t| t < 3) {
            return Err(Error::InvalidInput(
                "a fan needs at least 3 triangles".into(),
            ));
        }
    }
    let frame = options.frame;
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites: sites.len(),
        ..Default::default()
    };
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let picture = Picture {
        ids: machine.image(Format::R32Uint, frame.width, frame.height)?,
        depth: machine.image(Format::Depth, frame.width, frame.height)?,
    };

    let started = Instant::now();
    // The radius that reaches every pixel from a site, plus half a pixel so that
    // rasterization rules at the cone's rim never drop a pixel centre.
    let picture_wide: Vec<f64> = pixels
        .iter()
        .map(|p| frame.farthest_pixel(*p) + 0.5)
        .collect();
    let cones_with = |radius: &dyn Fn(usize) -> f64| -> Vec<Cone> {
        pixels
            .iter()
            .enumerate()
            .map(|(i, p)| Cone {
                site: *p,
                id: i as u32,
                radius: radius(i),
            })
            .filter(|c| c.radius > 0.0 && frame.distance_to_pixels(c.site) <= c.radius)
            .collect()
    };
    // The cones of each pass to try, with the quadtree radius it uses (if any).
    let mut attempts: Vec<(Option<f64>, Vec<Cone>)> = Vec::new();
    match options.speedup {
        Speedup::None => attempts.push((None, cones_with(&|i| picture_wide[i]))),
        Speedup::Local => {
            let (cell, bin) = radius::default_cell_and_bin(&frame, pixels.len());
            let radii = radius::local_radii(&pixels, &frame, cell, bin);
            attempts.push((None, cones_with(&|i| (radii[i] + 0.5).min(picture_wide[i]))));
        }
        Speedup::Quadtree => {
            let bounds = radius::quadtree_width_bounds(&pixels, &frame);
            let widest = picture_wide.iter().copied().fold(0.0, f64::max);
            for r in radius::retry_radii(&bounds, widest) {
                attempts.push((Some(r), cones_with(&|i| (r + 0.5).min(picture_wide[i]))));
            }
        }
    }
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let mut last = Vec::new();
    let tries = attempts.len();
    for (k, (radius, cones)) in attempts.into_iter().enumerate() {
        stats.passes += 1;
        stats.radii_tried.extend(radius);
        let fan_sizes = render(machine, &picture, &frame, &cones, options.accuracy)?;
        // Picture-wide and local radii cover every pixel by construction; the
        // quadtree's radius is checked with minmax, the thesis's way: a pixel no
        // truncated cone reached keeps the "no site" id, the largest value.
        let covered = options.speedup != Speedup::Quadtree
            || machine
                .minmax(&picture.ids, PixelRect::of(&picture.ids))?
                .max[0]
                < u32::MAX as f64;
        last = cones;
        stats.triangles = fan_sizes;
        if covered {
            break;
        }
        if k + 1 == tries {
            // Only the quadtree's short radii may leave pixels uncovered; anything
            // else is a bug worth reporting rather than a wrong picture.
            return Err(Error::InvalidInput(
                "cones left pixels uncovered; this is a pixgeo bug, please report it with the sites".into(),
            ));
        }
    }
    stats.render_ms = ms(started);
    stats.cones = last.len();
    if !last.is_empty() {
        stats.radius_min = last.iter().map(|c| c.radius).fold(f64::INFINITY, f64::min);
        stats.radius_max = last.iter().map(|c| c.radius).fold(0.0, f64::max);
        stats.radius_mean = last.iter().map(|c| c.radius).sum::<f64>() / last.len() as f64;
    }
    stats.distance_error_bound = match options.accuracy {
        Accuracy::Exact => 0.0,
        Accuracy::Fan {
            epsilon,
            triangles: None,
        } => epsilon / frame.scale,
        Accuracy::Fan {
            triangles: Some(t), ..
        } => fan_distance_error(stats.radius_max, t) / frame.scale,
    };

    let started = Instant::now();
    let rect = PixelRect::of(&picture.ids);
    let labels = machine.read_u32(&picture.ids, rect)?;
    let mut distances = if options.distances {
        machine.read_f32(&picture.depth, rect)?
    } else {
        Vec::new()
    };
    let scale = depth_scale(&last, options.accuracy);
    let to_world = (1.0 / frame.scale) as f32;
    let exact = options.accuracy == Accuracy::Exact;
    let unscale = if exact {
        1.0 / scale.fragment
    } else {
        1.0 / scale.vertex
    } as f32;
    distances
        .par_chunks_mut(4096)
        .zip(labels.par_chunks(4096))
        .for_each(|(depths, ids)| {
            for (z, id) in depths.iter_mut().zip(ids) {
                let d = if exact {
                    (*z * unscale).sqrt()
                } else {
                    *z * unscale
                };
                *z = if *id == u32::MAX {
                    f32::INFINITY
                } else {
                    d * to_world
                };
            }
        });
    stats.readback_ms = ms(started);
    Ok(VoronoiDiagram {
        width: frame.width,
        height: frame.height,
        labels,
        distances,
        stats,
    })
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Corners of an exact cone's footprint, a regular polygon around the disc it must
/// cover: a K-gon is K - 2 triangles of area `K tan(pi / K) r²`. On lavapipe a
/// triangle costs about a microsecond of setup, as much as ~400 fragments, so small
/// cones are single triangles (5.2 r²) and larger ones trade triangles for
/// fragments: squares (4 r²), hexagons (3.5 r²), octagons (3.3 r²). The thresholds
/// are where the measured costs cross.
fn exact_footprint_corners(radius: f64) -> u32 {
    match radius {
        r if r < 18.0 => 3,
        r if r < 37.0 => 4,
        r if r < 70.0 => 6,
        _ => 8,
    }
}

/// The triangle fan each cone is drawn with.
fn fan_shape(cone: &Cone, accuracy: Accuracy) -> FanShape {
    match accuracy {
        // The footprint of an exact cone only has to cover its radius: an octagon
        // wastes 5% of fragments over the circle, a square 27%.
        Accuracy::Exact => {
            FanShape::with_triangles(cone.radius, exact_footprint_corners(cone.radius))
        }
        Accuracy::Fan {
            triangles: Some(t), ..
        } => FanShape::with_triangles(cone.radius, t),
        Accuracy::Fan {
            epsilon,
            triangles: None,
        } => FanShape::for_distance_error(cone.radius, epsilon),
    }
}

/// Powers of two that map cone heights (fan) or squared distances (exact) into the
/// depth range [0, 1]; powers of two keep the mapping exact.
#[derive(Clone, Copy, Debug)]
struct DepthScale {
    vertex: f64,
    fragment: f64,
}

fn depth_scale(cones: &[Cone], accuracy: Accuracy) -> DepthScale {
    let outer = cones
        .iter()
        .map(|c| fan_shape(c, accuracy).outer_radius)
        .fold(1.0, f64::max)
        * 1.001;
    match accuracy {
        Accuracy::Exact => DepthScale {
            vertex: 0.0,
            fragment: (outer * outer).log2().ceil().exp2().recip(),
        },
        Accuracy::Fan { .. } => DepthScale {
            vertex: outer.log2().ceil().exp2().recip(),
            fragment: 0.0,
        },
    }
}

/// Draws the lower envelope of `cones` into the picture; returns (T, count) per
/// distinct fan size. Cones are grouped by T so each group is one instanced draw of
/// one unit fan.
fn render(
    machine: &Machine,
    picture: &Picture,
    frame: &Frame,
    cones: &[Cone],
    accuracy: Accuracy,
) -> Result<Vec<(u32, usize)>> {
    let mut shaped: Vec<(FanShape, &Cone)> =
        cones.iter().map(|c| (fan_shape(c, accuracy), c)).collect();
    shaped.sort_by_key(|(s, _)| s.triangles);
    let mut mesh: Vec<[f32; 3]> = Vec::new();
    let mut instances: Vec<[u32; 5]> = Vec::with_capacity(shaped.len());
    // (first vertex, vertex count, first instance, instance count, T)
    let mut groups: Vec<(u32, u32, u32, u32, u32)> = Vec::new();
    for (shape, cone) in &shaped {
        if groups.last().is_none_or(|g| g.4 != shape.triangles) {
            let fan = if accuracy == Accuracy::Exact {
                unit_footprint(shape.triangles)
            } else {
                unit_fan(shape.triangles)
            };
            groups.push((
                mesh.len() as u32,
                fan.len() as u32,
                instances.len() as u32,
                0,
                shape.triangles,
            ));
            mesh.extend(fan);
        }
        if let Some(g) = groups.last_mut() {
            g.3 += 1;
        }
        instances.push([
            (cone.site.x as f32).to_bits(),
            (cone.site.y as f32).to_bits(),
            (shape.outer_radius as f32).to_bits(),
            (cone.radius as f32).to_bits(),
            cone.id,
        ]);
    }
    let scale = depth_scale(cones, accuracy);
    let push = ConePush {
        picture_size: [frame.width as f32, frame.height as f32],
        vertex_depth_scale: scale.vertex as f32,
        fragment_depth_scale: scale.fragment as f32,
    };
    let program = match accuracy {
        Accuracy::Exact => Program::ConeExact,
        Accuracy::Fan { .. } => Program::ConeFan,
    };
    let mesh_buffer = machine.vertex_buffer(if mesh.is_empty() {
        &[[0.0f32; 3]][..]
    } else {
        &mesh
    })?;
    let instance_buffer = machine.vertex_buffer(if instances.is_empty() {
        &[[0u32; 5]][..]
    } else {
        &instances
    })?;
    let state = RasterState::lower_envelope();
    let params = DrawParams::default();
    machine.run(|pass| {
        pass.begin(
            Target {
                color: Some(&picture.ids),
                depth_stencil: Some(&picture.depth),
            },
            Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: Some(0),
            },
        )?;
        for &(first_vertex, vertex_count, first_instance, instance_count, _) in &groups {
            pass.draw_cones(
                program,
                &state,
                &params,
                &push,
                &ConeDraw {
                    mesh: &mesh_buffer,
                    first_vertex,
                    vertex_count,
                    instances: &instance_buffer,
                    first_instance,
                    instance_count,
                },
            )?;
        }
        pass.end()
    })?;
    Ok(groups.iter().map(|g| (g.4, g.3 as usize)).collect())
}
