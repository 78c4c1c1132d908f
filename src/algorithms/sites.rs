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
//!
//! The file is long because each of the four shapes of site takes its own fans,
//! batches, tile lists and exact rectangles, and they share one driver.

use super::ms;
use std::time::Instant;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::cone::check_fan_size,
    geometry::{
        buckets::{for_ring_cells, group_by_bucket},
        chain::{segment_distance, FanMeshes, MetricFan},
        frame::distance2_to_rect,
        metric::Metric,
        site::{check_general_sites, ArcWedge, Shape, Site},
        surface::{fan_surface, FanSurface},
    },
    machine::{
        Buffer, Clear, ClearColor, DrawParams, Format, GraphicsProgram, Machine, PixelRect,
        RasterState, Target,
    },
};

use super::cones::{
    draw_cones, draw_over_target, ConeDraw, ConePush, SiteBatch, SiteInstance, SiteShape,
    SITE_EXACT, SITE_EXACT_BATCH, SITE_FAN, SITE_FAN_FOLDED, SITE_TILES,
};

use super::envelope::{
    distances_of, drawn_accuracy, hilbert_index, metric_fan, records_image, Accuracy, DepthMap,
    DrawnTile, Speedup, Tiling, Tuning, BATCH, SCREEN_TILE_SIDE, UNIT_SQUARE,
};
use super::voronoi::{VoronoiDiagram, VoronoiOptions, VoronoiStats};

/// The Voronoi diagram of `sites` of any shape and weight (world coordinates):
/// every pixel labelled with a site of smallest weighted distance, and the
/// distance map holding that weighted distance (world units). In fan mode the
/// sites' fan surfaces ([`crate::geometry::surface`]) give a distance diagram
/// within the reported bound. Pictures larger than the device's image size (or
/// than `max_tile`) are drawn tile by tile.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{
///     algorithms::{sites::voronoi_sites, voronoi::VoronoiOptions},
///     geometry::{site::{Shape, Site}, Frame},
/// };
///
/// let road = Site::new(Shape::Segment(DVec2::new(0.0, 10.0), DVec2::new(31.0, 10.0)));
/// let town = Site { multiplicative: 2.0, ..Site::point(DVec2::new(16.0, 2.0)) };
/// let options = VoronoiOptions::exact(Frame::pixels(32, 16)?);
/// let d = pixgeo::with_default_machine(|m| voronoi_sites(m, &[road, town], &options))?;
/// assert_eq!(d.labels[15 * 32], 0); // the bottom-left corner is nearest the road
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn voronoi_sites(
    machine: &Machine,
    sites: &[Site],
    options: &VoronoiOptions,
) -> Result<VoronoiDiagram> {
    if options.window.is_some() {
        return Err(Error::InvalidInput(
            "windows take point sites: compute segments, circles, arcs and weighted sites \
             on the whole picture"
                .into(),
        ));
    }
    // The distance to a curve under a polygon's gauge is curved: chords,
    // however fine, may name the wrong one of two nearly equidistant sites.
    let curved = sites
        .iter()
        .any(|s| matches!(s.shape, Shape::Circle { .. } | Shape::Arc { .. }));
    if curved && matches!(options.metric, Metric::Polygon(_)) && options.accuracy == Accuracy::Exact
    {
        return Err(Error::InvalidInput(
            "circles and arcs under a polygon metric have no exact drawing on a Vulkan device: \
             use the CPU algorithm (--device cpu), which is exact, or fan mode, whose error \
             bound is reported"
                .into(),
        ));
    }
    check_general_sites(sites)?;
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
            .collect();
        let mut d = voronoi_sites(machine, &chosen, options)?;
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
        frame,
        window: PixelRect::sized(frame.width, frame.height),
        labels,
        distances,
        ties: Vec::new(),
        stats,
    })
}

/// The sites that may win some pixel by their additive weights: the site of
/// the smallest additive weight bounds the envelope everywhere by that weight
/// plus its farthest weighted distance from the picture, and a site whose
/// weight alone exceeds the bound wins nowhere.
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
        // `voronoi_sites` refuses them in exact mode).
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
    let window = PixelRect::sized(frame.width, frame.height);
    let tiling = Tiling::new(machine, options.max_tile, window, u32::MAX)?;
    let started = Instant::now();
    let pixels: Vec<Site> = sites
        .iter()
        .map(|s| s.to_pixels(|p| frame.to_pixel(p), frame.scale))
        .collect();
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
            cull(&pixels, frame.width, frame.height, metric, frame.scale)
        }
    };
    let drawn: Vec<f64> = reaches.iter().flatten().map(|(_, r)| *r).collect();
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
                .collect();
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
            vec![
                plain.upload(machine, &SITE_FAN)?,
                folded.upload(machine, &SITE_FAN_FOLDED)?,
            ]
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

/// The diagram of sites (pixels) under L2, L1 or L∞ in exact mode from screen
/// tiles ([`SITE_TILES`]), one pass per shape: each cell of [`CellBounds`]
/// lists the sites whose smallest weighted distance over it is within its
/// bound, by that distance, and each screen tile reads its cell's list. `None`
/// where the lists would be too long.
fn draw_site_tiles(
    machine: &Machine,
    pixels: &[Site],
    options: &VoronoiOptions,
    least_additive: f64,
    started: Instant,
    visit: &mut impl FnMut(&DrawnTile<'_>) -> Result<()>,
) -> Result<Option<(VoronoiStats, DepthMap)>> {
    let frame = options.frame;
    let (width, height) = (frame.width, frame.height);
    // Cells of one screen tile where sites are dense, of 2 x 2 or 4 x 4 where
    // they are sparse: the cells' bounds then cost less to find, and tiles share
    // their cell's list.
    let spacing = (width as f64 * height as f64 / pixels.len() as f64).sqrt();
    let per_cell: u32 = if spacing < 24.0 {
        1
    } else if spacing < 64.0 {
        2
    } else {
        4
    };
    let side = (SCREEN_TILE_SIDE * per_cell) as f64;
    let metric = options.metric;
    let cells = CellBounds::new(pixels, width, height, metric, frame.scale, side);
    // Per site: its cells with its smallest weighted distance there, and the
    // largest shape distance where it may win.
    let owned: Vec<(Vec<(u32, f64)>, f64)> = (0..pixels.len())
        .into_par_iter()
        .map(|k| {
            let mut its = Vec::new();
            let mut far = 0.0f64;
            cells.owned_cells(k, |owned| {
                let (x, y) = owned.cell;
                its.push(((y * cells.across + x) as u32, owned.least));
                far = far.max(owned.distance);
            });
            (its, far)
        })
        .collect();
    let cell_count = cells.across * cells.down;
    let depth_scale = depth_scale_of(cells.reach, least_additive);
    // A pixel more of reach, as the rectangles take.
    let drawn: Vec<f64> = owned
        .iter()
        .filter(|(its, _)| !its.is_empty())
        .map(|(_, far)| far + 1.0)
        .collect();
    let mut stats = VoronoiStats {
        tiles: 1,
        ..site_stats(machine, pixels.len(), &drawn)
    };
    // One pass per shape present: its records. Each site's texels, made once:
    // its shape words, then its weights (the smallest distance and id go with
    // each entry).
    const SHAPES: [SiteShape; 4] = [
        SiteShape::Point,
        SiteShape::Segment,
        SiteShape::Circle,
        SiteShape::Arc,
    ];
    let words: Vec<([[u32; 4]; 2], [u32; 2])> = pixels
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let i = instance(k as u32, s, [0.0; 4], frame.scale, least_additive);
            let bits = |w: &[f32]| [w[0], w[1], w[2], w[3]].map(f32::to_bits);
            (
                [bits(&i.shape[..4]), bits(&i.shape[4..])],
                i.weights.map(f32::to_bits),
            )
        })
        .collect();
    // Entries (smallest distance, site) by shape, then by cell.
    let (start, entries) = group_by_bucket(
        SHAPES.len() * cell_count,
        owned.iter().enumerate().flat_map(|(k, (its, _))| {
            let shape = SHAPES.iter().position(|&s| s == site_shape(&pixels[k]));
            let shape = shape.expect("every shape has a pass");
            its.iter()
                .map(move |&(c, least)| (shape * cell_count + c as usize, (least, k as u32)))
        }),
    );
    let mut passes = Vec::new();
    for (s, shape) in SHAPES.into_iter().enumerate() {
        let (first, last) = (
            start[s * cell_count] as usize,
            start[(s + 1) * cell_count] as usize,
        );
        if first == last {
            continue;
        }
        let words_per_site = if shape == SiteShape::Arc { 3 } else { 2 };
        if (last - first) * words_per_site > (width as usize * height as usize) * 64 {
            return Ok(None);
        }
        let range =
            |c: usize| start[s * cell_count + c] as usize..start[s * cell_count + c + 1] as usize;
        // A header per screen tile: its cell's list.
        let across = width.div_ceil(SCREEN_TILE_SIDE) as usize;
        let screen = across * height.div_ceil(SCREEN_TILE_SIDE) as usize;
        let mut texels = vec![[0u32; 4]; screen + words_per_site * (last - first)];
        let (headers, lists) = texels.split_at_mut(screen);
        let per_cell = per_cell as usize;
        for (t, header) in headers.iter_mut().enumerate() {
            let cell = (t / across / per_cell) * cells.across + t % across / per_cell;
            let r = range(cell);
            let at = screen + words_per_site * (r.start - first);
            *header = [at as u32, r.len() as u32, 0, 0];
        }
        // Each cell's sites by their smallest distance there (ties by id).
        let mut rest = lists;
        let mut cell_lists = Vec::with_capacity(cell_count);
        for c in 0..cell_count {
            let (list, tail) = rest.split_at_mut(words_per_site * range(c).len());
            cell_lists.push((c, list));
            rest = tail;
        }
        cell_lists
            .into_par_iter()
            .for_each_init(Vec::new, |sorted, (c, list)| {
                sorted.clear();
                sorted.extend_from_slice(&entries[range(c)]);
                sorted
                    .sort_unstable_by(|a: &(f64, u32), b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                for (&(least, k), texels) in
                    sorted.iter().zip(list.chunks_exact_mut(words_per_site))
                {
                    let (shape_words, weights) = &words[k as usize];
                    // The device's distances round: a margin keeps a site that may
                    // tie in the list.
                    let least = ((least - least_additive) * (1.0 - 1e-5) - 1e-6) as f32;
                    texels[..words_per_site - 1]
                        .copy_from_slice(&shape_words[..words_per_site - 1]);
                    texels[words_per_site - 1] = [weights[0], weights[1], least.to_bits(), k];
                }
            });
        match records_image(machine, texels)? {
            Some(records) => passes.push((shape, records)),
            None => return Ok(None),
        }
    }
    stats.passes = passes.len().max(1) as u32;
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let ids = machine.image(Format::R32Uint, width, height)?;
    let depth = machine.image(Format::DepthStencil, width, height)?;
    let push = ConePush {
        picture_size: [width as f32, height as f32],
        offset: [0.0, 0.0],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: depth_scale as f32,
        levels: 1,
        metric: metric.shader_code().unwrap_or((0, 2.0)).into(),
    };
    let target = Target {
        color: Some(&ids),
        depth_stencil: Some(&depth),
    };
    let clear = Clear {
        color: Some(ClearColor::Uint([u32::MAX; 4])),
        depth: Some(1.0),
        stencil: Some(0),
    };
    if passes.is_empty() {
        machine.run(|pass| {
            pass.begin(target, clear)?;
            pass.end()
        })?;
    }
    for (k, (shape, (upload, records))) in passes.iter().enumerate() {
        machine.run(|pass| {
            pass.upload_for_fragments(upload, records)?;
            // Later shapes draw over the earlier ones' envelope.
            pass.bind_fragment_buffers(&[], Some(records))?;
            pass.begin(target, if k == 0 { clear } else { Clear::default() })?;
            draw_over_target(
                pass,
                &SITE_TILES[*shape as usize],
                &RasterState::lower_envelope(),
                &DrawParams::default(),
                &push,
            )?;
            pass.end()
        })?;
    }
    let keys = DepthMap {
        key: None,
        scale: depth_scale,
        pixels_per_unit: 1.0,
        offset: least_additive,
    };
    visit(&DrawnTile {
        ids: &ids,
        depth: &depth,
        x0: 0,
        y0: 0,
        inner: PixelRect {
            x: 0,
            y: 0,
            width,
            height,
        },
        keys,
    })?;
    stats.render_ms = ms(started);
    Ok(Some((stats, keys)))
}

/// A diagram's statistics before drawing: `reaches` are the largest shape
/// distances (pixels) of the sites drawn.
fn site_stats(machine: &Machine, sites: usize, reaches: &[f64]) -> VoronoiStats {
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites,
        cones: reaches.len(),
        passes: 1,
        ..Default::default()
    };
    if !reaches.is_empty() {
        stats.radius_min = reaches.iter().copied().fold(f64::INFINITY, f64::min);
        stats.radius_max = reaches.iter().copied().fold(0.0, f64::max);
        stats.radius_mean = reaches.iter().sum::<f64>() / reaches.len() as f64;
    }
    stats
}

/// The power of two that maps weighted distances from the smallest additive
/// weight up to the envelope's `reach` into [0, 1) as depths.
fn depth_scale_of(reach: f64, least_additive: f64) -> f64 {
    let span = (reach - least_additive).max(1e-30) * 1.001;
    span.log2().ceil().exp2().recip()
}

/// The shape a site is drawn as.
fn site_shape(site: &Site) -> SiteShape {
    match site.shape {
        Shape::Point(_) => SiteShape::Point,
        Shape::Segment(..) => SiteShape::Segment,
        Shape::Circle { .. } => SiteShape::Circle,
        Shape::Arc { .. } => SiteShape::Arc,
    }
}

/// Fan vertices of N words (see [`SITE_FAN`] and
/// [`SITE_FAN_FOLDED`]) with their sites' ids.
#[derive(Default)]
struct FanBuffers<const N: usize> {
    vertices: Vec<[f32; N]>,
    ids: Vec<u32>,
}

impl<const N: usize> FanBuffers<N>
where
    [f32; N]: bytemuck::Pod,
{
    fn push(&mut self, vertex: [f32; N], id: u32) {
        self.vertices.push(vertex);
        self.ids.push(id);
    }

    fn append(&mut self, mut other: Self) {
        self.vertices.append(&mut other.vertices);
        self.ids.append(&mut other.ids);
    }

    /// The two vertex buffers for `program` and the vertices' count.
    fn upload(
        mut self,
        machine: &Machine,
        program: &'static GraphicsProgram,
    ) -> Result<(&'static GraphicsProgram, Buffer, Buffer, u32)> {
        let count = self.vertices.len() as u32;
        // Vulkan buffers cannot be empty.
        self.push([0.0; N], 0);
        Ok((
            program,
            machine.vertex_buffer(&self.vertices)?,
            machine.vertex_buffer(&self.ids)?,
            count,
        ))
    }
}

/// What one diagram draws.
enum SiteDraw {
    /// Batches of small sites of the shapes [`batched`] under the metric, and
    /// one rectangle per other site, both sorted by shape.
    Exact {
        batches: Vec<(SiteShape, SiteBatch)>,
        singles: Vec<SiteInstance>,
    },
    /// Each site's fan surface.
    Fan(Vec<(u32, FanSurface)>),
}

/// One draw of `program` per run of a shape among the `instances` (rectangles
/// of the unit square `mesh`), whose shapes in order are `shapes`.
fn rect_draws<'a>(
    mesh: &'a Buffer,
    programs: &'static [GraphicsProgram; 4],
    shapes: impl Iterator<Item = SiteShape>,
    instances: &'a Buffer,
) -> Vec<(&'static GraphicsProgram, ConeDraw<'a>)> {
    let mut draws: Vec<(&'static GraphicsProgram, ConeDraw<'a>)> = Vec::new();
    for (k, shape) in shapes.enumerate() {
        let program = &programs[shape as usize];
        match draws.last_mut() {
            Some((last, draw)) if std::ptr::eq(*last, program) => draw.instance_count += 1,
            _ => draws.push((
                program,
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
/// with small rectangles, and the rest, drawn one by one. A batch's rectangle
/// is the bounding box of its sites', so one large site would widen it for all
/// eight: a batched site's rectangle is no larger than a batched cone's square.
fn batch_sites(
    instances: Vec<SiteInstance>,
    metric: Metric,
    tuning: &Tuning,
) -> (Vec<(SiteShape, SiteBatch)>, Vec<SiteInstance>) {
    let side_limit = (2.0 * tuning.batch_radius) as f32;
    let (mut batched, singles): (Vec<SiteInstance>, Vec<SiteInstance>) =
        instances.into_iter().partition(|i| {
            batched(metric, SiteShape::of_kind(i.kind_id[0]))
                && i.rect[2] - i.rect[0] <= side_limit
                && i.rect[3] - i.rect[1] <= side_limit
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

/// Side of the site cull's blocks, in cells (see `cull`): blocks of 4 shorten
/// the site pass most for weighted points, whose reach varies with their
/// weights (docs/tuning.md, "Measured choices").
const CULL_BLOCK: usize = 4;

/// Each site's [`Reach`], `None` where it wins nowhere, and an upper bound on the
/// envelope over the picture.
///
/// Cells of about half the sites' spacing ([`CellBounds`]); a site's rectangle
/// holds the cells it may own a pixel of, each cut to where the site can reach.
fn cull(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> (Vec<Option<Reach>>, f64) {
    let spacing = (width as f64 * height as f64 / sites.len() as f64).sqrt();
    // Cells of half the spacing bound faster than a third, with rectangles
    // only a little larger. Few sites have few cells to walk: down to 16
    // pixels, but no less than an eighth of the spacing (a cell's walk to its
    // nearest site stays short), keeps their rectangles near their regions.
    // The measurements are in docs/tuning.md, "Measured choices".
    let side = (spacing / 2.0)
        .min(16.0)
        .max(spacing / 8.0)
        .clamp(3.0, 64.0)
        .floor();
    let cells = CellBounds::new(sites, width, height, metric, scale, side);
    let reaches = (0..sites.len())
        .into_par_iter()
        .map(|k| {
            let mut rect: Option<(DVec2, DVec2)> = None;
            let mut far = 0.0f64;
            cells.owned_cells(k, |owned| {
                far = far.max(owned.distance);
                let (p, q) = owned.rect;
                rect = Some(match rect {
                    None => (p, q),
                    Some((rp, rq)) => (rp.min(p), rq.max(q)),
                });
            });
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
    (reaches, cells.reach)
}

/// The picture in square cells, each with an upper bound on the weighted
/// envelope over it: the smallest largest-distance of the sites binned near it
/// (any subset of the sites bounds the envelope from above).
struct CellBounds<'a> {
    sites: &'a [Site],
    metric: Metric,
    scale: f64,
    /// Cell (i, j) holds the pixel centres [i side, (i + 1) side) (clipped).
    side: f64,
    across: usize,
    down: usize,
    corner: DVec2,
    /// Arcs are measured (in L2, see `spread`) many times each: their wedges
    /// once.
    wedges: Vec<Option<ArcWedge>>,
    upper: Vec<f64>,
    /// The largest bound in each block of CULL_BLOCK x CULL_BLOCK cells: a site
    /// skips a block beyond its reach there without visiting the cells.
    block_bounds: Vec<f64>,
    /// The largest bound of all.
    reach: f64,
}

/// A cell a site may own a pixel of (see [`CellBounds::owned_cells`]).
struct OwnedCell {
    /// Column and row.
    cell: (usize, usize),
    /// The site's smallest weighted distance there.
    least: f64,
    /// Its largest shape distance (pixels) where it may win there.
    distance: f64,
    /// The cell's pixel centres cut to where the site can reach.
    rect: (DVec2, DVec2),
}

impl<'a> CellBounds<'a> {
    fn new(
        sites: &'a [Site],
        width: u32,
        height: u32,
        metric: Metric,
        scale: f64,
        side: f64,
    ) -> Self {
        let (across, down) = (
            (width as f64 / side).ceil() as usize,
            (height as f64 / side).ceil() as usize,
        );
        let wedges = sites
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
        let mut cells = Self {
            sites,
            metric,
            scale,
            side,
            across,
            down,
            corner: DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
            wedges,
            upper: Vec::new(),
            block_bounds: Vec::new(),
            reach: 0.0,
        };
        // Sites binned by their box's centre, in bins of about their spacing
        // (no smaller than the cells): a cell's search then visits few empty
        // bins.
        let spacing = (width as f64 * height as f64 / sites.len() as f64).sqrt();
        let bin_side = side.max(spacing);
        let (bins_across, bins_down) = (
            (width as f64 / bin_side).ceil() as usize,
            (height as f64 / bin_side).ceil() as usize,
        );
        let bin_of = |v: f64, n: usize| ((v / bin_side).floor().max(0.0) as usize).min(n - 1);
        let (bin_start, binned) = group_by_bucket(
            bins_across * bins_down,
            sites.iter().enumerate().map(|(k, s)| {
                let (lo, hi) = s.bounds();
                let c = 0.5 * (lo + hi);
                (
                    bin_of(c.y, bins_down) * bins_across + bin_of(c.x, bins_across),
                    k as u32,
                )
            }),
        );
        let bin = |x: usize, y: usize| {
            let b = y * bins_across + x;
            &binned[bin_start[b] as usize..bin_start[b + 1] as usize]
        };
        let (a, _) = metric.euclidean_bounds();
        // Upper bounds from the sites of the nearest non-empty rings of bins,
        // row by row: each cell starts from its left neighbour's best site,
        // whose bound is usually near its own, so that the gap test skips most
        // of the others.
        let cells_ref = &cells;
        let mut upper = vec![0.0; across * down];
        upper
            .par_chunks_mut(across)
            .enumerate()
            .for_each(|(j, row)| {
                let mut hint: Option<usize> = None;
                for (i, bound) in row.iter_mut().enumerate() {
                    let (lo, hi) = cells_ref.bounds_of(i, j);
                    let block = [
                        bin_of(lo.x, bins_across),
                        bin_of(lo.y, bins_down),
                        bin_of(hi.x, bins_across),
                        bin_of(hi.y, bins_down),
                    ]
                    .map(|b| b as isize);
                    let centre = 0.5 * (lo + hi);
                    let (mut best, mut best_site) = match hint {
                        Some(k) => (cells_ref.range(k, i, j, false).1, k),
                        None => (f64::INFINITY, 0),
                    };
                    let mut found = false;
                    for ring in 0..bins_across.max(bins_down) {
                        for_ring_cells((bins_across, bins_down), block, ring, |x, y| {
                            for &k in bin(x, y) {
                                found = true;
                                // A site whose box is already too far cannot lower the
                                // bound: its largest distance exceeds a times that gap.
                                let s = &sites[k as usize];
                                let (blo, bhi) = s.bounds();
                                let gap = distance2_to_rect(centre, blo, bhi).sqrt();
                                if cells_ref.weighted(s, a * gap) < best {
                                    let (_, largest, _) = cells_ref.range(k as usize, i, j, false);
                                    if largest < best {
                                        (best, best_site) = (largest, k as usize);
                                    }
                                }
                            }
                        });
                        // One more ring after the first find tightens the bound
                        // cheaply (the hint is no find: it may lie far off).
                        if found && ring >= 1 {
                            break;
                        }
                    }
                    hint = best.is_finite().then_some(best_site);
                    *bound = best;
                }
            });
        let blocks_across = across.div_ceil(CULL_BLOCK);
        let mut block_bounds = vec![f64::NEG_INFINITY; blocks_across * down.div_ceil(CULL_BLOCK)];
        for (c, &bound) in upper.iter().enumerate() {
            let b = c / across / CULL_BLOCK * blocks_across + c % across / CULL_BLOCK;
            block_bounds[b] = block_bounds[b].max(bound);
        }
        cells.reach = upper.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        cells.upper = upper;
        cells.block_bounds = block_bounds;
        cells
    }

    fn cell_of(&self, v: f64, n: usize) -> usize {
        ((v / self.side).floor().max(0.0) as usize).min(n - 1)
    }

    /// Cell (i, j)'s first and last pixel centres.
    fn bounds_of(&self, i: usize, j: usize) -> (DVec2, DVec2) {
        let lo = DVec2::new(i as f64 * self.side, j as f64 * self.side);
        (lo, (lo + self.side - 1.0).min(self.corner))
    }

    fn weighted(&self, s: &Site, d: f64) -> f64 {
        d / (self.scale * s.multiplicative) + s.additive
    }

    /// Site k's smallest and largest weighted distance over cell (i, j), and
    /// its largest shape distance there; exact where `spread` can be.
    fn range(&self, k: usize, i: usize, j: usize, exact: bool) -> (f64, f64, f64) {
        let (lo, hi) = self.bounds_of(i, j);
        let s = &self.sites[k];
        // Only arcs read their wedge (the others' would cost a cache miss).
        let wedge = match s.shape {
            Shape::Arc { .. } => self.wedges[k].as_ref(),
            _ => None,
        };
        let (dlo, dhi) = spread(
            s,
            wedge,
            self.metric,
            0.5 * (lo + hi),
            0.5 * (hi - lo),
            exact,
        );
        (self.weighted(s, dlo), self.weighted(s, dhi), dhi)
    }

    /// Visits each cell that site k may own a pixel of: the cells the largest
    /// upper bound reaches from its box, skipping blocks of cells whose largest
    /// bound it cannot reach, where its smallest distance can reach the cell's
    /// bound.
    fn owned_cells(&self, k: usize, mut visit: impl FnMut(OwnedCell)) {
        let s = &self.sites[k];
        let (a, _) = self.metric.euclidean_bounds();
        let (blo, bhi) = s.bounds();
        let refine = self.metric == Metric::L2 && matches!(s.shape, Shape::Segment(..));
        // Where the cell's bound is its weighted distance, the shape distance.
        let limit_of = |bound: f64| (bound - s.additive) * self.scale * s.multiplicative;
        // No cell's bound is above the largest: the site owns no pixel
        // farther than this (Euclidean) from its box.
        let widest = limit_of(self.reach) / a * (1.0 + 1e-9);
        if widest.is_nan() || widest < 0.0 {
            return;
        }
        // Whether the pixel centres [p, q] lie beyond a shape distance of
        // `limit` from the site: a Euclidean 1 / a times that from its box.
        let beyond = |limit: f64, p: DVec2, q: DVec2| {
            let gap = (p - bhi).max(blo - q).max(DVec2::ZERO);
            limit < 0.0 || a * a * gap.length_squared() > limit * limit * (1.0 + 1e-9)
        };
        let mut cell = |x: usize, y: usize| {
            let bound = self.upper[y * self.across + x];
            let limit = limit_of(bound);
            // Most cells fail on the gap between them and the site's box.
            let (p, q) = self.bounds_of(x, y);
            if beyond(limit, p, q) {
                return;
            }
            // Where the exact range costs more, the quick one first: most
            // cells it rules out.
            let quick = self.range(k, x, y, false);
            let (least, _, d) = match refine {
                true if quick.0 > bound => return,
                true => self.range(k, x, y, true),
                false => quick,
            };
            if least <= bound {
                // The site owns a pixel of the cell only where its weighted
                // distance is at most the cell's bound: within that shape
                // distance of the shape, and a Euclidean 1 / a times that of
                // its box.
                let distance = d.min(limit);
                let grow = distance / a * (1.0 + 1e-9);
                let rect = (p.max(blo - grow), q.min(bhi + grow));
                if rect.0.cmple(rect.1).all() {
                    visit(OwnedCell {
                        cell: (x, y),
                        least,
                        distance,
                        rect,
                    });
                }
            }
        };
        let (x0, x1) = (
            self.cell_of(blo.x - widest, self.across),
            self.cell_of(bhi.x + widest, self.across),
        );
        let (y0, y1) = (
            self.cell_of(blo.y - widest, self.down),
            self.cell_of(bhi.y + widest, self.down),
        );
        let blocks_across = self.across.div_ceil(CULL_BLOCK);
        for j in y0 / CULL_BLOCK..=y1 / CULL_BLOCK {
            for i in x0 / CULL_BLOCK..=x1 / CULL_BLOCK {
                let (columns, rows) = (
                    CULL_BLOCK * i..(CULL_BLOCK * (i + 1)).min(self.across),
                    CULL_BLOCK * j..(CULL_BLOCK * (j + 1)).min(self.down),
                );
                let (p, _) = self.bounds_of(columns.start, rows.start);
                let (_, q) = self.bounds_of(columns.end - 1, rows.end - 1);
                if beyond(limit_of(self.block_bounds[j * blocks_across + i]), p, q) {
                    continue;
                }
                for y in rows.start.max(y0)..rows.end.min(y1 + 1) {
                    for x in columns.start.max(x0)..columns.end.min(x1 + 1) {
                        cell(x, y);
                    }
                }
            }
        }
    }
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

/// The range of the Euclidean distance to the segment `a b` over the box
/// `[lo, hi]`: the distance is convex, so largest at a corner; the smallest is 0
/// where the segment meets the box, else at an end of the segment or a corner
/// of the box (the nearest points of two convex polygons include a vertex).
fn segment_spread(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> (f64, f64) {
    let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
    let to_corners = corners.map(|c| segment_distance(c, a, b));
    let largest = to_corners.into_iter().fold(0.0, f64::max);
    // Liang-Barsky: the part of the segment inside the box.
    let e = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (q, p) in [(a - lo, -e), (hi - a, e)] {
        for axis in 0..2 {
            if p[axis] == 0.0 {
                if q[axis] < 0.0 {
                    t0 = 2.0;
                }
            } else {
                let t = q[axis] / p[axis];
                if p[axis] < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    if t0 <= t1 {
        return widened(0.0, largest);
    }
    let to_box = |p: DVec2| (p - p.clamp(lo, hi)).length();
    let least = to_corners
        .into_iter()
        .chain([to_box(a), to_box(b)])
        .fold(f64::INFINITY, f64::min);
    widened(least, largest)
}

/// A range widened past the rounding of the distances that found it.
fn widened(least: f64, largest: f64) -> (f64, f64) {
    (least * (1.0 - 1e-12), largest * (1.0 + 1e-12))
}

/// The range of the site's shape distance over a box of half-extents `half`
/// around `centre`. A point's is exact under the L_p norms, which grow with
/// each coordinate's size: the box's nearest and farthest offsets from it.
/// Euclidean circles' is exact, and segments' where `exact` (four distances
/// and a clip instead of one).
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
    exact: bool,
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
        let (lo, hi) = spread(site, wedge, Metric::L2, centre, half, exact);
        return (a * lo, b * hi);
    }
    if metric == Metric::L2 {
        match site.shape {
            Shape::Segment(a, b) if exact => {
                return segment_spread(a, b, centre - half, centre + half)
            }
            Shape::Circle { center, radius } => {
                // The distance to the centre spans [near, far] over the box.
                let offset = (center - centre).abs();
                let near = (offset - half).max(DVec2::ZERO).length();
                let far = (offset + half).length();
                let (a, b) = ((near - radius).abs(), (far - radius).abs());
                let least = if near <= radius && radius <= far {
                    0.0
                } else {
                    a.min(b)
                };
                return widened(least, a.max(b));
            }
            _ => {}
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact ranges of Euclidean segments and circles over a box hold every
    /// distance from a fine grid of its points, and reach within a grid step of
    /// the grid's extremes; the quick ranges hold them too.
    #[test]
    fn ranges_over_a_box_hold_its_distances() {
        let frame = crate::geometry::Frame::pixels(64, 64).unwrap();
        let ends = frame.random_points(120, 11);
        let (centre, half) = (DVec2::new(30.0, 33.0), DVec2::new(3.5, 3.5));
        let mut sites: Vec<Site> = ends
            .chunks_exact(2)
            .map(|e| Site::new(Shape::Segment(e[0], e[1])))
            .collect();
        // Through the box, along its side, from inside, and a point-like one.
        let segment = |a: [f64; 2], b: [f64; 2]| Site::new(Shape::Segment(a.into(), b.into()));
        sites.extend([
            segment([0.0, 33.0], [60.0, 33.0]),
            segment([26.5, 0.0], [26.5, 60.0]),
            segment([31.0, 34.0], [50.0, 50.0]),
            segment([10.0, 10.0], [10.0, 10.0]),
        ]);
        sites.extend(ends.iter().take(20).enumerate().map(|(i, &c)| {
            Site::new(Shape::Circle {
                center: c,
                radius: 2.0 * i as f64,
            })
        }));
        let steps = 56;
        for site in &sites {
            let (mut near, mut far) = (f64::INFINITY, 0.0f64);
            for i in 0..=steps {
                for j in 0..=steps {
                    let t = DVec2::new(i as f64, j as f64) / steps as f64;
                    let p = centre - half + 2.0 * half * t;
                    let d = site.distance_to_shape(Metric::L2, p);
                    near = near.min(d);
                    far = far.max(d);
                }
            }
            let step = 2.0 * half.length() / steps as f64;
            for exact in [true, false] {
                let (lo, hi) = spread(site, None, Metric::L2, centre, half, exact);
                assert!(
                    lo <= near && hi >= far,
                    "{site:?}: [{lo}, {hi}] against [{near}, {far}]"
                );
                if exact {
                    assert!(near - lo <= step && hi - far <= step, "{site:?}: not tight");
                }
            }
        }
    }
}
