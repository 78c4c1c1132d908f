//! Generalized Voronoi diagrams (thesis §3.8–3.9): weighted points, segments,
//! circles and arcs, mixed in one diagram. Each site is drawn as one rectangle
//! whose fragments write the site's exact weighted distance as depth, so the depth
//! test LESS keeps the lower envelope: the thesis's cones with raised apexes and
//! changed angles, roofs over segments and straw huts over circles, evaluated
//! exactly per pixel. In fan mode the same surfaces are drawn as triangles
//! (`crate::geometry::surface`), their depths interpolated from their vertices.
//!
//! Rectangles (and fan surfaces) are cut to where a site can win: the picture is divided into cells,
//! each cell gets an upper bound on the envelope (the smallest over the sites of
//! their largest weighted distance in the cell) and a site is drawn over the cells
//! where its smallest weighted distance is at most that bound. Distances to a set
//! change by at most the metric's size of the step (for p < 1, their p-th powers
//! by the p-th power of it), which bounds both from the cell's centre; Euclidean
//! segments and circles are bounded exactly.
//!
//! In exact mode sites under L2 (and under L1 and L∞ where some are segments or
//! curves) are not drawn at all: the same cells, one per 8-pixel screen tile
//! where sites are dense, list the sites that may win in them by their smallest
//! distance there, and one triangle over the picture takes each pixel's lowest
//! distance from its tile's list, stopping at the first site that cannot win
//! (`glsl/site_tiles.frag`), as the point diagrams do. A pixel then evaluates a
//! few sites instead of every site whose rectangle covers it.

use crate::algorithms::ms;
use crate::memory::Gather;
use std::time::Instant;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::{
    backend::drawn_only,
    error::{Error, Result},
    geometry::cone::check_fan_size,
    geometry::{
        buckets::{for_ring_cells, group_by_bucket},
        chain::{FanMeshes, MetricFan},
        frame::distance2_to_rect,
        metric::{segment_distance, Metric},
        site::{check_general_sites, ArcWedge, Shape, Site},
        surface::{fan_surface, FanSurface},
    },
    machine::{
        Buffer, Clear, ClearColor, DrawParams, Format, GraphicsProgram, Machine, PixelRect,
        RasterState, Target,
    },
    Backend,
};

use crate::algorithms::cones::{
    draw_cones, draw_over_target, ConeDraw, ConePush, SiteBatch, SiteInstance, SiteShape,
    SITE_EXACT, SITE_EXACT_BATCH, SITE_FAN, SITE_FAN_FOLDED, SITE_TILES,
};

use super::{VoronoiDiagram, VoronoiOptions, VoronoiStats};
use crate::algorithms::envelope::{
    distances_of, drawn_accuracy, hilbert_index, metric_fan, records_image, Accuracy, DepthMap,
    DrawnTile, Speedup, Tiling, Tuning, BATCH, SCREEN_TILE_SIDE, UNIT_SQUARE,
};

mod certify;
mod cpu;
mod draws;
mod reach;
mod tiles;

pub(crate) use certify::SiteCertifier;

use draws::*;
use reach::*;
use tiles::*;

/// The Voronoi diagram of `sites` of any shape and weight (world coordinates):
/// every pixel labelled with a site of smallest weighted distance, and the
/// distance map holding that weighted distance (world units). In fan mode the
/// sites' fan surfaces (`crate::geometry::surface`) give a distance diagram
/// within the reported bound. Pictures larger than the device's image size (or
/// than `max_tile`) are drawn tile by tile.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{
///     algorithms::voronoi::{voronoi, VoronoiOptions},
///     geometry::{site::{Shape, Site}, Frame},
/// };
///
/// let road = Site::new(Shape::Segment(DVec2::new(0.0, 10.0), DVec2::new(31.0, 10.0)));
/// let town = Site { multiplicative: 2.0, ..Site::point(DVec2::new(16.0, 2.0)) };
/// let options = VoronoiOptions::exact(Frame::pixels(32, 16)?);
/// let d = voronoi(&pixgeo::Backend::Cpu, &[road, town], &options)?;
/// assert_eq!(d.labels[15 * 32], 0); // the bottom-left corner is nearest the road
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub(crate) fn voronoi_of_sites(
    backend: &Backend,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    if options.window.is_some() {
        return Err(Error::unsupported_option(
            "windows take point sites: compute segments, circles, arcs and weighted sites \
             on the whole picture"
                .into(),
        ));
    }
    match backend {
        Backend::Device(machine) => drawn_sites(machine, sites, options),
        Backend::Cpu => {
            if options.ties || options.accuracy != Accuracy::Exact {
                return Err(drawn_only(
                    "fans and counts of equal distances for weighted or extended sites",
                ));
            }
            let started = Instant::now();
            let (labels, distances) = cpu::voronoi_sites(sites, &options.frame, options.metric)?;
            let stats = VoronoiStats {
                device: "cpu".into(),
                sites: sites.len(),
                render_ms: ms(started),
                ..Default::default()
            };
            let distances = match options.distances {
                true => distances,
                false => Vec::new(),
            };
            Ok(VoronoiDiagram::whole(
                options.frame,
                labels,
                distances,
                stats,
            ))
        }
    }
}

/// [`voronoi_of_sites`] drawn on `machine`, then proved in exact mode.
fn drawn_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    check_general_sites(sites)?;
    let exact = options.accuracy == Accuracy::Exact;
    if exact {
        check_exact_metric(sites, options.metric)?;
    }
    let mut d = proposed_diagram(machine, sites, options)?;
    if exact {
        let certify = Instant::now();
        let certifier = SiteCertifier::new(sites, &options.frame, options.metric)?;
        let distances = options.distances.then_some(&mut d.distances[..]);
        d.stats.mended = certifier.certify(&mut d.labels, distances)?;
        d.stats.certify_ms = ms(certify);
    }
    Ok(d)
}

/// Segments and curves under L_p (p not 1, 2 or ∞), and curves under a
/// polygon's gauge, have no distance that exact arithmetic holds (it is a
/// minimum along the shape with no closed form): refused in exact mode.
pub(crate) fn check_exact_metric(sites: &[Site], metric: Metric) -> Result<()> {
    let curved = |s: &Site| matches!(s.shape, Shape::Circle { .. } | Shape::Arc { .. });
    let refused = match metric {
        Metric::Lp(_) => sites.iter().find(|s| !matches!(s.shape, Shape::Point(_))),
        Metric::Polygon(_) => sites.iter().find(|s| curved(s)),
        _ => None,
    };
    match refused {
        Some(site) => Err(Error::unsupported_option(format!(
            "{} under {metric} have no exact distance (a minimum along the shape with no \
             closed form): exact mode takes segments, circles and arcs under L1, L2 and L∞, \
             and segments under polygons; fan mode draws them within its reported bound \
             (for L_p, p >= 1)",
            match site.shape {
                Shape::Segment(..) => "segments",
                _ => "circles and arcs",
            }
        ))),
        None => Ok(()),
    }
}

/// The diagram the device draws, before certification.
fn proposed_diagram(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    // A site whose additive weight alone exceeds another's whole weighted
    // distance over the picture wins nowhere, and a weight common to all
    // changes no label: left in, either would stretch the depth range past
    // float32's resolution. The rest is drawn with the least weight at 0, and
    // the distances get it back.
    let kept = winners_by_weight(sites, &options.frame, options.metric);
    let shift = kept
        .iter()
        .map(|&i| sites[i as usize].additive)
        .fold(f64::INFINITY, f64::min);
    if kept.len() < sites.len() || (shift != 0.0 && shift.is_finite()) {
        let chosen: Vec<Site> = kept
            .iter()
            .map(|&i| Site {
                additive: sites[i as usize].additive - shift,
                ..sites[i as usize]
            })
            .gather("additive")?;
        let mut d = proposed_diagram(machine, &chosen, options)?;
        for label in d.labels.iter_mut().filter(|l| **l != u32::MAX) {
            *label = kept[*label as usize];
        }
        for distance in &mut d.distances {
            *distance = (*distance as f64 + shift) as f32;
        }
        d.stats.sites = sites.len();
        return Ok(d);
    }
    let frame = options.frame;
    let width = frame.width as usize;
    frame.reserve(8, "a Voronoi diagram of sites")?;
    let mut labels = crate::memory::filled(frame.len(), u32::MAX, "labels")?;
    let mut depths = if options.distances {
        crate::memory::filled(frame.len(), 0.0f32, "distances")?
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
    Ok(VoronoiDiagram::whole(frame, labels, distances, stats))
}

/// The sites that may win some pixel by their additive weights: the site of
/// the smallest additive weight bounds the envelope everywhere by that weight
/// plus its farthest weighted distance from the picture, and a site whose
/// weight alone exceeds the bound wins nowhere.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn winners_by_weight(sites: &[Site], frame: &crate::geometry::Frame, metric: Metric) -> Vec<u32> {
    let Some(least) = sites
        .iter()
        .min_by(|a, b| a.additive.total_cmp(&b.additive))
    else {
        return Vec::new();
    };
    let corners = [
        frame.to_world(DVec2::splat(-0.5)),
        frame.to_world(DVec2::new(
            frame.width as f64 - 0.5,
            frame.height as f64 - 0.5,
        )),
    ];
    let (lo, hi) = least.bounds();
    let farthest =
        (corners[0].min(corners[1]).min(lo) - corners[0].max(corners[1]).max(hi)).length();
    let bound = least.additive + metric.euclidean_bounds().1 * farthest / least.multiplicative;
    (0..sites.len() as u32)
        .filter(|&i| sites[i as usize].additive <= bound)
        .collect()
}

/// Draws the lower envelope of the sites' distance surfaces tile by tile, handing
/// each tile to `visit` while it is on the device.
pub(crate) fn draw_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
    mut visit: impl FnMut(&DrawnTile<'_>) -> Result<()>,
) -> Result<(VoronoiStats, DepthMap)> {
    let accuracy = match (options.metric, options.accuracy) {
        // Fans over a polygon are exact for points and segments; circles and arcs
        // take chords within a thousandth of a pixel (which is why
        // `voronoi_of_sites` refuses them in exact mode).
        (Metric::Polygon(_), Accuracy::Exact) => Accuracy::Fan {
            epsilon: 1e-3,
            triangles: None,
        },
        (metric, accuracy) => drawn_accuracy(metric, accuracy),
    };
    let options = &VoronoiOptions {
        accuracy,
        ..options.clone()
    };
    let (frame, metric) = (options.frame, options.metric);
    frame.check()?;
    check_general_sites(sites)?;
    options.accuracy.check_for(options.metric)?;
    if options.ties {
        return Err(Error::unsupported_option(
            "equal distances are counted for unweighted points only".into(),
        ));
    }
    let window = PixelRect::sized(frame.width, frame.height);
    let tiling = Tiling::new(machine, options.max_tile, window, u32::MAX)?;
    let started = Instant::now();
    let pixels: Vec<Site> = sites
        .iter()
        .map(|s| s.to_pixels(|p| frame.to_pixel(p), frame.scale))
        .gather("pixels")?;
    let least_additive = sites
        .iter()
        .map(|s| s.additive)
        .fold(f64::INFINITY, f64::min);
    // Exact sites under L2 are found per screen tile where the picture takes one
    // tile image, and under L1 and L∞ where some are segments or curves (their
    // points alone cost less in batches, docs/tuning.md); their rectangles are
    // drawn where the lists would be too long.
    let one_image = tiling.is_single();
    let listed = match metric {
        Metric::L2 => true,
        Metric::L1 | Metric::LInf => sites.iter().any(|s| !matches!(s.shape, Shape::Point(_))),
        _ => false,
    };
    if options.accuracy == Accuracy::Exact
        && options.speedup == Speedup::Local
        && listed
        && one_image
    {
        let tiled = draw_site_tiles(
            machine,
            &pixels,
            options,
            least_additive,
            started,
            &mut visit,
        )?;
        if let Some(drawn) = tiled {
            return Ok(drawn);
        }
    }
    let (reaches, envelope_reach) = match options.speedup {
        Speedup::None => picture_wide(&pixels, frame.width, frame.height, metric, frame.scale),
        Speedup::Local | Speedup::Quadtree => {
            cull(&pixels, frame.width, frame.height, metric, frame.scale)?
        }
    };
    let drawn: Vec<f64> = reaches.iter().flatten().map(|(_, r)| *r).gather("drawn")?;
    let mut stats = site_stats(machine, sites.len(), &drawn);
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
                .gather("instances")?;
            // One draw per shape, each with its own program.
            instances.sort_by_key(|i| SiteShape::of_kind(i.kind_id[0]) as u8);
            let (batches, singles) = batch_sites(instances, metric, &Tuning::of(machine)?);
            (SiteDraw::Exact { batches, singles }, envelope_reach)
        }
        Accuracy::Fan { .. } => {
            let fan = metric_fan(options.accuracy);
            let meshes = FanMeshes::new(metric);
            if let MetricFan::Chain { epsilon } = fan {
                for (s, r) in pixels.iter().zip(&reaches) {
                    if let Some((_, reach)) = r {
                        let (lo, hi) = s.bounds();
                        let size = (hi - lo).length() / 2.0;
                        check_fan_size(reach + size, epsilon * s.multiplicative)?;
                    }
                }
            }
            let surfaces: Vec<(u32, FanSurface)> = pixels
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
                        (i as u32, fan_surface(s, &meshes, fan, reach))
                    })
                })
                .collect();
            // A folded surface's distances are its values' magnitudes.
            let reach = surfaces
                .par_iter()
                .map(|(i, f)| {
                    let s = &pixels[*i as usize];
                    f.triangles
                        .iter()
                        .flatten()
                        .map(|v| weighted(s, v.z.abs()))
                        .fold(least_additive, f64::max)
                })
                .reduce(|| least_additive, f64::max);
            stats.distance_error_bound = surfaces
                .iter()
                .map(|(i, f)| f.error / pixels[*i as usize].multiplicative)
                .fold(0.0, f64::max)
                / frame.scale;
            (SiteDraw::Fan(surfaces), reach)
        }
    };
    let depth_scale = depth_scale_of(reach, least_additive);
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    // Tiles as large as the device (or `max_tile`) allows; each draws the
    // rectangles that meet it, or every fan triangle (the rasterizer clips them).
    let (tile_w, tile_h) = (tiling.tile_w, tiling.tile_h);
    let ids = machine.image(Format::R32Uint, tile_w, tile_h)?;
    // The stencil is left for the visitor (a region mask, for instance).
    let depth = machine.image(Format::DepthStencil, tile_w, tile_h)?;
    let mesh = machine.vertex_buffer(&UNIT_SQUARE)?;
    // The fan surfaces' per-vertex buffers, plain and folded, made once for
    // every tile. Triangles that leave the picture come last: lavapipe clips
    // a run of vertices holding one through its slow general path.
    let depth_of = |s: &Site, z: f64| ((weighted(s, z) - least_additive) * depth_scale) as f32;
    let (right, bottom) = (frame.width as f64 - 0.5, frame.height as f64 - 0.5);
    let inside = |v: &DVec3| v.x >= -0.5 && v.y >= -0.5 && v.x <= right && v.y <= bottom;
    let fans = match &draw {
        SiteDraw::Exact { .. } => Vec::new(),
        SiteDraw::Fan(surfaces) => {
            let mut plain = [FanBuffers::<3>::default(), FanBuffers::default()];
            let mut folded = [FanBuffers::<4>::default(), FanBuffers::default()];
            for (i, surface) in surfaces {
                let s = &pixels[*i as usize];
                let zero = depth_of(s, 0.0);
                for (k, triangle) in surface.triangles.iter().enumerate() {
                    let leaves = usize::from(!triangle.iter().all(inside));
                    for v in triangle {
                        let (x, y, depth) = (v.x as f32, v.y as f32, depth_of(s, v.z));
                        match k < surface.folded {
                            false => plain[leaves].push([x, y, depth], *i),
                            true => folded[leaves].push([x, y, depth, zero], *i),
                        }
                    }
                }
            }
            let [mut plain, leaving] = plain;
            plain.append(leaving);
            let [mut folded, leaving] = folded;
            folded.append(leaving);
            Vec::from([
                plain.upload(machine, &SITE_FAN)?,
                folded.upload(machine, &SITE_FAN_FOLDED)?,
            ])
        }
    };
    for (x0, y0, inner) in tiling.tiles() {
        stats.tiles += 1;
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
                    singles
                        .iter()
                        .filter(|i| meets(&i.rect))
                        .copied()
                        .gather("meets")?,
                ),
                SiteDraw::Fan(_) => Default::default(),
            };
        let batch_buffer = (!batches.is_empty())
            .then(|| machine.vertex_buffer(&batches))
            .transpose()?;
        let rects = (!singles.is_empty())
            .then(|| machine.vertex_buffer(&singles))
            .transpose()?;
        let mut draws: Vec<(&'static GraphicsProgram, ConeDraw)> = Vec::new();
        for (program, vertices, ids, count) in &fans {
            draws.push((
                *program,
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
            draws.extend(rect_draws(&mesh, &SITE_EXACT_BATCH, shapes, buffer));
        }
        if let Some(buffer) = &rects {
            let shapes = singles.iter().map(|i| SiteShape::of_kind(i.kind_id[0]));
            draws.extend(rect_draws(&mesh, &SITE_EXACT, shapes, buffer));
        }
        // With nothing drawn the tile keeps the "no site" id.
        let push = ConePush {
            picture_size: [tile_w as f32, tile_h as f32],
            offset: [x0 as f32, y0 as f32],
            vertex_depth_scale: 0.0,
            fragment_depth_scale: depth_scale as f32,
            levels: 1,
            // Polygons are drawn as fans (see above).
            metric: metric.shader_code().unwrap_or((0, 2.0)).into(),
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
                draw_cones(
                    pass,
                    program,
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
            keys: DepthMap {
                key: None,
                scale: depth_scale,
                pixels_per_unit: 1.0,
                offset: least_additive,
            },
            marked: false,
        })?;
    }
    stats.render_ms = ms(started);
    Ok((
        stats,
        DepthMap {
            key: None,
            scale: depth_scale,
            pixels_per_unit: 1.0,
            offset: least_additive,
        },
    ))
}
