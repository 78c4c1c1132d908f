//! The digital Voronoi diagram by flooding (Cao, Edelsbrunner and Tan 2015)
//! on the machine.
//!
//! Flooding colours each pixel in the order of the paper's total order on
//! (pixel, seed) pairs, growing every region from its seed. Its Bulk Lemma
//! says each flooded region holds the bulk of the Euclidean region E_i (the
//! part connected to the seed), so the two colourings differ only on E's
//! debris. pixgeo therefore:
//!
//! 1. computes the Euclidean colouring exactly in two compute passes, the
//!    nearest seed per pixel, ties broken by the seeds' coordinates as the
//!    total order breaks them;
//! 2. finds the debris: a debris component's nearest pixel to its seed has no
//!    neighbour of its colour nearer to the seed, which no bulk pixel but the
//!    seed lacks (the lemma's proof), so the components of those "roots" are
//!    the debris;
//! 3. floods the debris alone, in the total order, from the bulk pixels around
//!    it, which flooding colours as E does and in the same order.
//!
//! The result is the reference flooding pixel for pixel. The roots are found
//! per pixel by a third compute pass. Debris needs a sharp corner of a
//! Euclidean region and is rare (none in 200 random sets of 60 seeds on 64 x
//! 48 pixels), so its components are gathered and flooded on the host, over
//! the colouring read back.

use super::ms;
use crate::memory::Gather;
use rayon::prelude::*;
use std::{cmp::Reverse, collections::BinaryHeap, time::Instant};

use glam::DVec2;

use crate::{
    error::{Error, Result},
    geometry::seed::{check_seeds, neighbours, priority, Priority, Seed, NONE},
    geometry::Frame,
    machine::{shaders, Buffer, ComputeProgram, Extent, Image, Machine},
};

/// The exact Euclidean colouring of the seed map in buffer 0 into buffer 1
/// (both twice the pixels; push `[width, height, phase, scale]`, one
/// invocation per column in phase 0, per row in phase 1, per strip of 64 rows
/// of a column in phases 2 and 3 (a grid of columns by strips): debris roots,
/// or scaled distances).
static EUCLIDEAN_COLOURING: ComputeProgram = ComputeProgram::new(
    "EuclideanColouring",
    shaders::EUCLIDEAN_COMP,
    std::mem::size_of::<[u32; 4]>(),
    &[TWICE_THE_PIXELS, TWICE_THE_PIXELS],
);

const PIXELS: Extent = Extent::Push(|p| 4 * p[0] as u64 * p[1] as u64);
const TWICE_THE_PIXELS: Extent = Extent::Push(|p| 8 * p[0] as u64 * p[1] as u64);

/// One pass of jump flooding from buffer 0 into buffer 1 (push `[width,
/// height, step, first pixel]`, one invocation per pixel).
static JUMP_FLOOD: ComputeProgram = ComputeProgram::new(
    "JumpFlood",
    shaders::JUMP_FLOOD_COMP,
    std::mem::size_of::<[u32; 4]>(),
    &[PIXELS, PIXELS],
);

/// The dual triangles of a colouring in buffer 0, appended to buffer 1 (push
/// `[width, height, capacity]`, one invocation per strip of 64 pixel corners
/// of a column, a grid of (width + 1) columns by strips).
static DUALIZE: ComputeProgram = ComputeProgram::new(
    "Dualize",
    shaders::DUALIZE_COMP,
    std::mem::size_of::<[u32; 3]>(),
    // The colouring; the count, then three words per triangle.
    &[PIXELS, Extent::Push(|p| 4 * (1 + 3 * p[2] as u64))],
);

/// How the flooding went.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FloodingStats {
    /// Milliseconds: the Euclidean colouring and its debris roots on the
    /// device, gathering the debris, flooding it.
    pub colour_ms: f64,
    pub debris_ms: f64,
    pub repair_ms: f64,
    /// Debris components and pixels of the Euclidean colouring.
    pub components: usize,
    pub debris: usize,
    /// Debris pixels that flooding gave another colour.
    pub recoloured: usize,
}

/// A colouring of a `width` x `height` texture, row-major.
#[derive(Clone, Debug)]
pub struct Flooding {
    pub width: u32,
    pub height: u32,
    /// The seed index per pixel.
    pub labels: Vec<u32>,
    pub stats: FloodingStats,
}

/// The longest texture side the Euclidean colouring takes.
pub const MAX_SIDE: u32 = 16_000;

/// The seeds of point `sites` on `frame`'s pixels: the pixel each lies in. A
/// site outside the picture, or two in one pixel, is refused, since flooding
/// grows one region from each seed pixel.
pub fn seeds_of(frame: &Frame, sites: &[DVec2]) -> Result<Vec<Seed>> {
    let mut seen = std::collections::HashMap::new();
    let mut seeds = crate::memory::room(sites.len(), "seeds")?;
    for (i, p) in sites.iter().enumerate() {
        let c = frame.to_pixel(*p).round();
        if !(c.x >= 0.0 && c.y >= 0.0 && c.x < frame.width as f64 && c.y < frame.height as f64) {
            return Err(Error::out_of_range(format!(
                "site {i} at {p} lies outside the picture; flooding starts from the sites' pixels"
            )));
        }
        let seed = [c.x as i32, c.y as i32];
        if let Some(j) = seen.insert(seed, i) {
            return Err(Error::out_of_range(format!(
                "sites {j} and {i} fall in pixel {seed:?}; flooding needs one site per pixel \
                 (use a larger picture)"
            )));
        }
        seeds.push(seed);
    }
    Ok(seeds)
}

/// The Euclidean colouring of `seeds` on the device, ties broken by the
/// total order: the nearest seed, then the smallest (x, y). Two compute
/// passes (`glsl/euclidean.comp`): the nearest seed of every column, then the
/// lower envelope of the columns' parabolas along every row, in integers.
pub fn euclidean_colouring(
    machine: &Machine,
    width: u32,
    height: u32,
    seeds: &[Seed],
) -> Result<Vec<u32>> {
    Ok(colouring_and_roots(machine, width, height, seeds)?.0)
}

/// The Euclidean colouring and, from a third pass, the roots of its debris
/// (pixel indices in order).
fn colouring_and_roots(
    machine: &Machine,
    width: u32,
    height: u32,
    seeds: &[Seed],
) -> Result<(Vec<u32>, Vec<usize>)> {
    let pixels = width as usize * height as usize;
    let output = colouring(machine, width, height, seeds, PixelPhase::Roots)?;
    let words = output.read::<u32>(2 * pixels);
    let roots = (0..pixels)
        .filter(|&k| words[pixels + k] == 1)
        .gather("roots")?;
    let mut labels = words;
    labels.truncate(pixels);
    Ok((labels, roots))
}

/// Writes into `depth` (a whole depth image) the squared distance of every pixel
/// to its nearest seed (distinct pixels of the image) plus one, times `scale`,
/// which must keep every value in [0, 1]: a distance picture above depth 0 (so
/// that a mask at 0 stays below it) in one submission, by the
/// colouring's passes and a fourth that turns labels into distances, copied
/// into the depth buffer for the graphics passes that follow.
pub(crate) fn euclidean_depth(
    machine: &Machine,
    seeds: &[Seed],
    depth: &Image,
    scale: f32,
) -> Result<()> {
    let (w, h) = (depth.width(), depth.height());
    colouring(machine, w, h, seeds, PixelPhase::Depth { depth, scale })?;
    Ok(())
}

/// What the colouring's per-pixel pass does after the two colouring passes.
enum PixelPhase<'a> {
    /// Marks the debris roots in the output's second half.
    Roots,
    /// Writes scaled squared distances there and copies them into `depth`.
    Depth { depth: &'a Image, scale: f32 },
}

/// The colouring's passes on the device (the output buffer: labels, then the
/// per-pixel pass's words).
fn colouring(
    machine: &Machine,
    width: u32,
    height: u32,
    seeds: &[Seed],
    then: PixelPhase<'_>,
) -> Result<Buffer> {
    check_seeds(width, height, seeds)?;
    // Squares of coordinates must fit 32 bits, and a row's invocation loops
    // at most 4 x width times (lavapipe stops a shader's loops at 65535).
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(Error::out_of_range(format!(
            "the Euclidean colouring takes sides up to {MAX_SIDE}: {width}x{height} is larger"
        )));
    }
    let pixels = width as usize * height as usize;
    // The seed map, room for the column pass, the seeds' packed positions.
    let mut input = crate::memory::filled(2 * pixels + seeds.len(), NONE, "flooding's input")?;
    for (i, s) in seeds.iter().enumerate() {
        input[s[1] as usize * width as usize + s[0] as usize] = i as u32;
        input[2 * pixels + i] = s[0] as u32 | (s[1] as u32) << 16;
    }
    let mut seed_buffer = machine.storage_buffer((input.len() * 4) as u64)?;
    seed_buffer.write(&input);
    let output = machine.storage_buffer((2 * pixels * 4) as u64)?;
    let (phase, scale) = match then {
        PixelPhase::Roots => (2, 0.0f32),
        PixelPhase::Depth { scale, .. } => (3, scale),
    };
    machine.run(|pass| {
        let kernel = &EUCLIDEAN_COLOURING;
        let buffers = [&seed_buffer, &output];
        let push = |phase: u32| [width, height, phase, scale.to_bits()];
        pass.dispatch(kernel, &buffers, width, bytemuck::bytes_of(&push(0)))?;
        pass.dispatch(kernel, &buffers, height, bytemuck::bytes_of(&push(1)))?;
        let grid = (width, height.div_ceil(64));
        pass.dispatch_grid(kernel, &buffers, grid, bytemuck::bytes_of(&push(phase)))?;
        if let PixelPhase::Depth { depth, .. } = then {
            pass.copy_depth_from_buffer(&output, 4 * pixels as u64, depth)?;
        }
        Ok(())
    })?;
    Ok(output)
}

/// The flooded colouring of `seeds` (distinct pixels of the texture).
///
/// ```
/// use pixgeo::algorithms::flooding::flood;
///
/// let seeds = [[2, 2], [12, 3], [7, 9]];
/// let f = pixgeo::with_default_machine(|m| flood(m, 16, 12, &seeds))?;
/// assert_eq!(f.labels[9 * 16 + 7], 2); // each seed's pixel is its own
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn flood(machine: &Machine, width: u32, height: u32, seeds: &[Seed]) -> Result<Flooding> {
    let mut stats = FloodingStats::default();
    let started = Instant::now();
    let (mut labels, roots) = colouring_and_roots(machine, width, height, seeds)?;
    stats.colour_ms = ms(started);

    let started = Instant::now();
    let w = width as i32;
    let at = |p: [i32; 2]| (p[1] * w + p[0]) as usize;
    let colour = |labels: &[u32], p: [i32; 2]| labels[at(p)];
    let mut debris = crate::memory::filled(labels.len(), false, "debris flags")?;
    let mut stack: Vec<[i32; 2]> = Vec::new();
    for &k in &roots {
        if debris[k] {
            continue;
        }
        stats.components += 1;
        debris[k] = true;
        stack.push([k as i32 % w, k as i32 / w]);
        while let Some([x, y]) = stack.pop() {
            let i = labels[at([x, y])];
            for b in neighbours(x, y, width, height) {
                if !debris[at(b)] && colour(&labels, b) == i {
                    debris[at(b)] = true;
                    stack.push(b);
                }
            }
        }
    }
    let debris_pixels: Vec<usize> = (0..labels.len())
        .filter(|&k| debris[k])
        .gather("debris pixels")?;
    stats.debris = debris_pixels.len();
    stats.debris_ms = ms(started);

    // Flood the debris in the total order: the bulk pixels around it are
    // coloured when their own (pixel, colour) pair comes up, and then offer
    // their colour to their debris neighbours.
    let started = Instant::now();
    let original = labels.clone();
    #[derive(PartialEq, Eq, PartialOrd, Ord)]
    enum Event {
        /// A bulk pixel (already coloured) whose turn comes.
        Coloured,
        /// A debris pixel may take a colour.
        Offer,
    }
    // (order, event, pixel, colour), smallest first.
    type Entry = (Priority, Event, [i32; 2], u32);
    let mut queue: BinaryHeap<Reverse<Entry>> = BinaryHeap::new();
    for &k in &debris_pixels {
        let d = [k as i32 % w, k as i32 / w];
        for n in neighbours(d[0], d[1], width, height) {
            if !debris[at(n)] {
                let c = labels[at(n)];
                queue.push(Reverse((
                    priority(n, seeds[c as usize]),
                    Event::Coloured,
                    n,
                    c,
                )));
            }
        }
    }
    let mut done = crate::memory::filled(labels.len(), false, "done flags")?;
    while let Some(Reverse((_, event, p, c))) = queue.pop() {
        match event {
            Event::Coloured => {}
            Event::Offer => {
                if done[at(p)] {
                    continue;
                }
                done[at(p)] = true;
                labels[at(p)] = c;
            }
        }
        for d in neighbours(p[0], p[1], width, height) {
            if debris[at(d)] && !done[at(d)] {
                queue.push(Reverse((
                    priority(d, seeds[c as usize]),
                    Event::Offer,
                    d,
                    c,
                )));
            }
        }
    }
    stats.recoloured = debris_pixels
        .iter()
        .filter(|&&k| labels[k] != original[k])
        .count();
    stats.repair_ms = ms(started);
    Ok(Flooding {
        width,
        height,
        labels,
        stats,
    })
}

/// Jump flooding (Rong and Tan 2006): passes with steps N/2, N/4, ..., 1 over
/// the texture (N its longer side rounded up to a power of two), each pixel
/// keeping the nearest seed its eight step-neighbours know. A fast label map
/// with a few pixels given a farther seed (0.018% in the tests), not the
/// flooding of the paper: regions need not be connected.
pub fn jump_flood(machine: &Machine, width: u32, height: u32, seeds: &[Seed]) -> Result<Vec<u32>> {
    check_seeds(width, height, seeds)?;
    if width >= 1 << 16 || height >= 1 << 16 {
        return Err(Error::out_of_range(format!(
            "jump flooding packs seed positions in 16 bits: {width}x{height} is too large"
        )));
    }
    const NO_SEED: u32 = u32::MAX;
    let pack = |s: Seed| s[0] as u32 | (s[1] as u32) << 16;
    let pixels = width as usize * height as usize;
    let mut start = crate::memory::filled(pixels, NO_SEED, "seeds' starts")?;
    for s in seeds {
        start[(s[1] as u32 * width + s[0] as u32) as usize] = pack(*s);
    }
    let bytes = (pixels * 4) as u64;
    let mut a = machine.storage_buffer(bytes)?;
    a.write(&start);
    let b = machine.storage_buffer(bytes)?;
    let side = width.max(height).next_power_of_two();
    let steps: Vec<u32> = std::iter::successors(Some(side / 2), |s| (*s > 1).then_some(s / 2))
        .filter(|&s| s > 0)
        .gather("steps")?;
    let chunk = crate::machine::MAX_GROUPS * JUMP_FLOOD.group();
    machine.run(|pass| {
        for (k, &step) in steps.iter().enumerate() {
            let buffers = if k % 2 == 0 { [&a, &b] } else { [&b, &a] };
            for first in (0..pixels as u32).step_by(chunk as usize) {
                let count = chunk.min(pixels as u32 - first);
                pass.dispatch(
                    &JUMP_FLOOD,
                    &buffers,
                    count,
                    bytemuck::bytes_of(&[width, height, step, first]),
                )?;
            }
        }
        Ok(())
    })?;
    let result = if steps.len() % 2 == 1 { &b } else { &a };
    // The seed at each seed pixel, to turn positions back into indices.
    let mut seed_at = crate::memory::filled(pixels, NONE, "seeds' pixels")?;
    for (i, s) in seeds.iter().enumerate() {
        seed_at[(s[1] as u32 * width + s[0] as u32) as usize] = i as u32;
    }
    result
        .read::<u32>(pixels)
        .into_iter()
        .map(|p| match p {
            NO_SEED => NONE,
            p => seed_at[((p >> 16) * width + (p & 0xFFFF)) as usize],
        })
        .gather("seed at")
}

/// The dual of a colouring on the device (`glsl/dualize.comp`): a triangle for
/// every digital Voronoi vertex, two where four colours meet, vertices
/// counter-clockwise, [`DUMMY`](crate::geometry::triangulation::DUMMY) beyond
/// the texture; each from its smallest vertex, sorted.
pub fn dualize(
    machine: &Machine,
    labels: &[u32],
    width: u32,
    height: u32,
) -> Result<Vec<[u32; 3]>> {
    let pixels = width as usize * height as usize;
    if labels.len() != pixels || pixels == 0 {
        return Err(Error::malformed(format!(
            "{} labels for a {width}x{height} texture",
            labels.len()
        )));
    }
    let mut input = machine.storage_buffer((pixels * 4) as u64)?;
    input.write(labels);
    // A valid dual of n seeds has 2n - 2 triangles; room for more, and a rerun
    // with the count if even that is short.
    let seeds = labels
        .iter()
        .copied()
        .filter(|&l| l != NONE)
        .max()
        .map_or(0, |m| m as usize + 1);
    let mut capacity = 2 * seeds + 64;
    loop {
        let mut output = machine.storage_buffer((4 + 12 * capacity) as u64)?;
        output.fill(0);
        machine.run(|pass| {
            let push = [width, height, capacity as u32];
            let strips = (height + 1).div_ceil(64);
            pass.dispatch_grid(
                &DUALIZE,
                &[&input, &output],
                (width + 1, strips),
                bytemuck::bytes_of(&push),
            )
        })?;
        let count = output.read::<u32>(1)[0] as usize;
        if count <= capacity {
            let words = output.read::<u32>(1 + 3 * count);
            let mut triangles: Vec<[u32; 3]> = words[1..]
                .chunks_exact(3)
                .map(|t| {
                    // The smallest vertex first, the turn kept.
                    let first = (0..3).min_by_key(|&k| t[k]).expect("three");
                    [t[first], t[(first + 1) % 3], t[(first + 2) % 3]]
                })
                .gather("triangles")?;
            // Appended as the device's invocations finish: sorted, so that
            // the meshes built from them are the same on every run.
            triangles.par_sort_unstable();
            return Ok(triangles);
        }
        capacity = count;
    }
}
