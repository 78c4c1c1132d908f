//! The two methods on the device: spans with prefix sums, and the thesis's
//! discs counted by stencil wrap-around and blending.

use super::*;
use crate::machine::Extent;
use crate::memory::Gather;

/// Push constants of the settle programs (`glsl/settle.glsl`): `[width,
/// height, metric kind, p, first, count, channel]`.
type SettleWords = [u32; 7];

/// The settle point's discs (thesis §3.10.3): one square per source pixel,
/// instanced without vertex buffers; the fragment shader keeps the disc and
/// reads each pixel's radius from the bound storage buffer. Its fragment
/// builds follow the distance function's kind.
static SETTLE_DISC: GraphicsProgram = GraphicsProgram::new(
    "SettleDisc",
    shaders::SETTLE_DISC_VERT,
    Fragments::ByVariant(&shaders::SETTLE_DISC_FRAG),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<SettleWords>(),
);

/// The span counting: every disc's parts into seven difference pictures of
/// `i32` in buffers 1 to 7, one invocation per source pixel, by the distance
/// function's kind.
static SETTLE_SPANS: [ComputeProgram; 5] = {
    const fn spans(name: &'static str, shader: crate::machine::Shader) -> ComputeProgram {
        // The radii by source pixel, and the seven difference pictures at
        // the discs' pixels.
        ComputeProgram::new(
            name,
            shader,
            std::mem::size_of::<SettleWords>(),
            &[Extent::ByData; 8],
        )
    }
    [
        spans("SettleSpans(L2)", shaders::SETTLE_SPANS_COMP[0]),
        spans("SettleSpans(L1)", shaders::SETTLE_SPANS_COMP[1]),
        spans("SettleSpans(LInf)", shaders::SETTLE_SPANS_COMP[2]),
        spans("SettleSpans(Lp)", shaders::SETTLE_SPANS_COMP[3]),
        spans("SettleSpans(LpSum)", shaders::SETTLE_SPANS_COMP[4]),
    ]
};

/// The counts from those difference pictures, into the first (push `[width,
/// height, phase]`, one invocation per column, per diagonal, per antidiagonal
/// and per row in phases 0 to 3).
static SETTLE_SUMS: ComputeProgram = ComputeProgram::new(
    "SettleSums",
    shaders::SETTLE_SUMS_COMP,
    std::mem::size_of::<[u32; 3]>(),
    &{
        // The radii, untouched; then the seven pictures.
        const PICTURE: Extent = Extent::Push(|p| 4 * p[0] as u64 * p[1] as u64);
        [
            Extent::Push(|_| 0),
            PICTURE,
            PICTURE,
            PICTURE,
            PICTURE,
            PICTURE,
            PICTURE,
            PICTURE,
        ]
    },
);

/// The push constants of the settle programs (`glsl/settle.glsl`).
#[derive(Clone, Copy)]
pub(super) struct Push {
    pub(super) frame: Frame,
    /// The kind of the radii's keys and its exponent (`glsl/metric.glsl`):
    /// the certifier's (`Certifier::shader_code`).
    pub(super) code: (u32, f32),
}

impl Push {
    fn metric_code(&self) -> (u32, f32) {
        self.code
    }

    fn words(&self, first: u32, count: u32, channel: u32) -> SettleWords {
        let (kind, p) = self.metric_code();
        [
            self.frame.width,
            self.frame.height,
            kind,
            p.to_bits(),
            first,
            count,
            channel,
        ]
    }
}

/// Difference pictures of the span counting (`glsl/settle_spans.comp`); the
/// first ends up holding the counts.
const SPAN_PICTURES: usize = 7;

pub(super) fn count_spans(
    machine: &Machine,
    radii: &crate::machine::Buffer,
    push: Push,
    stats: &mut SettleStats,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u32>> {
    let frame = push.frame;
    let pixels = frame.len() as u32;
    let bytes = 4 * pixels as u64;
    let pictures = (0..SPAN_PICTURES)
        .map(|_| {
            let mut picture = machine.storage_buffer(bytes)?;
            picture.fill(0);
            Ok(picture)
        })
        .try_gather::<_, Vec<_>>("span pictures")?;
    let buffers: Vec<_> = std::iter::once(radii).chain(&pictures).gather("buffers")?;
    let start = Instant::now();
    let kind = push.metric_code().0;
    // About 64 submissions, for progress; each within one dispatch's limits.
    let step = pixels
        .div_ceil(64)
        .clamp(1, MAX_GROUPS * SETTLE_SPANS[0].group());
    let mut first = 0;
    while first < pixels {
        let count = step.min(pixels - first);
        machine.run(|pass| {
            let kernel = SETTLE_SPANS.get(kind as usize).ok_or_else(|| {
                Error::unsupported_option(format!(
                    "settle spans are not built for distance kind {kind}"
                ))
            })?;
            pass.dispatch(
                kernel,
                &buffers,
                count,
                bytemuck::bytes_of(&push.words(first, count, 0)),
            )
        })?;
        first += count;
        progress(first as u64, pixels as u64);
    }
    machine.run(|pass| {
        let (w, h) = (frame.width, frame.height);
        // Columns, the two kinds of diagonals, rows.
        for (phase, lines) in [(0, w), (1, w + h - 1), (2, w + h - 1), (3, h)] {
            pass.dispatch(
                &SETTLE_SUMS,
                &buffers,
                lines,
                bytemuck::bytes_of(&[w, h, phase]),
            )?;
        }
        Ok(())
    })?;
    stats.count_ms = ms(start);
    let start = Instant::now();
    let area = pictures[0].read::<u32>(pixels as usize);
    stats.readback_ms = ms(start);
    Ok(area)
}

/// Discs one channel may count: 255 wrap-arounds of the 8-bit stencil, each
/// adding 1/255, fill the 8-bit channel, and a pixel is covered at most once per
/// disc.
const DISCS_PER_CHANNEL: u32 = 255 * 256;

pub(super) fn count_faithful(
    machine: &Machine,
    radii: &crate::machine::Buffer,
    push: Push,
    stats: &mut SettleStats,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u32>> {
    let frame = push.frame;
    let pixels = frame.len() as u32;
    let (w, h) = (frame.width, frame.height);
    let color = machine.image(Format::Rgba8Unorm, w, h)?;
    let depth_stencil = machine.image(Format::DepthStencil, w, h)?;
    // Fig. 3.49: stencil starts at 1, passes where it is 0, and every fragment
    // increments it with wrap-around; passing fragments add their colour.
    let state = RasterState {
        depth: DepthTest::OFF,
        stencil: StencilTest {
            compare: Compare::Equal,
            compare_mask: 0xff,
            write_mask: 0xff,
            on_fail: StencilOp::IncrementWrap,
            on_depth_fail: StencilOp::IncrementWrap,
            on_pass: StencilOp::IncrementWrap,
        },
        color: ColorUpdate::Blend(Blend::ADD),
        color_mask: ChannelMask::ALL,
    };
    let params = DrawParams::default();
    let target = Target {
        color: Some(&color),
        depth_stencil: Some(&depth_stencil),
    };
    let mut total = crate::memory::filled(pixels as usize, 0u32, "counts")?;
    let mut rgba = crate::memory::filled(pixels as usize, 0u32, "colours")?;
    let mut count_ms = 0.0;
    let mut readback_ms = 0.0;
    let mut first = 0;
    let mut channel = 0;
    while first < pixels {
        let count = DISCS_PER_CHANNEL.min(pixels - first);
        let clear = Clear {
            color: (channel == 0).then_some(ClearColor::Float([0.0; 4])),
            depth: (first == 0).then_some(1.0),
            stencil: (first == 0).then_some(1),
        };
        let start = Instant::now();
        machine.run(|pass| {
            pass.bind_fragment_buffers(&[radii], None)?;
            pass.begin(target, clear)?;
            pass.draw(
                &state,
                &params,
                &Draw {
                    program: &SETTLE_DISC,
                    variant: push.metric_code().0,
                    push: bytemuck::bytes_of(&push.words(first, count, channel)),
                    vertex_buffers: &[],
                    vertices: 0..4,
                    instances: 0..count,
                },
            )?;
            pass.end()
        })?;
        count_ms += ms(start);
        first += count;
        channel += 1;
        if channel == 4 || first == pixels {
            let start = Instant::now();
            let rect = PixelRect::of(&color);
            machine.read_u32_into(&color, rect, &mut rgba, w as usize)?;
            total.par_iter_mut().zip(&rgba).for_each(|(t, &c)| {
                let wraps: u32 = c.to_le_bytes().iter().map(|&b| b as u32).sum();
                *t += 256 * wraps;
            });
            stats.readbacks += 1;
            readback_ms += ms(start);
            channel = 0;
        }
        progress(first as u64, pixels as u64);
    }
    // The hits since the last wrap: the stencil started at 1.
    let start = Instant::now();
    machine.read_stencil_into(
        &depth_stencil,
        PixelRect::of(&depth_stencil),
        &mut rgba,
        w as usize,
    )?;
    total
        .par_iter_mut()
        .zip(&rgba)
        .for_each(|(t, &s)| *t += (s + 255) % 256);
    stats.readbacks += 1;
    stats.count_ms = count_ms;
    stats.readback_ms = readback_ms + ms(start);
    Ok(total)
}
