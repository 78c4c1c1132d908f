//! Generalized Voronoi diagrams (thesis §3.8–3.9): weighted points, segments,
//! circles and arcs, mixed in one diagram. Each site is drawn as one rectangle
//! whose fragments write the site's exact weighted distance as depth, so the depth
//! test LESS keeps the lower envelope: the thesis's cones with raised apexes and
//! changed angles, roofs over segments and straw huts over circles, evaluated
//! exactly per pixel.
//!
//! Rectangles are cut to where a site can win: the picture is divided into cells,
//! each cell gets an upper bound on the envelope (the smallest over the sites of
//! their largest weighted distance in the cell) and a site is drawn over the cells
//! where its smallest weighted distance is at most that bound. Distances to a set
//! change by at most the metric's size of the step (for p < 1, their p-th powers
//! by the p-th power of it), which bounds both from the cell's centre.

use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::{
        metric::Metric,
        site::{check_general_sites, Shape, Site},
    },
    machine::{
        Clear, ClearColor, ConeDraw, ConePush, DrawParams, Format, Machine, PixelRect, Program,
        RasterState, SiteInstance, Target,
    },
};

use super::voronoi::{Accuracy, VoronoiDiagram, VoronoiOptions, VoronoiStats};

/// Cells per side of the culling grid, at most; fewer for many sites, so that
/// cells times sites stays near `CULL_BUDGET`.
const CULL_CELLS: usize = 64;
const CULL_BUDGET: usize = 1 << 22;

/// The unit square as two triangles.
const UNIT_SQUARE: [[f32; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// The Voronoi diagram of `sites` of any shape and weight (world coordinates):
/// every pixel labelled with a site of smallest weighted distance, and the
/// distance map holding that weighted distance (world units). Exact mode only;
/// one picture of at most the device's image size.
pub fn voronoi_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    let (frame, metric) = (options.frame, options.metric);
    frame.check()?;
    check_general_sites(sites, metric)?;
    if options.accuracy != Accuracy::Exact {
        return Err(Error::InvalidInput(
            "weighted sites, segments, circles and arcs are drawn in exact mode; fans of them are not drawn yet (use --mode exact)".into(),
        ));
    }
    if options.ties {
        return Err(Error::InvalidInput(
            "equal distances are counted for unweighted points only".into(),
        ));
    }
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side || options.max_tile.is_some() {
        return Err(Error::InvalidInput(format!(
            "diagrams of weighted or extended sites are drawn in one image of at most {side}x{side} pixels, without tiles"
        )));
    }
    let started = Instant::now();
    let pixels: Vec<Site> = sites
        .iter()
        .map(|s| s.to_pixels(|p| frame.to_pixel(p), frame.scale))
        .collect();
    let (rects, reach) = cull(&pixels, frame.width, frame.height, metric, frame.scale);
    let least_additive = sites
        .iter()
        .map(|s| s.additive)
        .fold(f64::INFINITY, f64::min);
    // A power of two maps the envelope's range into [0, 1).
    let span = (reach - least_additive).max(1e-30) * 1.001;
    let depth_scale = span.log2().ceil().exp2().recip();
    let instances: Vec<SiteInstance> = pixels
        .iter()
        .zip(&rects)
        .enumerate()
        .filter_map(|(i, (s, rect))| {
            rect.map(|rect| instance(i as u32, s, rect, frame.scale, least_additive))
        })
        .collect();
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites: sites.len(),
        cones: instances.len(),
        tiles: 1,
        passes: 1,
        bounds_ms: ms(started),
        ..Default::default()
    };

    let started = Instant::now();
    let ids = machine.image(Format::R32Uint, frame.width, frame.height)?;
    let depth = machine.image(Format::Depth, frame.width, frame.height)?;
    let mesh = machine.vertex_buffer(&UNIT_SQUARE)?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    let push = ConePush {
        picture_size: [frame.width as f32, frame.height as f32],
        offset: [0.0, 0.0],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: depth_scale as f32,
        levels: 1,
        metric: metric.shader_code(),
    };
    machine.run(|pass| {
        pass.begin(
            Target {
                color: Some(&ids),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: None,
            },
        )?;
        pass.draw_cones(
            Program::SiteExact,
            &RasterState::lower_envelope(),
            &DrawParams::default(),
            &push,
            &ConeDraw {
                mesh: &mesh,
                first_vertex: 0,
                vertex_count: UNIT_SQUARE.len() as u32,
                instances: &instance_buffer,
                first_instance: 0,
                instance_count: instances.len() as u32,
            },
        )?;
        pass.end()
    })?;
    stats.render_ms = ms(started);

    let started = Instant::now();
    let rect = PixelRect::of(&ids);
    let labels = machine.read_u32(&ids, rect)?;
    let distances = if options.distances {
        let depths = machine.read_f32(&depth, rect)?;
        depths
            .par_iter()
            .zip(&labels)
            .map(|(z, id)| {
                if *id == u32::MAX {
                    f32::INFINITY
                } else {
                    (*z as f64 / depth_scale + least_additive) as f32
                }
            })
            .collect()
    } else {
        Vec::new()
    };
    stats.readback_ms = ms(started);
    Ok(VoronoiDiagram {
        width: frame.width,
        height: frame.height,
        labels,
        distances,
        ties: Vec::new(),
        stats,
    })
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// The site's instance: shape words in pixel coordinates, weights that turn pixel
/// distances into weighted world distances less the smallest additive weight.
fn instance(id: u32, s: &Site, rect: [f32; 4], scale: f64, least_additive: f64) -> SiteInstance {
    let f = |v: f64| v as f32;
    let (kind, shape) = match s.shape {
        Shape::Point(p) => (0, [f(p.x), f(p.y), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Shape::Segment(a, b) => (1, [f(a.x), f(a.y), f(b.x), f(b.y), 0.0, 0.0, 0.0, 0.0]),
        Shape::Circle { center, radius } => (
            2,
            [f(center.x), f(center.y), f(radius), 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => (
            3,
            [
                f(center.x),
                f(center.y),
                f(radius),
                0.0,
                f(start.rem_euclid(std::f64::consts::TAU)),
                f(end - start),
                0.0,
                0.0,
            ],
        ),
    };
    SiteInstance {
        rect,
        shape,
        weights: [
            f(1.0 / (scale * s.multiplicative)),
            f(s.additive - least_additive),
        ],
        kind_id: [kind, id],
    }
}

/// Each site's rectangle (pixel coordinates, `None` where it wins nowhere) and an
/// upper bound on the envelope over the picture.
fn cull(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> (Vec<Option<[f32; 4]>>, f64) {
    let cells_per_side = ((CULL_BUDGET / sites.len()) as f64).sqrt() as usize;
    let cells_per_side = cells_per_side.clamp(1, CULL_CELLS);
    let side = (width.max(height) as f64 / cells_per_side as f64)
        .ceil()
        .max(1.0);
    let (cx, cy) = (
        (width as f64 / side).ceil() as usize,
        (height as f64 / side).ceil() as usize,
    );
    // Cell (i, j) holds the pixel centres [i side, (i + 1) side) (clipped).
    let cells: Vec<(DVec2, DVec2)> = (0..cx * cy)
        .map(|k| {
            let lo = DVec2::new((k % cx) as f64 * side, (k / cx) as f64 * side);
            let hi = (lo + side - 1.0).min(DVec2::new(width as f64 - 1.0, height as f64 - 1.0));
            (lo, hi)
        })
        .collect();
    // Weighted distance bounds of every site over every cell.
    let bounds: Vec<Vec<(f64, f64)>> = sites
        .par_iter()
        .map(|s| {
            cells
                .iter()
                .map(|&(lo, hi)| {
                    let centre = 0.5 * (lo + hi);
                    let d = s.distance_to_shape(metric, centre);
                    let (dlo, dhi) = spread(metric, d, 0.5 * (hi - lo));
                    let w = |d: f64| d / (scale * s.multiplicative) + s.additive;
                    (w(dlo), w(dhi))
                })
                .collect()
        })
        .collect();
    let upper: Vec<f64> = (0..cells.len())
        .map(|c| bounds.iter().map(|b| b[c].1).fold(f64::INFINITY, f64::min))
        .collect();
    let reach = upper.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let rects = bounds
        .par_iter()
        .map(|b| {
            let mut rect: Option<(DVec2, DVec2)> = None;
            for (c, &(lo, _)) in b.iter().enumerate() {
                if lo <= upper[c] {
                    let (a, z) = cells[c];
                    rect = Some(match rect {
                        None => (a, z),
                        Some((ra, rz)) => (ra.min(a), rz.max(z)),
                    });
                }
            }
            // Half a pixel around the centres, so rasterization keeps the rim.
            rect.map(|(a, z)| {
                [
                    (a.x - 0.5) as f32,
                    (a.y - 0.5) as f32,
                    (z.x + 0.5) as f32,
                    (z.y + 0.5) as f32,
                ]
            })
        })
        .collect();
    (rects, reach)
}

/// The range of a distance-to-a-set over a box of half-extents `half` around a
/// point where it is `d`: d ± |half| for norms, and (d^p ± |half|^p)^(1/p) for
/// p < 1, whose p-th power is subadditive.
fn spread(metric: Metric, d: f64, half: DVec2) -> (f64, f64) {
    let h = metric.distance(half);
    match metric {
        Metric::Lp(p) if p < 1.0 => {
            let (dp, hp) = (d.powf(p), h.powf(p));
            ((dp - hp).max(0.0).powf(1.0 / p), (dp + hp).powf(1.0 / p))
        }
        _ => ((d - h).max(0.0), d + h),
    }
}
