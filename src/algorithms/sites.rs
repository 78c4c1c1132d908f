//! Generalized Voronoi diagrams (thesis §3.8–3.9): weighted points, segments,
//! circles and arcs, mixed in one diagram. Each site is drawn as one rectangle
//! whose fragments write the site's exact weighted distance as depth, so the depth
//! test LESS keeps the lower envelope: the thesis's cones with raised apexes and
//! changed angles, roofs over segments and straw huts over circles, evaluated
//! exactly per pixel. In fan mode the same surfaces are drawn as triangles
//! ([`crate::geometry::surface`]), their depths interpolated from their vertices.
//!
//! Rectangles (and fan surfaces) are cut to where a site can win: the picture is divided into cells,
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
        buckets::{for_ring_cells, group_by_bucket},
        chain::{FanMeshes, MetricFan},
        frame::distance2_to_rect,
        metric::Metric,
        site::{check_general_sites, ArcWedge, Shape, Site},
        surface::{fan_surface, Triangles},
    },
    machine::{
        Buffer, Clear, ClearColor, ConeDraw, ConePush, DrawParams, Format, Image, Machine,
        PixelRect, Program, RasterState, SiteBatch, SiteInstance, SiteShape, Target,
    },
};

use super::voronoi::{
    distances_of, drawn_accuracy, hilbert_index, Accuracy, Speedup, VoronoiDiagram, VoronoiOptions,
    VoronoiStats, BATCH, UNIT_SQUARE,
};

/// The Voronoi diagram of `sites` of any shape and weight (world coordinates):
/// every pixel labelled with a site of smallest weighted distance, and the
/// distance map holding that weighted distance (world units). In fan mode the
/// sites' fan surfaces ([`crate::geometry::surface`]) give a distance diagram
/// within the reported bound. Pictures larger than the device's image size (or
/// than `max_tile`) are drawn tile by tile.
pub fn voronoi_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    let frame = options.frame;
    let width = frame.width as usize;
    let mut labels = vec![u32::MAX; frame.len()];
    let mut depths = if options.distances {
        vec![0.0f32; frame.len()]
    } else {
        Vec::new()
    };
    let mut readback_ms = 0.0;
    let (mut stats, depth) = draw_sites(machine, sites, options, |tile| {
        let read = Instant::now();
        let at = tile.y0 as usize * width + tile.x0 as usize;
        machine.read_u32_into(tile.ids, tile.inner, &mut labels[at..], width)?;
        if options.distances {
            machine.read_f32_into(tile.depth, tile.inner, &mut depths[at..], width)?;
        }
        readback_ms += ms(read);
        Ok(())
    })?;
    stats.readback_ms = readback_ms;
    stats.render_ms -= readback_ms;
    let started = Instant::now();
    let distances = distances_of(&depths, &labels, |z| depth.distance(z));
    stats.readback_ms += ms(started);
    Ok(VoronoiDiagram {
        width: frame.width,
        height: frame.height,
        labels,
        distances,
        ties: Vec::new(),
        stats,
    })
}

/// One drawn tile of a diagram of sites: its images (ids, and depth with a clear
/// stencil), where it lies in the picture and the part of it that is picture.
pub(crate) struct DrawnTile<'a> {
    pub ids: &'a Image,
    pub depth: &'a Image,
    pub x0: u32,
    pub y0: u32,
    pub inner: PixelRect,
    pub keys: SiteDepth,
}

/// How depths of a diagram of sites map to weighted distances (world units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SiteDepth {
    pub scale: f64,
    pub least_additive: f64,
}

impl SiteDepth {
    pub fn distance(self, z: f32) -> f64 {
        z as f64 / self.scale + self.least_additive
    }
}

/// Draws the lower envelope of the sites' distance surfaces tile by tile, handing
/// each tile to `visit` while it is on the device.
pub(crate) fn draw_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
    mut visit: impl FnMut(&DrawnTile<'_>) -> Result<()>,
) -> Result<(VoronoiStats, SiteDepth)> {
    let accuracy = match (options.metric, options.accuracy) {
        // Fans over a polygon are exact for points and segments; circles and arcs
        // take chords within a thousandth of a pixel.
        (Metric::Polygon(_), Accuracy::Exact) => Accuracy::Fan {
            epsilon: 1e-3,
            triangles: None,
        },
        (metric, accuracy) => drawn_accuracy(metric, accuracy),
    };
    let options = &VoronoiOptions {
        accuracy,
        ..*options
    };
    let (frame, metric) = (options.frame, options.metric);
    frame.check()?;
    check_general_sites(sites)?;
    options.accuracy.check()?;
    if options.ties {
        return Err(Error::InvalidInput(
            "equal distances are counted for unweighted points only".into(),
        ));
    }
    let side = machine.max_picture_side();
    let max_tile = options.max_tile.unwrap_or(side).min(side);
    if max_tile == 0 {
        return Err(Error::InvalidInput("tile size must be at least 1".into()));
    }
    let started = Instant::now();
    let pixels: Vec<Site> = sites
        .iter()
        .map(|s| s.to_pixels(|p| frame.to_pixel(p), frame.scale))
        .collect();
    let (reaches, envelope_reach) = match options.speedup {
        Speedup::None => picture_wide(&pixels, frame.width, frame.height, metric, frame.scale),
        Speedup::Local | Speedup::Quadtree => {
            cull(&pixels, frame.width, frame.height, metric, frame.scale)
        }
    };
    let least_additive = sites
        .iter()
        .map(|s| s.additive)
        .fold(f64::INFINITY, f64::min);
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites: sites.len(),
        cones: reaches.iter().filter(|r| r.is_some()).count(),
        passes: 1,
        ..Default::default()
    };
    let drawn: Vec<f64> = reaches.iter().flatten().map(|(_, r)| *r).collect();
    if !drawn.is_empty() {
        stats.radius_min = drawn.iter().copied().fold(f64::INFINITY, f64::min);
        stats.radius_max = drawn.iter().copied().fold(0.0, f64::max);
        stats.radius_mean = drawn.iter().sum::<f64>() / drawn.len() as f64;
    }
    let weighted = |s: &Site, d: f64| d / (frame.scale * s.multiplicative) + s.additive;
    // Exact sites are rectangles with per-fragment distances; fans are triangles
    // with per-vertex depths.
    let (draw, reach) = match options.accuracy {
        Accuracy::Exact => {
            let mut instances: Vec<SiteInstance> = pixels
                .iter()
                .zip(&reaches)
                .enumerate()
                .filter_map(|(i, (s, r))| {
                    r.map(|(rect, _)| instance(i as u32, s, rect, frame.scale, least_additive))
                })
                .collect();
            // One draw per shape, each with its own program.
            instances.sort_by_key(|i| SiteShape::of_kind(i.kind_id[0]) as u8);
            let (batches, singles) = batch_sites(instances, metric);
            (SiteDraw::Exact { batches, singles }, envelope_reach)
        }
        Accuracy::Fan { .. } => {
            let fan = super::voronoi::metric_fan(options.accuracy);
            let meshes = FanMeshes::new(metric);
            let surfaces: Vec<(u32, Triangles, f64)> = pixels
                .par_iter()
                .zip(&reaches)
                .enumerate()
                .filter_map(|(i, (s, r))| {
                    r.map(|(_, reach)| {
                        // ε bounds the weighted distance: m ε of shape distance.
                        let fan = match fan {
                            MetricFan::Chain { epsilon } => MetricFan::Chain {
                                epsilon: epsilon * s.multiplicative,
                            },
                            uniform => uniform,
                        };
                        let (t, error) = fan_surface(s, &meshes, fan, reach);
                        (i as u32, t, error / s.multiplicative)
                    })
                })
                .collect();
            let reach = surfaces
                .iter()
                .flat_map(|(i, t, _)| {
                    let s = &pixels[*i as usize];
                    t.iter().flatten().map(move |v| weighted(s, v.z))
                })
                .fold(least_additive, f64::max);
            stats.distance_error_bound =
                surfaces.iter().map(|(_, _, e)| *e).fold(0.0, f64::max) / frame.scale;
            (SiteDraw::Fan(surfaces), reach)
        }
    };
    // A power of two maps the envelope's range into [0, 1).
    let span = (reach - least_additive).max(1e-30) * 1.001;
    let depth_scale = span.log2().ceil().exp2().recip();
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    // Tiles as large as the device (or `max_tile`) allows; each draws the
    // rectangles that meet it, or every fan triangle (the rasterizer clips them).
    let (tile_w, tile_h) = (max_tile.min(frame.width), max_tile.min(frame.height));
    let ids = machine.image(Format::R32Uint, tile_w, tile_h)?;
    // The stencil is left for the visitor (a region mask, for instance).
    let depth = machine.image(Format::DepthStencil, tile_w, tile_h)?;
    let mesh = machine.vertex_buffer(&UNIT_SQUARE)?;
    // The fan surfaces' two per-vertex buffers, made once for every tile.
    let fans = match &draw {
        SiteDraw::Exact { .. } => None,
        SiteDraw::Fan(surfaces) => {
            let mut vertices: Vec<[f32; 3]> = Vec::new();
            let mut ids: Vec<u32> = Vec::new();
            for (i, triangles, _) in surfaces {
                let s = &pixels[*i as usize];
                for v in triangles.iter().flatten() {
                    let depth = (weighted(s, v.z) - least_additive) * depth_scale;
                    vertices.push([v.x as f32, v.y as f32, depth as f32]);
                    ids.push(*i);
                }
            }
            let count = vertices.len() as u32;
            // Vulkan buffers cannot be empty.
            vertices.push([0.0; 3]);
            ids.push(0);
            Some((
                machine.vertex_buffer(&vertices)?,
                machine.vertex_buffer(&ids)?,
                count,
            ))
        }
    };
    for y0 in (0..frame.height).step_by(tile_h as usize) {
        for x0 in (0..frame.width).step_by(tile_w as usize) {
            stats.tiles += 1;
            let inner = PixelRect {
                x: 0,
                y: 0,
                width: tile_w.min(frame.width - x0),
                height: tile_h.min(frame.height - y0),
            };
            let (lo, hi) = (
                [x0 as f32 - 0.5, y0 as f32 - 0.5],
                [
                    (x0 + inner.width) as f32 - 0.5,
                    (y0 + inner.height) as f32 - 0.5,
                ],
            );
            let meets = |rect: &[f32; 4]| {
                rect[0] < hi[0] && rect[2] > lo[0] && rect[1] < hi[1] && rect[3] > lo[1]
            };
            let ((batch_shapes, batches), singles): ((Vec<SiteShape>, Vec<SiteBatch>), Vec<_>) =
                match &draw {
                    SiteDraw::Exact { batches, singles } => (
                        batches
                            .iter()
                            .filter(|(_, b)| meets(&b.rect))
                            .copied()
                            .unzip(),
                        singles.iter().filter(|i| meets(&i.rect)).copied().collect(),
                    ),
                    SiteDraw::Fan(_) => Default::default(),
                };
            let batch_buffer = (!batches.is_empty())
                .then(|| machine.vertex_buffer(&batches))
                .transpose()?;
            let rects = (!singles.is_empty())
                .then(|| machine.vertex_buffer(&singles))
                .transpose()?;
            let mut draws: Vec<(Program, ConeDraw)> = Vec::new();
            if let Some((vertices, ids, count)) = &fans {
                draws.push((
                    Program::SiteFan,
                    ConeDraw {
                        mesh: vertices,
                        first_vertex: 0,
                        vertex_count: *count,
                        instances: ids,
                        first_instance: 0,
                        instance_count: u32::from(*count > 0),
                    },
                ));
            }
            if let Some(buffer) = &batch_buffer {
                let shapes = batch_shapes.iter().copied();
                draws.extend(rect_draws(&mesh, Program::SiteExactBatch, shapes, buffer));
            }
            if let Some(buffer) = &rects {
                let shapes = singles.iter().map(|i| SiteShape::of_kind(i.kind_id[0]));
                draws.extend(rect_draws(&mesh, Program::SiteExact, shapes, buffer));
            }
            // With nothing drawn the tile keeps the "no site" id.
            let push = ConePush {
                picture_size: [tile_w as f32, tile_h as f32],
                offset: [x0 as f32, y0 as f32],
                vertex_depth_scale: 0.0,
                fragment_depth_scale: depth_scale as f32,
                levels: 1,
                // Polygons are drawn as fans (see above).
                metric: metric.shader_code().unwrap_or((0, 2.0)),
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
                        stencil: Some(0),
                    },
                )?;
                for (program, draw) in &draws {
                    pass.draw_cones(
                        *program,
                        &RasterState::lower_envelope(),
                        &DrawParams::default(),
                        &push,
                        draw,
                    )?;
                }
                pass.end()
            })?;
            visit(&DrawnTile {
                ids: &ids,
                depth: &depth,
                x0,
                y0,
                inner,
                keys: SiteDepth {
                    scale: depth_scale,
                    least_additive,
                },
            })?;
        }
    }
    stats.render_ms = ms(started);
    Ok((
        stats,
        SiteDepth {
            scale: depth_scale,
            least_additive,
        },
    ))
}

/// What one diagram draws.
enum SiteDraw {
    /// Batches of small sites of the shapes [`batched`] under the metric, and
    /// one rectangle per other site, both sorted by shape.
    Exact {
        batches: Vec<(SiteShape, SiteBatch)>,
        singles: Vec<SiteInstance>,
    },
    /// Each site's fan surface with its error bound (world units).
    Fan(Vec<(u32, Triangles, f64)>),
}

/// One draw of `program` per run of a shape among the `instances` (rectangles
/// of the unit square `mesh`), whose shapes in order are `shapes`.
fn rect_draws<'a>(
    mesh: &'a Buffer,
    program: fn(SiteShape) -> Program,
    shapes: impl Iterator<Item = SiteShape>,
    instances: &'a Buffer,
) -> Vec<(Program, ConeDraw<'a>)> {
    let mut draws: Vec<(Program, ConeDraw<'a>)> = Vec::new();
    for (k, shape) in shapes.enumerate() {
        match draws.last_mut() {
            Some((last, draw)) if *last == program(shape) => draw.instance_count += 1,
            _ => draws.push((
                program(shape),
                ConeDraw {
                    mesh,
                    first_vertex: 0,
                    vertex_count: UNIT_SQUARE.len() as u32,
                    instances,
                    first_instance: k as u32,
                    instance_count: 1,
                },
            )),
        }
    }
    draws
}

/// Largest side (pixels) of a batched site's rectangle: a batch's rectangle is
/// the bounding box of its sites', so one large site would widen it for all
/// eight.
const BATCH_SIDE_LIMIT: f32 = 96.0;

/// Whether sites of `shape` under `metric` are drawn in batches: those whose
/// distance costs a few operations (Euclidean points, segments, circles and
/// arcs; L1 and L∞ points and segments). A batch evaluates eight per fragment
/// (four arcs), so the searches of curves under other metrics and of L_p stay
/// one to a rectangle.
fn batched(metric: Metric, shape: SiteShape) -> bool {
    match metric {
        Metric::L2 => true,
        Metric::L1 | Metric::LInf => matches!(shape, SiteShape::Point | SiteShape::Segment),
        _ => false,
    }
}

/// Splits sites' rectangles (sorted by shape) into batches of up to eight
/// neighbours along a Hilbert curve, for the shapes [`batched`] under `metric`
/// with small rectangles, and the rest, drawn one by one.
fn batch_sites(
    instances: Vec<SiteInstance>,
    metric: Metric,
) -> (Vec<(SiteShape, SiteBatch)>, Vec<SiteInstance>) {
    let (mut batched, singles): (Vec<SiteInstance>, Vec<SiteInstance>) =
        instances.into_iter().partition(|i| {
            batched(metric, SiteShape::of_kind(i.kind_id[0]))
                && i.rect[2] - i.rect[0] <= BATCH_SIDE_LIMIT
                && i.rect[3] - i.rect[1] <= BATCH_SIDE_LIMIT
        });
    batched.sort_by_cached_key(|i| {
        let q = |v: f32| (v.max(0.0) as u32).min(65535);
        let centre = |a: usize| q(0.5 * (i.rect[a] + i.rect[a + 2]));
        (i.kind_id[0], hilbert_index(centre(0), centre(1)))
    });
    let mut batches = Vec::new();
    for run in batched.chunk_by(|a, b| a.kind_id[0] == b.kind_id[0]) {
        let shape = SiteShape::of_kind(run[0].kind_id[0]);
        // An arc's shape takes two of the batch's shape slots.
        let words = if shape == SiteShape::Arc { 2 } else { 1 };
        for chunk in run.chunks(BATCH / words) {
            let mut batch = SiteBatch {
                rect: [f32::MAX, f32::MAX, f32::MIN, f32::MIN],
                shapes: [[0.0; 4]; BATCH],
                weights: [[0.0; 2]; BATCH],
                ids: [0; BATCH],
            };
            for k in 0..BATCH / words {
                let site = &chunk[k.min(chunk.len() - 1)];
                for w in 0..words {
                    batch.shapes[words * k + w].copy_from_slice(&site.shape[4 * w..][..4]);
                }
                batch.weights[k] = site.weights;
                batch.ids[k] = site.kind_id[1];
                for a in 0..2 {
                    batch.rect[a] = batch.rect[a].min(site.rect[a]);
                    batch.rect[a + 2] = batch.rect[a + 2].max(site.rect[a + 2]);
                }
            }
            batches.push((shape, batch));
        }
    }
    (batches, singles)
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
                f(end - start),
                f(start.cos()),
                f(start.sin()),
                f(end.cos()),
                f(end.sin()),
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

/// A site's rectangle (pixel coordinates) and the largest shape distance (pixels)
/// it may have where it wins.
type Reach = ([f32; 4], f64);

/// Side of the site cull's blocks, in cells (see `cull`). Blocks of 4 took the
/// cull's site pass at 16000 sites (medians of six) from 10.7 to 8.8 ms for
/// weighted points, whose reach varies with their weights; arcs 10.2 → 9.3,
/// circles 8.6 → 8.3, segments unchanged.
const CULL_BLOCK: usize = 4;

/// Each site's [`Reach`], `None` where it wins nowhere, and an upper bound on the
/// envelope over the picture.
///
/// Cells of about half the sites' spacing: a cell's upper bound is the smallest
/// largest-distance of the sites binned near it (any subset of the sites bounds
/// the envelope from above); a site then visits the cells that the largest
/// upper bound reaches from its box, skipping blocks of cells whose largest
/// bound it cannot reach, and keeping the cells where its smallest distance can
/// reach the cell's bound.
fn cull(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> (Vec<Option<Reach>>, f64) {
    let spacing = (width as f64 * height as f64 / sites.len() as f64).sqrt();
    // At 16000 sites cells of a third of the spacing took 27-35 ms of bounds
    // for weights and segments, a half 21-25 ms, with the rectangles only a
    // little larger (whole segment diagrams 66 -> 51-53 ms). Few sites have
    // few cells to walk: down to 16 pixels, but no less than an eighth of the
    // spacing (a cell's walk to its nearest site stays short), keeps their
    // rectangles near their regions (circles at 100 sites 15 -> 13 ms).
    let side = (spacing / 2.0)
        .min(16.0)
        .max(spacing / 8.0)
        .clamp(3.0, 64.0)
        .floor();
    let (cx, cy) = (
        (width as f64 / side).ceil() as usize,
        (height as f64 / side).ceil() as usize,
    );
    let cell_of = |v: f64, n: usize| ((v / side).floor().max(0.0) as usize).min(n - 1);
    // Cell (i, j) holds the pixel centres [i side, (i + 1) side) (clipped).
    let bounds_of = |i: usize, j: usize| {
        let lo = DVec2::new(i as f64 * side, j as f64 * side);
        let hi = (lo + side - 1.0).min(DVec2::new(width as f64 - 1.0, height as f64 - 1.0));
        (lo, hi)
    };
    let weighted = |s: &Site, d: f64| d / (scale * s.multiplicative) + s.additive;
    // Arcs are measured (in L2, see `spread`) many times each: their wedges
    // once.
    let wedges: Vec<Option<ArcWedge>> = sites
        .iter()
        .map(|s| match s.shape {
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Some(ArcWedge::new(center, radius, start, end)),
            _ => None,
        })
        .collect();
    let range = |k: usize, i: usize, j: usize| {
        let (lo, hi) = bounds_of(i, j);
        let s = &sites[k];
        // Only arcs read their wedge (the others' would cost a cache miss).
        let wedge = match s.shape {
            Shape::Arc { .. } => wedges[k].as_ref(),
            _ => None,
        };
        let (dlo, dhi) = spread(s, wedge, metric, 0.5 * (lo + hi), 0.5 * (hi - lo));
        (weighted(s, dlo), weighted(s, dhi), dhi)
    };
    // Sites binned by the cell of their box's centre.
    let (bin_start, binned) = group_by_bucket(
        cx * cy,
        sites.iter().enumerate().map(|(k, s)| {
            let (lo, hi) = s.bounds();
            let c = 0.5 * (lo + hi);
            (cell_of(c.y, cy) * cx + cell_of(c.x, cx), k as u32)
        }),
    );
    let bin = |x: usize, y: usize| {
        let b = y * cx + x;
        &binned[bin_start[b] as usize..bin_start[b + 1] as usize]
    };
    let (a, _) = metric.euclidean_bounds();
    // Upper bounds from the sites of the nearest non-empty rings of bins.
    let upper: Vec<f64> = (0..cx * cy)
        .into_par_iter()
        .map(|c| {
            let (i, j) = (c % cx, c / cx);
            let block = [i as isize, j as isize, i as isize, j as isize];
            let (lo, hi) = bounds_of(i, j);
            let centre = 0.5 * (lo + hi);
            let mut best = f64::INFINITY;
            for ring in 0..cx.max(cy) {
                for_ring_cells((cx, cy), block, ring, |x, y| {
                    for &k in bin(x, y) {
                        // A site whose box is already too far cannot lower the
                        // bound: its largest distance exceeds a times that gap.
                        let s = &sites[k as usize];
                        let (blo, bhi) = s.bounds();
                        let gap = distance2_to_rect(centre, blo, bhi).sqrt();
                        if weighted(s, a * gap) < best {
                            best = best.min(range(k as usize, i, j).1);
                        }
                    }
                });
                // One more ring after the first find tightens the bound cheaply.
                if best.is_finite() && ring >= 1 {
                    break;
                }
            }
            best
        })
        .collect();
    let reach = upper.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // The largest bound in each block of CULL_BLOCK x CULL_BLOCK cells: a site
    // skips a block beyond its reach there without visiting the cells.
    let blocks_across = cx.div_ceil(CULL_BLOCK);
    let mut block_bounds = vec![f64::NEG_INFINITY; blocks_across * cy.div_ceil(CULL_BLOCK)];
    for (c, &bound) in upper.iter().enumerate() {
        let b = c / cx / CULL_BLOCK * blocks_across + c % cx / CULL_BLOCK;
        block_bounds[b] = block_bounds[b].max(bound);
    }
    let reaches = sites
        .par_iter()
        .enumerate()
        .map(|(k, s)| {
            let (blo, bhi) = s.bounds();
            // Where the cell's bound is its weighted distance, the shape distance.
            let limit_of = |bound: f64| (bound - s.additive) * scale * s.multiplicative;
            // No cell's bound is above the largest: the site owns no pixel
            // farther than this (Euclidean) from its box.
            let widest = limit_of(reach) / a * (1.0 + 1e-9);
            if widest.is_nan() || widest < 0.0 {
                return None;
            }
            // Whether the pixel centres [p, q] lie beyond a shape distance of
            // `limit` from the site: a Euclidean 1 / a times that from its box.
            let beyond = |limit: f64, p: DVec2, q: DVec2| {
                let gap = (p - bhi).max(blo - q).max(DVec2::ZERO);
                limit < 0.0 || a * a * gap.length_squared() > limit * limit * (1.0 + 1e-9)
            };
            let mut rect: Option<(DVec2, DVec2)> = None;
            let mut far = 0.0f64;
            let mut visit = |x: usize, y: usize| {
                let bound = upper[y * cx + x];
                let limit = limit_of(bound);
                // Most cells fail on the gap between them and the site's box.
                let (p, q) = bounds_of(x, y);
                if beyond(limit, p, q) {
                    return;
                }
                let (lo, _, d) = range(k, x, y);
                if lo <= bound {
                    // The site owns a pixel of the cell only where its
                    // weighted distance is at most the cell's bound: within
                    // that shape distance of the shape, and a Euclidean 1 / a
                    // times that of its box.
                    let owned = d.min(limit);
                    let grow = owned / a * (1.0 + 1e-9);
                    let (p, q) = (p.max(blo - grow), q.min(bhi + grow));
                    if p.cmple(q).all() {
                        far = far.max(owned);
                        rect = Some(match rect {
                            None => (p, q),
                            Some((rp, rq)) => (rp.min(p), rq.max(q)),
                        });
                    }
                }
            };
            let (x0, x1) = (cell_of(blo.x - widest, cx), cell_of(bhi.x + widest, cx));
            let (y0, y1) = (cell_of(blo.y - widest, cy), cell_of(bhi.y + widest, cy));
            for j in y0 / CULL_BLOCK..=y1 / CULL_BLOCK {
                for i in x0 / CULL_BLOCK..=x1 / CULL_BLOCK {
                    let (columns, rows) = (
                        CULL_BLOCK * i..(CULL_BLOCK * (i + 1)).min(cx),
                        CULL_BLOCK * j..(CULL_BLOCK * (j + 1)).min(cy),
                    );
                    let (p, _) = bounds_of(columns.start, rows.start);
                    let (_, q) = bounds_of(columns.end - 1, rows.end - 1);
                    if beyond(limit_of(block_bounds[j * blocks_across + i]), p, q) {
                        continue;
                    }
                    for y in rows.start.max(y0)..rows.end.min(y1 + 1) {
                        for x in columns.start.max(x0)..columns.end.min(x1 + 1) {
                            visit(x, y);
                        }
                    }
                }
            }
            // Half a pixel around the centres, so rasterization keeps the rim; a
            // pixel more of reach for the same reason.
            rect.map(|(p, q)| {
                let rect = [
                    (p.x - 0.5) as f32,
                    (p.y - 0.5) as f32,
                    (q.x + 0.5) as f32,
                    (q.y + 0.5) as f32,
                ];
                (rect, far + 1.0)
            })
        })
        .collect();
    (reaches, reach)
}

/// Every site over the whole picture (no speedup), reaching the farthest pixel:
/// the Euclidean distance to the far corner of its box, stretched by the metric.
fn picture_wide(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> (Vec<Option<Reach>>, f64) {
    let (lo, hi) = (
        DVec2::splat(0.0),
        DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
    );
    let rect = [-0.5, -0.5, width as f32 - 0.5, height as f32 - 0.5];
    let b = metric.euclidean_bounds().1;
    let reaches: Vec<Option<Reach>> = sites
        .iter()
        .map(|s| {
            let (a, z) = s.bounds();
            let far = (hi - a).max(z - lo).length();
            Some((rect, b * far + 1.0))
        })
        .collect();
    // The envelope is at most any one site's largest weighted distance.
    let envelope = sites
        .iter()
        .zip(&reaches)
        .map(|(s, r)| {
            r.map_or(f64::INFINITY, |r| {
                r.1 / (scale * s.multiplicative) + s.additive
            })
        })
        .fold(f64::INFINITY, f64::min);
    (reaches, envelope)
}

/// The range of the site's shape distance over a box of half-extents `half`
/// around `centre`. A point's is exact under the L_p norms, which grow with
/// each coordinate's size: the box's nearest and farthest offsets from it.
/// Other shapes' comes from the value d at the centre: d ± |half| for the L_p
/// norms, and (d^p ± |half|^p)^(1/p) for p < 1, whose p-th power is
/// subadditive. A polygon need be neither symmetric nor convex, and segments
/// and curves under L_p are costly to measure: their range comes from the
/// Euclidean one and the bounds a |x| <= |x| <= b |x| of the metric.
fn spread(
    site: &Site,
    wedge: Option<&ArcWedge>,
    metric: Metric,
    centre: DVec2,
    half: DVec2,
) -> (f64, f64) {
    if let (Shape::Point(p), Metric::L2 | Metric::L1 | Metric::LInf | Metric::Lp(_)) =
        (site.shape, metric)
    {
        let offset = (p - centre).abs();
        return (
            metric.distance((offset - half).max(DVec2::ZERO)),
            metric.distance(offset + half),
        );
    }
    // Distances to extended shapes under other metrics need a search per
    // evaluation (but under L1 and L∞, a few candidates), and polygon gauges
    // bound nothing by their value at the centre; the Euclidean range is
    // closed-form and, stretched, as rigorous.
    if !matches!(metric, Metric::L2 | Metric::L1 | Metric::LInf) {
        let (a, b) = metric.euclidean_bounds();
        let (lo, hi) = spread(site, wedge, Metric::L2, centre, half);
        return (a * lo, b * hi);
    }
    let d = match wedge {
        Some(wedge) if metric == Metric::L2 => wedge.distance(centre),
        _ => site.distance_to_shape(metric, centre),
    };
    let h = metric.distance(half);
    match metric {
        Metric::Lp(p) if p < 1.0 => {
            let (dp, hp) = (d.powf(p), h.powf(p));
            ((dp - hp).max(0.0).powf(1.0 / p), (dp + hp).powf(1.0 / p))
        }
        _ => ((d - h).max(0.0), d + h),
    }
}
