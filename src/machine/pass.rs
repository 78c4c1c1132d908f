//! Recording work for the machine: rendering into the picture's buffers, copies and
//! compute dispatches. A `Pass` records into one command buffer; `Machine::run`
//! submits it and waits.
//!
//! The file is long because every command the machine records goes through one
//! type, which tracks the open rendering pass and each resource's last use.

use ash::vk;

use super::{
    memory::{Buffer, Format, Image},
    pipelines::{
        BufferKernel, Kernel, Program, SiteShape, BUFFER_KERNEL_BINDINGS, GRAPHICS_RECORDS_BINDING,
    },
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

/// One site of [`crate::machine::Program::SiteExact`] (`glsl/site.vert`): its
/// rectangle, shape words, weights, kind and id.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SiteInstance {
    /// (min x, min y, max x, max y) in picture pixels.
    pub rect: [f32; 4],
    /// shape0 and shape1 as `glsl/site_distance.glsl` reads them.
    pub shape: [f32; 8],
    /// (1 / (frame scale * m), a - the smallest a).
    pub weights: [f32; 2],
    /// Kind (0 point, 1 segment, 2 circle, 3 arc) and site id.
    pub kind_id: [u32; 2],
}

/// One instance of [`crate::machine::Program::SiteExactBatch`]
/// (`glsl/site_batch.vert`): up to eight sites of one shape drawn as one
/// rectangle that covers all of theirs, or up to four arcs, whose shapes take
/// eight words. Unused slots repeat a used one.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SiteBatch {
    /// (min x, min y, max x, max y) in picture pixels.
    pub rect: [f32; 4],
    /// The first four shape words of each site ([`SiteInstance::shape`]); arc
    /// k's eight in `shapes[2 k]` and `shapes[2 k + 1]`.
    pub shapes: [[f32; 4]; 8],
    /// Each site's [`SiteInstance::weights`].
    pub weights: [[f32; 2]; 8],
    pub ids: [u32; 8],
}

/// Push constants of the cone programs (`glsl/common.glsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConePush {
    /// Size of the target in pixels.
    pub picture_size: [f32; 2],
    /// The picture pixel shown at the target's pixel (0, 0): a tile's origin.
    pub offset: [f32; 2],
    pub vertex_depth_scale: f32,
    pub fragment_depth_scale: f32,
    /// Length of each pixel's list of nearest sites, for the k-nearest programs
    /// (else unused).
    pub levels: u32,
    /// The distance function of exact cones, as `Metric::shader_code` gives it:
    /// kind (0 Euclidean, 1 L1, 2 L-infinity, 3 L_p) and p.
    pub metric: (u32, f32),
}

/// One cone of the programs that draw `glsl/cone.vert`: the unit mesh scaled to
/// the outer radius around the site, its corners clamped into `clip`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ConeInstance {
    /// Site x, y, outer radius and truncation radius, in picture pixels.
    pub site: [f32; 4],
    /// `(min x, min y, max x, max y)`: an exact cone's footprint is cut to this
    /// rectangle. Clamping its corners cuts an axis-aligned square exactly;
    /// other footprints, and fans (whose depth follows their corners), need a
    /// rectangle that holds them whole.
    pub clip: [f32; 4],
    pub id: u32,
}

impl ConeInstance {
    /// A cone drawn whole.
    pub fn new(id: u32, site: [f64; 2], outer_radius: f64, radius: f64) -> Self {
        Self {
            site: [site[0], site[1], outer_radius, radius].map(|v| v as f32),
            clip: [-f32::MAX, -f32::MAX, f32::MAX, f32::MAX],
            id,
        }
    }
}

/// An instanced draw of cones: `vertex_count` vertices of the unit fan mesh from
/// `first_vertex`, once per instance in `first_instance..first_instance + count`.
/// The mesh holds `[f32; 3]` unit vertices (cos, sin, h); for the programs of
/// `glsl/cone.vert` the instances are [`ConeInstance`]s.
#[derive(Clone, Copy)]
pub struct ConeDraw<'a> {
    pub mesh: &'a Buffer,
    pub first_vertex: u32,
    pub vertex_count: u32,
    pub instances: &'a Buffer,
    pub first_instance: u32,
    pub instance_count: u32,
}

/// One instance of [`Program::ConeExactBatch`]: up to eight exact cones drawn as
/// one rectangle that covers all their footprints. Unused slots repeat a used one.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ConeBatch {
    /// Pixel coordinates `(min x, min y, max x, max y)` of the rectangle.
    pub rect: [f32; 4],
    /// Site positions, two per group of four: `x0, y0, x1, y1, x2, ...`.
    pub sites: [f32; 16],
    /// Squared truncation radii.
    pub radii2: [f32; 8],
    pub ids: [u32; 8],
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

struct Rendering {
    color: Option<Format>,
    depth: Option<Format>,
    width: u32,
    height: u32,
    /// The programs drawn so far, each once, which name the pass.
    programs: Vec<Program>,
}

impl Rendering {
    /// The pass's label in a profile: `render: ConeFan+Rect`, or `render: clear`.
    fn label(&self) -> String {
        let programs: Vec<String> = self.programs.iter().map(|p| format!("{p:?}")).collect();
        if programs.is_empty() {
            "render: clear".into()
        } else {
            format!("render: {}", programs.join("+"))
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
}

impl<'m, 'r> Pass<'m, 'r> {
    pub(crate) fn new(machine: &'m Machine, cmd: vk::CommandBuffer) -> Self {
        Self {
            machine,
            cmd,
            rendering: None,
            buffers: Vec::new(),
        }
    }

    /// Declares that `buffer` is used as `usage` from here on; records the
    /// barrier its last use needs. Inside a rendering pass no barrier can be
    /// recorded, so a use that needs one there is an error.
    fn use_buffer(&mut self, buffer: &'r Buffer, usage: BufferUse) -> Result<()> {
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
    pub(crate) fn use_image(&mut self, image: &Image, usage: Usage) {
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
            if clear.color.is_some() {
                c.last_use.set(Usage::Undefined);
            }
            self.use_image(c, Usage::ColorAttachment);
        }
        if let Some(d) = target.depth_stencil {
            if clear.depth.is_some() && (clear.stencil.is_some() || !d.format().has_stencil()) {
                d.last_use.set(Usage::Undefined);
            }
            self.use_image(d, Usage::DepthStencilAttachment);
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

    /// Binds the pipeline for `program` and `state` and sets the per-draw state;
    /// `metric` is the kind of distance function the draw pushes (0 when none).
    fn bind(
        &mut self,
        program: Program,
        metric: u32,
        state: &RasterState,
        params: &DrawParams,
    ) -> Result<()> {
        let r = self
            .rendering
            .as_ref()
            .ok_or_else(|| Error::InvalidInput("draw outside a rendering pass".into()))?;
        let pipeline = self
            .machine
            .pipelines
            .graphics(program, metric, r.color, r.depth, state)?;
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
        if !r.programs.contains(&program) {
            if let Some(r) = self.rendering.as_mut() {
                r.programs.push(program);
            }
        }
        self.machine
            .ctx
            .insert_label(self.cmd, &format!("draw {program:?}"));
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
        }
        Ok(())
    }

    fn push_graphics(&mut self, words: &[u32]) {
        // SAFETY: the layout's range covers VERTEX|FRAGMENT and at least these bytes.
        unsafe {
            self.device().cmd_push_constants(
                self.cmd,
                self.machine.pipelines.graphics_layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::cast_slice(words),
            )
        };
    }

    /// Gives the vertex and fragment shaders of the draws that follow
    /// `buffers` as storage buffers 0, 1, 2 (at most three) and `records` as
    /// storage image 3 (filled by [`Pass::upload_for_fragments`]).
    pub fn bind_fragment_buffers(
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

    /// Draws instanced cones (a "display list" translated per site, thesis §3.3).
    pub fn draw_cones(
        &mut self,
        program: Program,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
        draw: &ConeDraw<'r>,
    ) -> Result<()> {
        if !program.reads_vertex_buffers() || program == Program::Disc {
            return Err(Error::InvalidInput(
                "draw_cones needs a cone program".into(),
            ));
        }
        if draw.instance_count == 0 {
            return Ok(());
        }
        self.use_buffer(draw.mesh, BufferUse::VertexInput)?;
        self.use_buffer(draw.instances, BufferUse::VertexInput)?;
        self.bind(program, push.metric.0, state, params)?;
        self.push_cone_constants(push);
        let device = self.device();
        // SAFETY: buffers are borrowed for 'r, past the submission's end; counts
        // are within the buffers.
        unsafe {
            device.cmd_bind_vertex_buffers(
                self.cmd,
                0,
                &[draw.mesh.raw, draw.instances.raw],
                &[0, 0],
            );
            device.cmd_draw(
                self.cmd,
                draw.vertex_count,
                draw.instance_count,
                draw.first_vertex,
                draw.first_instance,
            );
        }
        Ok(())
    }

    /// Draws the lower envelope of the sites binned to screen tiles with
    /// [`Program::NearestTiles`]: one triangle over the target, the tiles and
    /// their sites read from the records image of the bound set.
    pub fn draw_nearest_tiles(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
    ) -> Result<()> {
        self.draw_over_target(Program::NearestTiles, state, params, push)
    }

    /// Draws the lower envelope of sites of `shape` (under L2, L1 or L∞) listed per screen
    /// tile with [`Program::SiteTiles`]: one triangle over the target, the tiles
    /// and their sites read from the records image of the bound set.
    pub fn draw_site_tiles(
        &mut self,
        shape: SiteShape,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
    ) -> Result<()> {
        self.draw_over_target(Program::SiteTiles(shape), state, params, push)
    }

    /// One triangle over the target with `program`, whose fragment shader reads
    /// the records image of the bound set.
    fn draw_over_target(
        &mut self,
        program: Program,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
    ) -> Result<()> {
        self.bind(program, push.metric.0, state, params)?;
        self.push_cone_constants(push);
        // SAFETY: inside a rendering pass with a bound pipeline; the fragment
        // shader reads the records image of the bound set.
        unsafe { self.device().cmd_draw(self.cmd, 3, 1, 0, 0) };
        Ok(())
    }

    /// Draws `tiles` screen tiles with [`Program::KNearestTiles`] for
    /// `push.levels` levels, whose records come from the second storage buffer of
    /// the bound set.
    pub fn draw_tiles(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
        tiles: u32,
    ) -> Result<()> {
        if tiles == 0 {
            return Ok(());
        }
        self.bind(
            Program::KNearestTiles(push.levels),
            push.metric.0,
            state,
            params,
        )?;
        self.push_cone_constants(push);
        // SAFETY: inside a rendering pass with a bound pipeline; the vertex shader
        // reads its tile records from the bound storage buffer.
        unsafe { self.device().cmd_draw(self.cmd, 6, tiles, 0, 0) };
        Ok(())
    }

    /// Draws `count` closed discs with [`Program::Disc`] from `discs`, a buffer
    /// of `[x, y, radius, value]` in the target's pixel coordinates (as placed by
    /// `push.picture_size` and `push.offset`), into a float colour target.
    pub fn draw_discs(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        push: &ConePush,
        discs: &'r Buffer,
        count: u32,
    ) -> Result<()> {
        if count == 0 {
            return Ok(());
        }
        self.use_buffer(discs, BufferUse::VertexInput)?;
        self.bind(Program::Disc, 0, state, params)?;
        self.push_cone_constants(push);
        let device = self.device();
        // SAFETY: the buffer is borrowed for 'r, past the submission's end, and
        // holds `count` instances.
        unsafe {
            device.cmd_bind_vertex_buffers(self.cmd, 0, &[discs.raw], &[0]);
            device.cmd_draw(self.cmd, 4, count, 0, 0);
        }
        Ok(())
    }

    fn push_cone_constants(&mut self, push: &ConePush) {
        let words = [
            push.picture_size[0].to_bits(),
            push.picture_size[1].to_bits(),
            push.offset[0].to_bits(),
            push.offset[1].to_bits(),
            push.vertex_depth_scale.to_bits(),
            push.fragment_depth_scale.to_bits(),
            push.levels,
            push.metric.0,
            push.metric.1.to_bits(),
        ];
        self.push_graphics(&words);
    }

    /// Draws an axis-aligned rectangle of constant depth and colour.
    pub fn draw_rect(
        &mut self,
        state: &RasterState,
        params: &DrawParams,
        rect: &RectDraw,
    ) -> Result<()> {
        self.bind(Program::Rect, 0, state, params)?;
        let r = self
            .rendering
            .as_ref()
            .map(|r| (r.width, r.height))
            .unwrap_or((1, 1));
        let v = rect.value.map(f32::to_bits);
        let words = [
            (r.0 as f32).to_bits(),
            (r.1 as f32).to_bits(),
            rect.lo[0].to_bits(),
            rect.lo[1].to_bits(),
            rect.hi[0].to_bits(),
            rect.hi[1].to_bits(),
            rect.depth.to_bits(),
            0,
            v[0],
            v[1],
            v[2],
            v[3],
        ];
        self.push_graphics(&words);
        // SAFETY: inside a rendering pass with a bound pipeline.
        unsafe { self.device().cmd_draw(self.cmd, 4, 1, 0, 0) };
        Ok(())
    }

    /// Draws the `instances` of a program that makes its own vertices (such as
    /// [`Program::SettleDisc`]): `vertex_count` vertices each, with `push` as its
    /// push constants. `gl_InstanceIndex` counts from `instances.start`.
    pub fn draw_instances(
        &mut self,
        program: Program,
        state: &RasterState,
        params: &DrawParams,
        push: &[u32],
        vertex_count: u32,
        instances: std::ops::Range<u32>,
    ) -> Result<()> {
        if program.reads_vertex_buffers() {
            return Err(Error::InvalidInput(format!(
                "{program:?} draws from vertex buffers"
            )));
        }
        if instances.is_empty() {
            return Ok(());
        }
        let metric = match program {
            Program::SettleDisc(kind) => kind,
            _ => 0,
        };
        self.bind(program, metric, state, params)?;
        self.push_graphics(push);
        // SAFETY: inside a rendering pass with a bound pipeline that reads no
        // vertex buffers.
        unsafe {
            self.device().cmd_draw(
                self.cmd,
                vertex_count,
                instances.len() as u32,
                0,
                instances.start,
            )
        };
        Ok(())
    }

    /// Records `kernel` over `invocations` invocations (one dimension) with
    /// `buffers` as its storage buffers 0, 1, … (at most
    /// [`BUFFER_KERNEL_BINDINGS`]), ordered after
    /// earlier host writes, copies and dispatches, and visible to the host and to
    /// later work afterwards.
    pub fn dispatch(
        &mut self,
        kernel: BufferKernel,
        buffers: &[&'r Buffer],
        invocations: u32,
        push: &[u32],
    ) -> Result<()> {
        self.dispatch_grid(kernel, buffers, (invocations, 1), push)
    }

    /// Dispatches `kernel` over a `width` x `height` grid of invocations (rows
    /// of workgroups): a kernel finds its place in `gl_GlobalInvocationID.xy`,
    /// for example a column and a strip of rows.
    pub fn dispatch_grid(
        &mut self,
        kernel: BufferKernel,
        buffers: &[&'r Buffer],
        (width, height): (u32, u32),
        push: &[u32],
    ) -> Result<()> {
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
        self.begin_section(&format!("dispatch {kernel:?}"))?;
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
        push: &[u32],
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
            device.cmd_push_constants(
                self.cmd,
                layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::cast_slice(push),
            );
            device.cmd_dispatch(self.cmd, groups.0, groups.1, 1);
        }
    }

    /// Copies all of `image` (for depth/stencil: its depth) into `buffer` from byte
    /// `offset`, row-major, for fragment shaders of later passes to read.
    pub fn feed_fragment_buffer(
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
    pub fn copy_depth_from_buffer(
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
    pub fn upload_for_fragments(&mut self, buffer: &'r Buffer, image: &'r Image) -> Result<()> {
        let bytes = image.width() as u64 * image.height() as u64 * image.format().texel_bytes();
        if image.format().is_depth() || bytes > buffer.size() {
            return Err(Error::InvalidInput(
                "an upload needs a colour image and a buffer that holds all of it".into(),
            ));
        }
        self.record_upload(buffer, 0, image, vk::ImageAspectFlags::COLOR)?;
        self.use_image(image, Usage::FragmentRead);
        Ok(())
    }

    /// Records the copy of `buffer` from byte `offset` into `aspect` of all of
    /// `image`.
    fn record_upload(
        &mut self,
        buffer: &'r Buffer,
        offset: u64,
        image: &Image,
        aspect: vk::ImageAspectFlags,
    ) -> Result<()> {
        self.use_buffer(buffer, BufferUse::TransferSrc)?;
        self.use_image(image, Usage::TransferDst);
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
        image: &Image,
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
    pub fn copy_stencil_to_buffer(
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
        image: &Image,
        rect: PixelRect,
        buffer: &'r Buffer,
        offset: u64,
        aspect: vk::ImageAspectFlags,
    ) -> Result<()> {
        self.use_buffer(buffer, BufferUse::TransferDst)?;
        self.use_image(image, Usage::TransferSrc);
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
        self.use_image(image, Usage::ComputeRead);
        let mut words = vec![rect.x, rect.y, rect.width, rect.height];
        words.extend_from_slice(extra_push);
        let layout = self.machine.pipelines.compute_layout;
        self.begin_section(&format!("reduce {kernel:?}"))?;
        self.record_dispatch(
            pipeline,
            layout,
            set,
            &words,
            kernel.groups(rect.width, rect.height),
        );
        self.end_section(None)
    }
}

/// Ends a command buffer, mapping the error.
pub(crate) fn end_commands(device: &ash::Device, cmd: vk::CommandBuffer) -> Result<()> {
    // SAFETY: the command buffer is in the recording state.
    unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")
}
