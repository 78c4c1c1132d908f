//! Site tiles: screen tiles where sites are dense list the sites that may win
//! in them, and one triangle takes each pixel's lowest distance from its
//! tile's list (`glsl/site_tiles.frag`).

use super::*;
use crate::memory::Gather;

/// The diagram of sites (pixels) under L2, L1 or L∞ in exact mode from screen
/// tiles ([`SITE_TILES`]), one pass per shape: each cell of [`CellBounds`]
/// lists the sites whose smallest weighted distance over it is within its
/// bound, by that distance, and each screen tile reads its cell's list. `None`
/// where the lists would be too long.
pub(super) fn draw_site_tiles(
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
    let cells = CellBounds::new(pixels, width, height, metric, frame.scale, side)?;
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
        .gather("drawn")?;
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
        .gather("bits")?;
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
        let mut texels = crate::memory::filled(
            screen + words_per_site * (last - first),
            [0u32; 4],
            "texels",
        )?;
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
        let mut cell_lists = crate::memory::room(cell_count, "cells' lists")?;
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
        marked: false,
    })?;
    stats.render_ms = ms(started);
    Ok(Some((stats, keys)))
}
