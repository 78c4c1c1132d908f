//! Recording work for the machine: rendering into the picture's buffers, copies and
//! compute dispatches. A `Pass` records into one command buffer; `Machine::run`
//! submits it and waits.
//!
//! One type records every command, so it alone tracks the open rendering pass
//! and each resource's last use; its commands are in `draw` (rendering),
//! `compute` (dispatches and reductions) and `copy` (transfers).

use std::sync::Arc;

use ash::vk;

use super::{
    context::Context,
    memory::{Buffer, Format, Image},
    pipelines::{Kernel, GRAPHICS_RECORDS_BINDING},
    program::{
        ComputeProgram, Extent, Fragments, GraphicsProgram, Output, Topology, COMPUTE_PUSH_BYTES,
    },
    shaders,
    state::{DrawParams, RasterState},
    sync::{self, BufferUse, Usage},
    Machine,
};
use crate::error::{Error, Result, VkContext};

mod compute;
mod copy;
mod draw;

/// The buffers a rendering pass draws into.
#[derive(Clone, Copy)]
pub struct Target<'a> {
    /// The colour buffer(s) of the pixel: one image.
    pub color: Option<&'a Image>,
    /// The z buffer and stencil (`DepthStencil`), or the z buffer alone (`Depth`).
    pub depth_stencil: Option<&'a Image>,
}

/// A colour clear value matching the target's format.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClearColor {
    Uint([u32; 4]),
    Float([f32; 4]),
}

/// What the buffers hold when a rendering pass begins; `None` keeps the contents.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clear {
    pub color: Option<ClearColor>,
    pub depth: Option<f32>,
    pub stencil: Option<u8>,
}

/// A rectangle of pixels `(x, y, width, height)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl PixelRect {
    /// `width` x `height` pixels from the corner (0, 0).
    pub fn sized(width: u32, height: u32) -> Self {
        Self {
            x: 0,
            y: 0,
            width,
            height,
        }
    }

    /// The whole of `image`.
    pub fn of(image: &Image) -> Self {
        Self {
            x: 0,
            y: 0,
            width: image.width(),
            height: image.height(),
        }
    }

    fn check_inside(&self, image: &Image) -> Result<()> {
        if self.width == 0
            || self.height == 0
            || self
                .x
                .checked_add(self.width)
                .is_none_or(|r| r > image.width())
            || self
                .y
                .checked_add(self.height)
                .is_none_or(|b| b > image.height())
        {
            return Err(Error::Usage(format!(
                "rectangle {self:?} is empty or not inside the {}x{} picture",
                image.width(),
                image.height()
            )));
        }
        Ok(())
    }
}

/// A rectangle in world coordinates with constant depth and colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectDraw {
    /// World corners `(min x, min y)` and `(max x, max y)`.
    pub lo: [f32; 2],
    pub hi: [f32; 2],
    pub depth: f32,
    /// The colour; for integer targets the values are written as `u32` bit patterns
    /// (use [`RectDraw::uint`]).
    pub value: [f32; 4],
}

impl RectDraw {
    /// A rectangle covering the whole picture of `width` x `height` pixels.
    pub fn full_picture(width: u32, height: u32) -> Self {
        Self {
            lo: [-0.5, -0.5],
            hi: [width as f32 - 0.5, height as f32 - 0.5],
            depth: 0.0,
            value: [0.0; 4],
        }
    }

    /// Sets an integer colour (for `R32Uint` targets).
    pub fn uint(mut self, value: [u32; 4]) -> Self {
        self.value = value.map(f32::from_bits);
        self
    }

    pub fn float(mut self, value: [f32; 4]) -> Self {
        self.value = value;
        self
    }

    pub fn at_depth(mut self, depth: f32) -> Self {
        self.depth = depth;
        self
    }
}

/// One draw of a program: `variant` chooses its fragment build (see
/// [`Fragments`]), `push` holds its push
/// constants, and `vertex_buffers` feed its declared vertex buffers in order.
#[derive(Clone)]
pub struct Draw<'a, 'r> {
    pub program: &'static GraphicsProgram,
    pub variant: u32,
    pub push: &'a [u8],
    pub vertex_buffers: &'a [&'r Buffer],
    /// Vertices drawn per instance: per-vertex buffers are read from
    /// `vertices.start`.
    pub vertices: std::ops::Range<u32>,
    /// Instances drawn: per-instance buffers and `gl_InstanceIndex` count
    /// from `instances.start`.
    pub instances: std::ops::Range<u32>,
}

/// Push constants of `glsl/rect.vert` and `glsl/rect.frag`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct RectPush {
    size: [f32; 2],
    lo: [f32; 2],
    hi: [f32; 2],
    depth: f32,
    pad: u32,
    value: [f32; 4],
}

/// The machine's one program of its own: [`Pass::draw_rect`].
static RECT: GraphicsProgram = GraphicsProgram::new(
    "Rect",
    shaders::RECT_VERT,
    Fragments::ByVariant(&shaders::RECT_FRAG),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<RectPush>(),
);

struct Rendering {
    color: Option<Format>,
    depth: Option<Format>,
    width: u32,
    height: u32,
    /// The names of the programs drawn so far, each once, which name the pass.
    programs: Vec<&'static str>,
}

impl Rendering {
    /// The pass's label in a profile: `render: A+B` by the programs' names, or `render: clear`.
    fn label(&self) -> String {
        if self.programs.is_empty() {
            "render: clear".into()
        } else {
            format!("render: {}", self.programs.join("+"))
        }
    }
}

/// Workgroups one dispatch may have in x on every Vulkan device.
pub const MAX_GROUPS: u32 = 65535;

/// Records commands for one submission of [`Machine::run`] on the machine
/// `'m`; every image and buffer it is given is borrowed for `'r`, past the
/// submission's end.
pub struct Pass<'m, 'r> {
    pub(crate) machine: &'m Machine,
    pub(crate) cmd: vk::CommandBuffer,
    rendering: Option<Rendering>,
    /// The buffers used so far, each once: at the end of the run their writes
    /// are made visible to the host and they return to `BufferUse::Host`.
    buffers: Vec<&'r Buffer>,
    /// The images used so far, each once, with their use before the run: a
    /// run that fails never executes, so they return to it
    /// ([`Pass::roll_back`]).
    images: Vec<(&'r Image, Usage)>,
}

impl<'m, 'r> Pass<'m, 'r> {
    pub(crate) fn new(machine: &'m Machine, cmd: vk::CommandBuffer) -> Self {
        Self {
            machine,
            cmd,
            rendering: None,
            buffers: Vec::new(),
            images: Vec::new(),
        }
    }

    /// Refuses an image or buffer made by another machine: each machine is a
    /// device of its own, and one device cannot use another's objects.
    fn check_owner(&self, owner: &Arc<Context>, what: &str) -> Result<()> {
        if Arc::ptr_eq(owner, &self.machine.ctx) {
            return Ok(());
        }
        Err(Error::Usage(format!(
            "{what} belongs to another machine: make it with the machine whose run uses it"
        )))
    }

    /// Remembers `image`'s use before this run, the first time the run meets it.
    fn claim_image(&mut self, image: &'r Image) -> Result<()> {
        self.check_owner(&image.ctx, "an image")?;
        if !self.images.iter().any(|(i, _)| std::ptr::eq(*i, image)) {
            self.images.push((image, image.last_use.get()));
        }
        Ok(())
    }

    /// Returns every image to its use before a run whose commands will not
    /// execute (its closure or its submission failed).
    pub(crate) fn roll_back(&mut self) {
        for (image, usage) in self.images.drain(..) {
            image.last_use.set(usage);
        }
    }

    /// Declares that `buffer` is used as `usage` from here on; records the
    /// barrier its last use needs. Inside a rendering pass no barrier can be
    /// recorded, so a use that needs one there is an error.
    fn use_buffer(&mut self, buffer: &'r Buffer, usage: BufferUse) -> Result<()> {
        self.check_owner(&buffer.ctx, "a buffer")?;
        let from = buffer.last_use.get();
        if let Some(barrier) = sync::buffer_barrier(buffer.raw, from, usage) {
            if self.rendering.is_some() {
                return Err(Error::Usage(format!(
                    "a buffer last used as {from:?} is used as {usage:?} inside a rendering pass: use it before `begin`"
                )));
            }
            let barriers = [barrier];
            let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barriers);
            // SAFETY: recording state, outside a rendering pass.
            unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
        }
        if from == BufferUse::Host && !self.buffers.iter().any(|b| std::ptr::eq(*b, buffer)) {
            self.buffers.push(buffer);
        }
        buffer.last_use.set(usage);
        Ok(())
    }

    /// Ends the run's recording: closes a rendering pass left open, and makes
    /// the device's writes to every buffer used visible to the host.
    #[expect(clippy::disallowed_methods, reason = "one pass's buffers")]
    pub(crate) fn finish(&mut self) {
        if let Some(rendering) = self.rendering.take() {
            // SAFETY: close a pass the caller left open so the buffer can end.
            unsafe { self.device().cmd_end_rendering(self.cmd) };
            let _ = self.end_section(Some(rendering.label()));
        }
        let barriers: Vec<_> = self
            .buffers
            .iter()
            .filter_map(|b| sync::buffer_barrier(b.raw, b.last_use.get(), BufferUse::Host))
            .collect();
        if !barriers.is_empty() {
            let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barriers);
            // SAFETY: recording state, outside a rendering pass.
            unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
        }
        for b in self.buffers.drain(..) {
            b.last_use.set(BufferUse::Host);
        }
    }

    fn device(&self) -> &ash::Device {
        &self.machine.ctx.device
    }

    /// Opens a labelled (and, with a profiler, timed) section of the run.
    fn begin_section(&mut self, label: &str) -> Result<()> {
        self.machine.sections.borrow_mut().begin(self.cmd, label)
    }

    fn end_section(&mut self, label: Option<String>) -> Result<()> {
        self.machine.sections.borrow_mut().end(self.cmd, label)
    }

    /// Declares that `image` is used as `usage` from here on; records the barrier.
    pub(crate) fn use_image(&mut self, image: &'r Image, usage: Usage) -> Result<()> {
        self.claim_image(image)?;
        let from = image.last_use.get();
        if let Some(barrier) =
            sync::image_barrier(image.raw, image.subresource_range(), from, usage)
        {
            let barriers = [barrier];
            let dep = vk::DependencyInfo::default().image_memory_barriers(&barriers);
            // SAFETY: recording into a command buffer in the recording state.
            unsafe { self.device().cmd_pipeline_barrier2(self.cmd, &dep) };
        }
        image.last_use.set(usage);
        Ok(())
    }
}

/// Refuses push constants of another size than the program's.
fn check_push(program: &str, bytes: u32, push: &[u8]) -> Result<()> {
    if push.len() == bytes as usize {
        return Ok(());
    }
    Err(Error::Usage(format!(
        "{program} takes {bytes} bytes of push constants, not {}",
        push.len()
    )))
}

/// Ends a command buffer, mapping the error.
pub(crate) fn end_commands(device: &ash::Device, cmd: vk::CommandBuffer) -> Result<()> {
    // SAFETY: the command buffer is in the recording state.
    unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")
}
