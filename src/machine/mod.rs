//! The pixel machine of thesis ch. 1 on Vulkan.
//!
//! | thesis model | here |
//! | --- | --- |
//! | picture of p×p pixels, its buffers | [`Image`]s in a [`Format`] |
//! | z buffer and stencil | one [`Format::DepthStencil`] image |
//! | state of the raster pipeline | [`RasterState`] (cached as `VkPipeline`s) |
//! | display list + translate | instanced [`Pass::draw_cones`] |
//! | a set of triangles | [`Pass::draw_rect`], [`Pass::draw_cones`] |
//! | read back a rectangle | [`Machine::read_u32`], [`Machine::read_f32`] |
//! | minmax, histogram | [`Machine::minmax`], [`Machine::histogram`] (compute) |

mod cache;
mod context;
mod conv;
mod descriptors;
mod memory;
mod pass;
mod pipelines;
mod profile;
pub mod state;
mod sync;

#[allow(clippy::all)]
mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

use std::sync::Arc;

use ash::vk;

pub use context::{DeviceChoice, MachineOptions};
pub use memory::{Buffer, BufferKind, Format, Image};
pub use pass::{
    Clear, ClearColor, ConeBatch, ConeDraw, ConeInstance, ConePush, Pass, PixelRect, RectDraw,
    SiteBatch, SiteInstance, Target, MAX_GROUPS,
};
pub use pipelines::{BufferKernel, Program, SiteShape, BUFFER_KERNEL_BINDINGS};
pub use profile::{HostSpan, PassSpan, Phase, Profiler, Timeline};
pub use state::{
    Blend, BlendFactor, BlendOp, ChannelMask, ColorUpdate, Compare, DepthTest, DrawParams, LogicOp,
    RasterState, StencilOp, StencilTest,
};

use crate::error::{Error, Result, VkContext};
use context::Context;
use descriptors::DescriptorSets;
use pipelines::{Kernel, Pipelines};
use profile::Sections;

/// Per-channel minimum and maximum of a picture buffer (thesis §1.7, Fig. 1.12).
/// Integer buffers report their values exactly (as `f64`); single-channel buffers
/// fill channel 0 only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinMax {
    pub min: [f64; 4],
    pub max: [f64; 4],
    pub channels: usize,
}

/// The smallest and largest depth of a picture, the first pixel (row-major
/// index) holding each, and the pixels near one of them when asked for (then
/// only that extreme's pixel is found).
#[derive(Clone, Debug, PartialEq)]
pub struct DepthExtremes {
    pub min: f32,
    pub max: f32,
    /// The first pixel of each extreme; of the other extreme than the one
    /// [`NearExtreme`] asked about, `u32::MAX`.
    pub at_min: usize,
    pub at_max: usize,
    /// Pixels within [`NearExtreme::within`] of the extreme asked for (at most
    /// its capacity of them, in no order).
    pub near: Vec<usize>,
    /// How many pixels were that near (more than `near` holds if it overflowed).
    pub near_count: usize,
}

/// Which pixels [`Machine::depth_extremes`] should also list: those within
/// `within` of the minimum or of the maximum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearExtreme {
    pub maximum: bool,
    /// In depth units; or, when `squared_scale` is positive and depths are
    /// squared distances times it, in distance units.
    pub within: f32,
    pub squared_scale: f32,
    pub capacity: u32,
}

/// Bins of a histogram: `[low + b * width, low + (b + 1) * width)` for `b < bins`.
/// For integer buffers `low` and `width` are rounded to integers (width at least 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bins {
    pub channel: u32,
    pub low: f64,
    pub width: f64,
    pub bins: u32,
}

/// The pixel machine: one Vulkan device with its queue, pipeline cache and the
/// means to submit passes and read results back.
pub struct Machine {
    pipelines: Pipelines,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    descriptors: DescriptorSets,
    scratch: std::cell::RefCell<Option<Buffer>>,
    /// The labelled (and, with a profiler, timed) sections of the run being
    /// recorded.
    sections: std::cell::RefCell<Sections>,
    profiler: Option<Profiler>,
    ctx: Arc<Context>,
}

impl Machine {
    /// Creates the machine on the device `options` choose.
    pub fn new(options: &MachineOptions) -> Result<Self> {
        let ctx = Arc::new(Context::new(options)?);
        let device = &ctx.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create infos; every object is destroyed in `Drop`.
        let command_pool =
            unsafe { device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        let mut machine = Self {
            pipelines: Pipelines::new(&ctx, options.pipeline_cache.as_deref())?,
            command_pool,
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            descriptors: DescriptorSets::new(&ctx),
            scratch: Default::default(),
            sections: Sections::new(&ctx, options.profiler.is_some()).into(),
            profiler: options.profiler.clone(),
            ctx: ctx.clone(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: as above.
        unsafe {
            machine.command_buffer = device
                .allocate_command_buffers(&alloc)
                .vk("vkAllocateCommandBuffers")?[0];
            machine.fence = device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .vk("vkCreateFence")?;
        }
        ctx.name_object(machine.command_buffer, "pixgeo run");
        ctx.check_validation()?;
        Ok(machine)
    }

    /// The machine `PIXGEO_DEVICE` and `PIXGEO_VALIDATION` ask for.
    pub fn from_env() -> Result<Self> {
        Self::new(&MachineOptions::from_env())
    }

    /// The device's name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub fn device_name(&self) -> &str {
        &self.ctx.device_name
    }

    /// The largest picture side the device allows.
    pub fn max_picture_side(&self) -> u32 {
        let l = &self.ctx.properties.limits;
        l.max_image_dimension2_d
            .min(l.max_framebuffer_width)
            .min(l.max_framebuffer_height)
    }

    /// The most bytes a shader may see of one storage buffer.
    pub fn max_storage_buffer_bytes(&self) -> u64 {
        self.ctx.properties.limits.max_storage_buffer_range as u64
    }

    /// Number of distinct graphics pipelines created so far.
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.graphics_count()
    }

    /// A picture buffer of `format`, `width` x `height` pixels.
    pub fn image(&self, format: Format, width: u32, height: u32) -> Result<Image> {
        let side = self.max_picture_side();
        if width > side || height > side {
            return Err(Error::PictureTooLarge {
                width,
                height,
                limit: side,
            });
        }
        Image::new(&self.ctx, format, width, height)
    }

    /// A host-visible buffer with `data`, for vertices and instances.
    pub fn vertex_buffer<T: bytemuck::Pod>(&self, data: &[T]) -> Result<Buffer> {
        Buffer::with_data(&self.ctx, BufferKind::Vertices, data)
    }

    /// A host-visible buffer of `bytes` for reading results back.
    pub fn readback_buffer(&self, bytes: u64) -> Result<Buffer> {
        Buffer::new(&self.ctx, BufferKind::Readback, bytes)
    }

    /// Records the passes of `record` into one command buffer, submits it and waits.
    /// With validation on, any message reported meanwhile makes this an error.
    ///
    /// Every image and buffer a pass uses is borrowed for `'r`, which outlasts
    /// the call, so none can be dropped before the submission has completed:
    ///
    /// ```compile_fail
    /// # use pixgeo::machine::*;
    /// # fn main() -> pixgeo::Result<()> {
    /// let machine = Machine::from_env()?;
    /// machine.run(|pass| {
    ///     // Dropped at the closure's end, before the submission:
    ///     let picture = machine.image(Format::R32Uint, 4, 4)?;
    ///     let target = Target { color: Some(&picture), depth_stencil: None };
    ///     pass.begin(target, Clear::default())?;
    ///     pass.end()
    /// })?;
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// Made before the run, it lives long enough:
    ///
    /// ```
    /// # use pixgeo::machine::*;
    /// # fn main() -> pixgeo::Result<()> {
    /// let machine = Machine::from_env()?;
    /// let picture = machine.image(Format::R32Uint, 4, 4)?;
    /// machine.run(|pass| {
    ///     let target = Target { color: Some(&picture), depth_stencil: None };
    ///     pass.begin(target, Clear::default())?;
    ///     pass.end()
    /// })?;
    /// # Ok(())
    /// # }
    /// ```
    pub fn run<'r, R>(&self, record: impl FnOnce(&mut Pass<'_, 'r>) -> Result<R>) -> Result<R> {
        let started = std::time::Instant::now();
        self.sections.borrow_mut().clear();
        let device = &self.ctx.device;
        let cmd = self.command_buffer;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the command buffer is not in use (every run waits for its fence).
        unsafe {
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            device
                .begin_command_buffer(cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        let recorded = {
            let mut pass = Pass::new(self, cmd);
            let recorded = record(&mut pass);
            pass.finish();
            recorded
        };
        pass::end_commands(device, cmd)?;
        let value = match recorded {
            Ok(value) => value,
            Err(e) => {
                self.descriptors.release()?;
                return Err(e);
            }
        };
        let cmds = [cmd];
        let submit = vk::SubmitInfo::default().command_buffers(&cmds);
        let submitted = std::time::Instant::now();
        // SAFETY: the command buffer is fully recorded; the fence is unsignalled and
        // reset after waiting, so the next run starts from the same state.
        unsafe {
            device
                .queue_submit(self.ctx.queue, &[submit], self.fence)
                .vk("vkQueueSubmit")?;
            device
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .vk("vkWaitForFences")?;
            device.reset_fences(&[self.fence]).vk("vkResetFences")?;
        }
        self.descriptors.release()?;
        self.ctx.check_validation()?;
        self.pipelines.cache.save();
        if let Some(profiler) = &self.profiler {
            profiler.record_passes(self.sections.borrow().spans(profiler, submitted)?);
            profiler.record_host("run", started, std::time::Instant::now());
        }
        Ok(value)
    }

    /// Reads back `rect` of an integer image, row-major.
    pub fn read_u32(&self, image: &Image, rect: PixelRect) -> Result<Vec<u32>> {
        let mut out = vec![0; rect.width as usize * rect.height as usize];
        self.read_u32_into(image, rect, &mut out, rect.width as usize)?;
        Ok(out)
    }

    /// Reads back `rect` of an integer image into `out`: row `r` of the rectangle
    /// goes to `out[r * stride..]`, so a tile lands in place in a wider array.
    /// An `Rgba8Unorm` pixel reads as one word, red in the lowest byte.
    pub fn read_u32_into(
        &self,
        image: &Image,
        rect: PixelRect,
        out: &mut [u32],
        stride: usize,
    ) -> Result<()> {
        if !matches!(image.format(), Format::R32Uint | Format::Rgba8Unorm) {
            return Err(Error::InvalidInput(format!(
                "read_u32 reads R32Uint or Rgba8Unorm images, not {:?}",
                image.format()
            )));
        }
        self.read_into(image, rect, out, stride)
    }

    /// Reads back `rect` of a float image (for `DepthStencil`: the z buffer),
    /// row-major; `Rgba32Float` gives four values per pixel.
    pub fn read_f32(&self, image: &Image, rect: PixelRect) -> Result<Vec<f32>> {
        let per_pixel = (image.format().texel_bytes() / 4) as usize;
        let row = rect.width as usize * per_pixel;
        let mut out = vec![0.0; row * rect.height as usize];
        self.read_f32_into(image, rect, &mut out, row)?;
        Ok(out)
    }

    /// Reads back `rect` of a float image into `out` with a row stride, as
    /// [`Machine::read_u32_into`] does (the stride counts floats).
    pub fn read_f32_into(
        &self,
        image: &Image,
        rect: PixelRect,
        out: &mut [f32],
        stride: usize,
    ) -> Result<()> {
        if !matches!(
            image.format(),
            Format::R32Float | Format::Rgba32Float | Format::DepthStencil | Format::Depth
        ) {
            return Err(Error::InvalidInput(format!(
                "read_f32 reads float images or depth, not {:?}",
                image.format()
            )));
        }
        self.read_into(image, rect, out, stride)
    }

    /// Reads back the stencil of `rect` of a depth/stencil image into `out`, row
    /// `r` at `out[r * stride..]`.
    pub fn read_stencil_into(
        &self,
        image: &Image,
        rect: PixelRect,
        out: &mut [u32],
        stride: usize,
    ) -> Result<()> {
        let (w, h) = (rect.width as usize, rect.height as usize);
        if stride < w || out.len() < h.saturating_sub(1) * stride + w {
            return Err(Error::InvalidInput(format!(
                "stencil readback of {w}x{h} pixels does not fit {} values with stride {stride}",
                out.len()
            )));
        }
        let buffer = self.readback_buffer((w * h).max(4) as u64)?;
        self.run(|pass| pass.copy_stencil_to_buffer(image, rect, &buffer))?;
        for (r, row) in buffer.mapped()[..w * h].chunks_exact(w).enumerate() {
            for (o, v) in out[r * stride..][..w].iter_mut().zip(row) {
                *o = *v as u32;
            }
        }
        Ok(())
    }

    fn read_into<T: bytemuck::Pod>(
        &self,
        image: &Image,
        rect: PixelRect,
        out: &mut [T],
        stride: usize,
    ) -> Result<()> {
        let bytes = rect.width as u64 * rect.height as u64 * image.format().texel_bytes();
        let row =
            (rect.width as u64 * image.format().texel_bytes()) as usize / std::mem::size_of::<T>();
        let needed = (rect.height as usize).saturating_sub(1) * stride + row;
        if stride < row || out.len() < needed {
            return Err(Error::InvalidInput(format!(
                "readback of {}x{} pixels needs {needed} values with stride {stride}, got {}",
                rect.width,
                rect.height,
                out.len()
            )));
        }
        // One readback buffer is kept and grown: allocating fresh host memory for
        // every read costs more than the copy.
        let mut scratch = self.scratch.borrow_mut();
        if scratch.as_ref().is_none_or(|b| b.size() < bytes) {
            *scratch = None;
            *scratch = Some(self.readback_buffer(bytes)?);
        }
        let buffer = scratch
            .as_ref()
            .ok_or_else(|| Error::InvalidInput("no readback buffer".into()))?;
        self.run(|pass| pass.copy_to_buffer(image, rect, buffer))?;
        let src: &[T] = bytemuck::try_cast_slice(&buffer.mapped()[..bytes as usize])
            .map_err(|e| Error::InvalidInput(format!("readback buffer: {e}")))?;
        for (r, src_row) in src.chunks_exact(row).enumerate() {
            out[r * stride..][..row].copy_from_slice(src_row);
        }
        Ok(())
    }

    /// A host-visible storage buffer of `bytes` bytes, for kernels and fragment
    /// shaders to read and write and the host to fill and read.
    pub fn storage_buffer(&self, bytes: u64) -> Result<Buffer> {
        self.readback_buffer(bytes)
    }

    /// Whether fragment shaders may write storage buffers, which the k nearest
    /// sites and the thesis's peeling need.
    pub fn has_fragment_stores(&self) -> bool {
        self.ctx.fragment_stores
    }

    /// Whether fragment shaders may do 64-bit atomics on storage buffers, which
    /// [`Program::ConeKNearest`] needs.
    pub fn has_fragment_atomics64(&self) -> bool {
        self.ctx.fragment_atomics64
    }

    /// Whether shaders may compute in double precision.
    pub fn has_float64(&self) -> bool {
        self.ctx.float64
    }

    /// The minmax function (thesis §1.7) over `rect`, computed on the device; only
    /// eight numbers come back to the host.
    pub fn minmax(&self, image: &Image, rect: PixelRect) -> Result<MinMax> {
        let float = image.format() != Format::R32Uint;
        let channels = if image.format() == Format::Rgba32Float {
            4
        } else {
            1
        };
        let mut buffer = self.readback_buffer(32)?;
        buffer.write(&[u32::MAX, u32::MAX, u32::MAX, u32::MAX, 0, 0, 0, 0]);
        self.run(|pass| pass.reduce(Kernel::MinMax, image, rect, &buffer, &[]))?;
        let raw: Vec<u32> = buffer.read(8);
        let decode = |u: u32| -> f64 {
            if float {
                let bits = if u & 0x8000_0000 != 0 {
                    u & 0x7fff_ffff
                } else {
                    !u
                };
                f32::from_bits(bits) as f64
            } else {
                u as f64
            }
        };
        let mut out = MinMax {
            min: [0.0; 4],
            max: [0.0; 4],
            channels,
        };
        for c in 0..channels {
            out.min[c] = decode(raw[c]);
            out.max[c] = decode(raw[4 + c]);
        }
        Ok(out)
    }

    /// The extremes of the depth buffer `depth` and where they are: the depth is
    /// copied to a storage buffer on the device and reduced there by
    /// [`BufferKernel::Extremum`], whose later passes visit only the strips of
    /// the picture that can hold what they look for; four words (and the near
    /// list) come back to the host.
    pub fn depth_extremes(
        &self,
        depth: &Image,
        near: Option<NearExtreme>,
    ) -> Result<DepthExtremes> {
        if !matches!(depth.format(), Format::Depth | Format::DepthStencil) {
            return Err(Error::InvalidInput(
                "depth extremes are taken of a depth image".into(),
            ));
        }
        let (w, h) = (depth.width(), depth.height());
        let values = self.storage_buffer(4 * w as u64 * h as u64)?;
        let capacity = near.map_or(0, |n| n.capacity);
        // One invocation per strip of 64 rows of a column.
        let strips = w * h.div_ceil(64);
        // The extremes, the list, each strip's extremes (written by phase 0).
        let words = 5 + 2 * capacity as u64 + 2 * strips as u64;
        let mut result = self.storage_buffer(4 * words)?;
        result.write(&[u32::MAX, 0, u32::MAX, u32::MAX, 0]);
        let push = |phase: u32| {
            let within = near.map_or(0.0, |n| n.within);
            let squared = near.map_or(0.0, |n| n.squared_scale);
            [w, h, phase, within.to_bits(), capacity, squared.to_bits()]
        };
        let buffers = [&values, &result];
        self.run(|pass| {
            pass.feed_fragment_buffer(depth, &values, 0)?;
            pass.dispatch(BufferKernel::Extremum, &buffers, strips, &push(0))?;
            // With a list, it holds the extremes' pixels (with their values).
            let phase = near.map_or(1, |n| 2 + u32::from(n.maximum));
            pass.dispatch(BufferKernel::Extremum, &buffers, strips, &push(phase))
        })?;
        let raw: Vec<u32> = result.read(5 + 2 * capacity as usize);
        let near_count = raw[4] as usize;
        let listed: Vec<(usize, u32)> = raw[5..5 + 2 * near_count.min(capacity as usize)]
            .chunks_exact(2)
            .map(|p| (p[0] as usize, p[1]))
            .collect();
        let (mut at_min, mut at_max) = (raw[2] as usize, raw[3] as usize);
        if let Some(n) = near {
            // The first pixel holding the extreme among those listed; a list that
            // overflowed may have lost it, so then ask the device.
            let extreme = if n.maximum { raw[1] } else { raw[0] };
            let first = listed
                .iter()
                .filter(|(_, v)| *v == extreme)
                .map(|(i, _)| *i)
                .min();
            let first = match first {
                Some(i) => i,
                None => {
                    self.run(|pass| {
                        pass.dispatch(BufferKernel::Extremum, &buffers, strips, &push(1))
                    })?;
                    let again: Vec<u32> = result.read(4);
                    if n.maximum {
                        again[3] as usize
                    } else {
                        again[2] as usize
                    }
                }
            };
            if n.maximum {
                at_max = first;
            } else {
                at_min = first;
            }
        }
        let decode = |u: u32| {
            f32::from_bits(if u & 0x8000_0000 != 0 {
                u & 0x7fff_ffff
            } else {
                !u
            })
        };
        Ok(DepthExtremes {
            min: decode(raw[0]),
            max: decode(raw[1]),
            at_min,
            at_max,
            near: listed.iter().map(|(i, _)| *i).collect(),
            near_count,
        })
    }

    /// The histogram function (thesis §1.7) of one channel over `rect`, computed on
    /// the device; only the bin counts come back.
    pub fn histogram(&self, image: &Image, rect: PixelRect, bins: Bins) -> Result<Vec<u32>> {
        if bins.bins == 0 || bins.width.is_nan() || bins.width <= 0.0 || !bins.low.is_finite() {
            return Err(Error::InvalidInput(format!("histogram bins {bins:?}")));
        }
        let channels = if image.format() == Format::Rgba32Float {
            4
        } else {
            1
        };
        if bins.channel >= channels {
            return Err(Error::InvalidInput(format!(
                "channel {} of a {}-channel picture",
                bins.channel, channels
            )));
        }
        let (low, width) = if image.format() == Format::R32Uint {
            (
                bins.low.clamp(0.0, u32::MAX as f64) as u32,
                bins.width.round().clamp(1.0, u32::MAX as f64) as u32,
            )
        } else {
            ((bins.low as f32).to_bits(), (bins.width as f32).to_bits())
        };
        let mut buffer = self.readback_buffer(4 * bins.bins as u64)?;
        buffer.write(&vec![0u32; bins.bins as usize]);
        self.run(|pass| {
            pass.reduce(
                Kernel::Histogram,
                image,
                rect,
                &buffer,
                &[bins.channel, bins.bins, low, width],
            )
        })?;
        Ok(buffer.read(bins.bins as usize))
    }
}

impl Drop for Machine {
    fn drop(&mut self) {
        // SAFETY: no submission is pending (`run` waits); each object is destroyed
        // once, before the context (dropped after this with the last `Arc`).
        unsafe {
            let device = &self.ctx.device;
            let _ = device.device_wait_idle();
            device.destroy_fence(self.fence, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}
