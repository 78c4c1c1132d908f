//! The k nearest by screen tiles: each tile's fragments keep the k lowest
//! layers of the tile's cones (`glsl/cone_tiles.frag`).

use super::*;
use crate::memory::Gather;

/// Most levels a tile fragment keeps (`glsl/cone_tiles.frag`: MAX_LEVELS).
pub(super) const TILE_LEVELS: u32 = 32;

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
pub(super) fn k_nearest_tiled(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
    started: Instant,
) -> Result<KNearest> {
    let (frame, k) = (options.frame, options.k);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).gather("pixels")?;
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
        bin_to_tiles(&pixels, &frame, radii)?
    };
    let cones = drawn_cones(&pixels, &tiles.radii, &frame);
    let mut stats = cone_stats(machine, sites.len(), options.k, cones);
    let binned = &tiles.lists;
    // Tile records (six words each) for the vertex shader; the cones (one texel
    // each) for the fragment shader, rows of RECORD_ROW texels. Every tile is
    // drawn, those without cones too: its fragments write "no site", so the keys
    // need no filling first.
    let mut words: Vec<u32> = crate::memory::room(6 * binned.len(), "tile words")?;
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
        return Err(Error::out_of_range(format!(
            "the cones of {k} levels meet screen tiles {next} times, more than this device \
             holds ({}); use the speedup, fewer levels or a smaller picture",
            most * RECORD_ROW
        )));
    }
    let mut texels: Vec<[u32; 4]> = crate::memory::room(rows * RECORD_ROW, "tile records")?;
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
    read_labels(&labels, &pixels, options, stats)
}

/// Site indices per screen tile for cones of the given radii: a cone goes to
/// every tile its disc meets, nearest to the tile's centre first.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn bin_to_tiles(pixels: &[DVec2], frame: &Frame, radii: Vec<f64>) -> Result<radius::TileLists> {
    let mut tiles = radius::TileLists {
        across: frame.width.div_ceil(TILE_SIDE) as usize,
        side: TILE_SIDE,
        ..Default::default()
    };
    let down = frame.height.div_ceil(TILE_SIDE) as usize;
    let mut binned: Vec<Vec<(f64, u32)>> =
        crate::memory::filled(tiles.across * down, Vec::new(), "screen tiles' lists")?;
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
    Ok(tiles)
}
