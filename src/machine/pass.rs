//! Recording work for the machine: rendering into the picture's buffers, copies and
//! compute dispatches. A `Pass` records into one command buffer; `Machine::run`
//! submits it and waits.
//!
//! The file is long because every command the machine records goes through one
//! type, which tracks the open rendering pass and each resource's last use.

use std::sync::Arc;

use ash::vk;

use super::{
    context::Context,
    memory::{Buffer, Format, Image},
    pipelines::{Kernel, BUFFER_KERNEL_BINDINGS, GRAPHICS_RECORDS_BINDING},
    program::{ComputeProgram, Fragments, GraphicsProgram, Output, Topology},
    shaders,
    state::{DrawParams, RasterState},
    sync::{self, BufferUse, Usage},
    Machine,
};
use crate::error::{Error, Result, VkContext};

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
            return Err(Error::InvalidInput(format!(
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
                return Err(Error::InvalidInput(format!(
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

    /// Begins rendering into `target`, clearing what `clear` names.
    pub fn begin(&mut self, target: Target<'r>, clear: Clear) -> Result<()> {
        if self.rendering.is_some() {
            return Err(Error::InvalidInput(
                "a rendering pass is already open".into(),
            ));
        }
        let (width, height) = match (target.color, target.depth_stencil) {
            (Some(c), _) => (c.width(), c.height()),
            (None, Some(d)) => (d.width(), d.height()),
            (None, None) => {
                return Err(Error::InvalidInput(
                    "a rendering pass needs a target".into(),
                ))
            }
        };
        if let Some(d) = target.depth_stencil {
            if d.width() != width || d.height() != height || !d.format().is_depth() {
                return Err(Error::InvalidInput(
                    "depth/stencil target must be a DepthStencil image of the colour target's size"
                        .into(),
                ));
            }
        }
        if target.color.is_some_and(|c| c.format().is_depth()) {
            return Err(Error::InvalidInput(
                "colour target has a depth format".into(),
            ));
        }
        self.begin_section(&format!("render {width}x{height}"))?;
        if let Some(c) = target.color {
            self.claim_image(c)?;
            if clear.color.is_some() {
                c.last_use.set(Usage::Undefined);
            }
            self.use_image(c, Usage::ColorAttachment)?;
        }
        if let Some(d) = target.depth_stencil {
            self.claim_image(d)?;
            if clear.depth.is_some() && (clear.stencil.is_some() || !d.format().has_stencil()) {
                d.last_use.set(Usage::Undefined);
            }
            self.use_image(d, Usage::DepthStencilAttachment)?;
        }
        let color_clear = match clear.color {
            Some(ClearColor::Uint(v)) => vk::ClearValue {
                color: vk::ClearColorValue { uint32: v },
            },
            Some(ClearColor::Float(v)) => vk::ClearValue {
                color: vk::ClearColorValue { float32: v },
            },
            None => vk::ClearValue::default(),
        };
        let load = |c: bool| {
            if c {
                vk::AttachmentLoadOp::CLEAR
            } else {
                vk::AttachmentLoadOp::LOAD
            }
        };
        let color_attachments: Vec<vk::RenderingAttachmentInfo> = target
            .color
            .iter()
            .map(|c| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(c.view)
                    .image_layout(sync::layout(Usage::ColorAttachment))
                    .load_op(load(clear.color.is_some()))
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(color_clear)
            })
            .collect();
        let ds_clear = vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: clear.depth.unwrap_or(1.0),
                stencil: clear.stencil.unwrap_or(0).into(),
            },
        };
        let ds = target.depth_stencil.map(|d| {
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view)
                .image_layout(sync::layout(Usage::DepthStencilAttachment))
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(ds_clear)
        });
        let depth_attachment = ds.map(|a| a.load_op(load(clear.depth.is_some())));
        let stencil_attachment = ds.map(|a| a.load_op(load(clear.stencil.is_some())));
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D { width, height },
        };
        let mut info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachments);
        if let Some(d) = depth_attachment.as_ref() {
            info = info.depth_attachment(d);
        }
        let has_stencil = target
            .depth_stencil
            .is_some_and(|d| d.format().has_stencil());
        if let (Some(s), true) = (stencil_attachment.as_ref(), has_stencil) {
            info = info.stencil_attachment(s);
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: width as f32,
            height: height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: attachments are in the layouts declared above; the info's pointers
        // refer to locals alive during the call.
        unsafe {
            self.device().cmd_begin_rendering(self.cmd, &info);
            self.device().cmd_set_viewport(self.cmd, 0, &[viewport]);
        }
        self.rendering = Some(Rendering {
            color: target.color.map(|c| c.format()),
            depth: target.depth_stencil.map(|d| d.format()),
            width,
            height,
            programs: Vec::new(),
        });
        Ok(())
    }

    /// Ends the rendering pass begun with [`Pass::begin`].
    pub fn end(&mut self) -> Result<()> {
        let Some(rendering) = self.rendering.take() else {
            return Err(Error::InvalidInput("no rendering pass is open".into()));
        };
        // SAFETY: a rendering pass was begun in this command buffer.
        unsafe { self.device().cmd_end_rendering(self.cmd) };
        self.end_section(Some(rendering.label()))
    }

    /// Binds the pipeline for `program`'s build for `variant` and `state`, sets
    /// the per-draw state and pushes `push`.
    fn bind(
        &mut self,
        program: &'static GraphicsProgram,
        variant: u32,
        state: &RasterState,
        params: &DrawParams,
        push: &[u8],
    ) -> Result<()> {
        let r = self
            .rendering
            .as_ref()
            .ok_or_else(|| Error::InvalidInput("draw outside a rendering pass".into()))?;
        check_push(program.name, program.push_bytes, push)?;
        let fragment = program.fragment(variant).ok_or_else(|| {
            Error::InvalidInput(format!(
                "{} has no build for variant {variant}",
                program.name
            ))
        })?;
        let uint_target = r.color == Some(Format::R32Uint);
        let fits = match fragment.output {
            Output::None => true,
            Output::Uint => r.color.is_none() || uint_target,
            Output::Float => r.color.is_none() || !uint_target,
        };
        if !fits {
            return Err(Error::InvalidInput(format!(
                "{} writes {} values and needs a {} colour target (or none)",
                program.name,
                if uint_target { "float" } else { "integer" },
                if uint_target { "float" } else { "R32Uint" },
            )));
        }
        let pipeline = self
            .machine
            .pipelines
            .graphics(program, fragment, r.color, r.depth, state)?;
        let [x, y, w, h] = params.scissor.unwrap_or([0, 0, r.width, r.height]);
        let x = x.min(r.width);
        let y = y.min(r.height);
        let scissor = vk::Rect2D {
            offset: vk::Offset2D {
                x: x as i32,
                y: y as i32,
            },
            extent: vk::Extent2D {
                width: w.min(r.width - x),
                height: h.min(r.height - y),
            },
        };
        if !r.programs.contains(&program.name) {
            if let Some(r) = self.rendering.as_mut() {
                r.programs.push(program.name);
            }
        }
        self.machine
            .ctx
            .insert_label(self.cmd, &format!("draw {}", program.name));
        let device = self.device();
        // SAFETY: inside a rendering pass whose formats match the pipeline's.
        unsafe {
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            device.cmd_set_scissor(self.cmd, 0, &[scissor]);
            device.cmd_set_stencil_reference(
                self.cmd,
                vk::StencilFaceFlags::FRONT_AND_BACK,
                params.stencil_reference.into(),
            );
            device.cmd_set_blend_constants(self.cmd, &params.blend_constant);
            if !push.is_empty() {
                // The program's push bytes fit the layout's range (checked
                // when it was declared).
                device.cmd_push_constants(
                    self.cmd,
                    self.machine.pipelines.graphics_layout,
                    vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                    0,
                    push,
                );
            }
        }
        Ok(())
    }

    /// Gives the vertex and fragment shaders of the draws that follow
    /// `buffers` as storage buffers 0, 1, 2 (at most three) and `records` as
    /// storage image 3 (filled by [`Pass::upload_for_fragments`]).
    pub(crate) fn bind_fragment_buffers(
        &mut self,
        buffers: &[&'r Buffer],
        records: Option<&'r Image>,
    ) -> Result<()> {
        if (buffers.is_empty() && records.is_none()) || buffers.len() > 3 {
            return Err(Error::InvalidInput(
                "graphics programs take up to three storage buffers and a records image, at least one of them".into(),
            ));
        }
        if self.rendering.is_some() {
            return Err(Error::InvalidInput(
                "bind fragment buffers before `begin`, where their barriers can be recorded".into(),
            ));
        }
        for &buffer in buffers {
            self.use_buffer(buffer, BufferUse::GraphicsStorage)?;
        }
        let pipelines = &self.machine.pipelines;
        let set = self.machine.descriptors.set(
            pipelines.graphics_set_layout,
            records.map(|image| (image, GRAPHICS_RECORDS_BINDING)),
            0,
            buffers,
        )?;
        let layout = pipelines.graphics_layout;
        // SAFETY: the set matches the graphics layout's set 0 and lives until
        // the run has completed.
        unsafe {
            self.device().cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                layout,
                0,
                &[set],
                &[],
            )
        };
        Ok(())
    }

    /// Draws `draw.program` (thesis §1.5: a set of triangles entering the
    /// pipeline) with `state`: its vertex buffers bound in order, the vertices
    /// and instances of `draw`'s ranges.
    pub fn draw(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        draw: &Draw<'_, 'r>,
    ) -> Result<()> {
        let program = draw.program;
        if draw.vertex_buffers.len() != program.vertex_buffers.len() {
            return Err(Error::InvalidInput(format!(
                "{} reads {} vertex buffers, not {}",
                program.name,
                program.vertex_buffers.len(),
                draw.vertex_buffers.len()
            )));
        }
        if draw.vertices.is_empty() || draw.instances.is_empty() {
            return Ok(());
        }
        for &buffer in draw.vertex_buffers {
            self.use_buffer(buffer, BufferUse::VertexInput)?;
        }
        self.bind(program, draw.variant, state, params, draw.push)?;
        let device = self.device();
        // SAFETY: inside a rendering pass with a bound pipeline that reads these
        // buffers, borrowed for 'r, past the submission's end.
        unsafe {
            for (binding, buffer) in (0u32..).zip(draw.vertex_buffers) {
                device.cmd_bind_vertex_buffers(self.cmd, binding, &[buffer.raw], &[0]);
            }
            device.cmd_draw(
                self.cmd,
                draw.vertices.len() as u32,
                draw.instances.len() as u32,
                draw.vertices.start,
                draw.instances.start,
            );
        }
        Ok(())
    }

    /// Draws an axis-aligned rectangle of constant depth and colour.
    pub fn draw_rect(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        rect: &RectDraw,
    ) -> Result<()> {
        let (width, height) = self
            .rendering
            .as_ref()
            .map(|r| (r.width, r.height))
            .unwrap_or((1, 1));
        let uint_target = self
            .rendering
            .as_ref()
            .is_some_and(|r| r.color == Some(Format::R32Uint));
        let push = RectPush {
            size: [width as f32, height as f32],
            lo: rect.lo,
            hi: rect.hi,
            depth: rect.depth,
            pad: 0,
            value: rect.value,
        };
        self.draw(
            state,
            params,
            &Draw {
                program: &RECT,
                // rect.frag's builds: UINT, FLOAT.
                variant: if uint_target { 0 } else { 1 },
                push: bytemuck::bytes_of(&push),
                vertex_buffers: &[],
                vertices: 0..4,
                instances: 0..1,
            },
        )
    }

    /// Records `kernel` over `invocations` invocations (one dimension) with
    /// `buffers` as its storage buffers 0, 1, … (at most
    /// [`BUFFER_KERNEL_BINDINGS`]), ordered after
    /// earlier host writes, copies and dispatches, and visible to the host and to
    /// later work afterwards.
    pub fn dispatch(
        &mut self,
        kernel: &'static ComputeProgram,
        buffers: &[&'r Buffer],
        invocations: u32,
        push: &[u8],
    ) -> Result<()> {
        self.dispatch_grid(kernel, buffers, (invocations, 1), push)
    }

    /// Dispatches `kernel` over a `width` x `height` grid of invocations (rows
    /// of workgroups): a kernel finds its place in `gl_GlobalInvocationID.xy`,
    /// for example a column and a strip of rows.
    pub fn dispatch_grid(
        &mut self,
        kernel: &'static ComputeProgram,
        buffers: &[&'r Buffer],
        (width, height): (u32, u32),
        push: &[u8],
    ) -> Result<()> {
        check_push(kernel.name, kernel.push_bytes, push)?;
        if buffers.is_empty() || buffers.len() > BUFFER_KERNEL_BINDINGS as usize {
            return Err(Error::InvalidInput(format!(
                "compute kernels take one to {BUFFER_KERNEL_BINDINGS} storage buffers"
            )));
        }
        if self.rendering.is_some() {
            return Err(Error::InvalidInput(
                "dispatch inside a rendering pass".into(),
            ));
        }
        if width == 0 || height == 0 {
            return Ok(());
        }
        let groups = (width.div_ceil(kernel.group()), height);
        if groups.0 > MAX_GROUPS || groups.1 > MAX_GROUPS {
            return Err(Error::InvalidInput(format!(
                "a {width}x{height} grid of invocations needs more than {MAX_GROUPS} workgroups along a side: split it"
            )));
        }
        for &buffer in buffers {
            self.use_buffer(buffer, BufferUse::ComputeStorage)?;
        }
        let pipelines = &self.machine.pipelines;
        let pipeline = pipelines.buffer_compute(kernel)?;
        let set = self
            .machine
            .descriptors
            .set(pipelines.buffer_set_layout, None, 0, buffers)?;
        let layout = pipelines.buffer_layout;
        self.begin_section(&format!("dispatch {}", kernel.name))?;
        self.record_dispatch(pipeline, layout, set, push, groups);
        self.end_section(None)
    }

    /// Records a compute dispatch; its buffers' and images' barriers are
    /// already recorded.
    fn record_dispatch(
        &mut self,
        pipeline: vk::Pipeline,
        layout: vk::PipelineLayout,
        set: vk::DescriptorSet,
        push: &[u8],
        groups: (u32, u32),
    ) {
        let device = self.device();
        // SAFETY: recording state outside a rendering pass; the set matches the
        // layout and lives until the run has completed; push fits the layout's range.
        unsafe {
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            device.cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::COMPUTE,
                layout,
                0,
                &[set],
                &[],
            );
            device.cmd_push_constants(self.cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, push);
            device.cmd_dispatch(self.cmd, groups.0, groups.1, 1);
        }
    }

    /// Copies all of `image` (for depth/stencil: its depth) into `buffer` from byte
    /// `offset`, row-major, for fragment shaders of later passes to read.
    pub(crate) fn feed_fragment_buffer(
        &mut self,
        image: &'r Image,
        buffer: &'r Buffer,
        offset: u64,
    ) -> Result<()> {
        let bytes = image.width() as u64 * image.height() as u64 * 4;
        if image.format().texel_bytes() != 4 || offset + bytes > buffer.size() {
            return Err(Error::InvalidInput(
                "fragment buffer too small for the image".into(),
            ));
        }
        self.record_copy(image, PixelRect::of(image), buffer, offset)
    }

    /// Fills the depth of all of `image` from `buffer` (from byte `offset`, one
    /// `f32` in [0, 1] per pixel, row-major), after the dispatches that wrote it:
    /// a depth picture computed by a kernel, for the graphics passes that follow.
    pub(crate) fn copy_depth_from_buffer(
        &mut self,
        buffer: &'r Buffer,
        offset: u64,
        image: &'r Image,
    ) -> Result<()> {
        let bytes = image.width() as u64 * image.height() as u64 * 4;
        if !image.format().is_depth() || offset + bytes > buffer.size() {
            return Err(Error::InvalidInput(
                "a depth upload needs a depth image and a float per pixel".into(),
            ));
        }
        self.record_upload(buffer, offset, image, vk::ImageAspectFlags::DEPTH)
    }

    /// Fills all of a colour `image` from the start of `buffer` (texels
    /// row-major, as the host wrote them) for the fragment shaders that follow
    /// to read with `imageLoad` (outside a rendering pass).
    pub(crate) fn upload_for_fragments(
        &mut self,
        buffer: &'r Buffer,
        image: &'r Image,
    ) -> Result<()> {
        let bytes = image.width() as u64 * image.height() as u64 * image.format().texel_bytes();
        if image.format().is_depth() || bytes > buffer.size() {
            return Err(Error::InvalidInput(
                "an upload needs a colour image and a buffer that holds all of it".into(),
            ));
        }
        self.record_upload(buffer, 0, image, vk::ImageAspectFlags::COLOR)?;
        self.use_image(image, Usage::FragmentRead)?;
        Ok(())
    }

    /// Records the copy of `buffer` from byte `offset` into `aspect` of all of
    /// `image`.
    fn record_upload(
        &mut self,
        buffer: &'r Buffer,
        offset: u64,
        image: &'r Image,
        aspect: vk::ImageAspectFlags,
    ) -> Result<()> {
        self.use_buffer(buffer, BufferUse::TransferSrc)?;
        self.use_image(image, Usage::TransferDst)?;
        self.begin_section("upload")?;
        let region = vk::BufferImageCopy::default()
            .buffer_offset(offset)
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(aspect)
                    .layer_count(1),
            )
            .image_extent(vk::Extent3D {
                width: image.width(),
                height: image.height(),
                depth: 1,
            });
        // SAFETY: image in TRANSFER_DST layout, buffer large enough (checked).
        unsafe {
            self.device().cmd_copy_buffer_to_image(
                self.cmd,
                buffer.raw,
                image.raw,
                sync::layout(Usage::TransferDst),
                &[region],
            )
        };
        self.end_section(None)
    }

    /// Copies `rect` of `image` (for depth/stencil: its depth) into `buffer`,
    /// row-major, tightly packed.
    pub fn copy_to_buffer(
        &mut self,
        image: &'r Image,
        rect: PixelRect,
        buffer: &'r Buffer,
    ) -> Result<()> {
        rect.check_inside(image)?;
        let bytes = rect.width as u64 * rect.height as u64 * image.format().texel_bytes();
        if bytes > buffer.size() {
            return Err(Error::InvalidInput("readback buffer too small".into()));
        }
        self.record_copy(image, rect, buffer, 0)
    }

    /// Records the copy of `rect` of `image` into `buffer` at byte `offset`.
    fn record_copy(
        &mut self,
        image: &'r Image,
        rect: PixelRect,
        buffer: &'r Buffer,
        offset: u64,
    ) -> Result<()> {
        let aspect = if image.format().is_depth() {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        self.record_aspect_copy(image, rect, buffer, offset, aspect)
    }

    /// Copies the stencil of `rect` of a depth/stencil `image` into `buffer`, one
    /// byte per pixel, row-major, tightly packed.
    pub(crate) fn copy_stencil_to_buffer(
        &mut self,
        image: &'r Image,
        rect: PixelRect,
        buffer: &'r Buffer,
    ) -> Result<()> {
        rect.check_inside(image)?;
        if !image.format().has_stencil() || rect.width as u64 * rect.height as u64 > buffer.size() {
            return Err(Error::InvalidInput(
                "stencil readback needs a DepthStencil image and room for a byte per pixel".into(),
            ));
        }
        self.record_aspect_copy(image, rect, buffer, 0, vk::ImageAspectFlags::STENCIL)
    }

    fn record_aspect_copy(
        &mut self,
        image: &'r Image,
        rect: PixelRect,
        buffer: &'r Buffer,
        offset: u64,
        aspect: vk::ImageAspectFlags,
    ) -> Result<()> {
        self.use_buffer(buffer, BufferUse::TransferDst)?;
        self.use_image(image, Usage::TransferSrc)?;
        self.begin_section("copy to buffer")?;
        let region = vk::BufferImageCopy::default()
            .buffer_offset(offset)
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(aspect)
                    .layer_count(1),
            )
            .image_offset(vk::Offset3D {
                x: rect.x as i32,
                y: rect.y as i32,
                z: 0,
            })
            .image_extent(vk::Extent3D {
                width: rect.width,
                height: rect.height,
                depth: 1,
            });
        // SAFETY: image in TRANSFER_SRC layout, buffer large enough (checked).
        unsafe {
            self.device().cmd_copy_image_to_buffer(
                self.cmd,
                image.raw,
                sync::layout(Usage::TransferSrc),
                buffer.raw,
                &[region],
            )
        };
        self.end_section(None)
    }

    /// Records a reduction kernel over `rect` of `image` writing into `result`
    /// (which the caller has initialised). `push` follows the rect's origin/extent.
    pub(crate) fn reduce(
        &mut self,
        kernel: Kernel,
        image: &'r Image,
        rect: PixelRect,
        result: &'r Buffer,
        extra_push: &[u32],
    ) -> Result<()> {
        rect.check_inside(image)?;
        let pipeline = self.machine.pipelines.compute(kernel, image.format())?;
        self.use_buffer(result, BufferUse::ComputeStorage)?;
        let set = self.machine.descriptors.set(
            self.machine.pipelines.compute_set_layout,
            Some((image, 0)),
            1,
            &[result],
        )?;
        self.use_image(image, Usage::ComputeRead)?;
        let mut words = vec![rect.x, rect.y, rect.width, rect.height];
        words.extend_from_slice(extra_push);
        let layout = self.machine.pipelines.compute_layout;
        self.begin_section(&format!("reduce {kernel:?}"))?;
        self.record_dispatch(
            pipeline,
            layout,
            set,
            bytemuck::cast_slice(&words),
            kernel.groups(rect.width, rect.height),
        );
        self.end_section(None)
    }
}

/// Refuses push constants of another size than the program's.
fn check_push(program: &str, bytes: u32, push: &[u8]) -> Result<()> {
    if push.len() == bytes as usize {
        return Ok(());
    }
    Err(Error::InvalidInput(format!(
        "{program} takes {bytes} bytes of push constants, not {}",
        push.len()
    )))
}

/// Ends a command buffer, mapping the error.
pub(crate) fn end_commands(device: &ash::Device, cmd: vk::CommandBuffer) -> Result<()> {
    // SAFETY: the command buffer is in the recording state.
    unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")
}
