//! Rendering: beginning and ending a pass on a target, binding a program's
//! pipeline and buffers, and drawing.

use super::*;
use crate::memory::Gather;

impl<'m, 'r> Pass<'m, 'r> {
    /// Begins rendering into `target`, clearing what `clear` names.
    pub fn begin(&mut self, target: Target<'r>, clear: Clear) -> Result<()> {
        if self.rendering.is_some() {
            return Err(Error::Usage("a rendering pass is already open".into()));
        }
        let (width, height) = match (target.color, target.depth_stencil) {
            (Some(c), _) => (c.width(), c.height()),
            (None, Some(d)) => (d.width(), d.height()),
            (None, None) => return Err(Error::Usage("a rendering pass needs a target".into())),
        };
        if let Some(d) = target.depth_stencil {
            if d.width() != width || d.height() != height || !d.format().is_depth() {
                return Err(Error::Usage(
                    "depth/stencil target must be a DepthStencil image of the colour target's size"
                        .into(),
                ));
            }
        }
        if target.color.is_some_and(|c| c.format().is_depth()) {
            return Err(Error::Usage("colour target has a depth format".into()));
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
            .gather("color attachments")?;
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
            return Err(Error::Usage("no rendering pass is open".into()));
        };
        // SAFETY: a rendering pass was begun in this command buffer.
        unsafe { self.device().cmd_end_rendering(self.cmd) };
        self.end_section(Some(rendering.label()))
    }

    /// Binds the pipeline for `program`'s build for `variant` and `state`, sets
    /// the per-draw state and pushes `push`.
    pub(super) fn bind(
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
            .ok_or_else(|| Error::Usage("draw outside a rendering pass".into()))?;
        check_push(program.name, program.push_bytes, push)?;
        let fragment = program.fragment(variant).ok_or_else(|| {
            Error::Usage(format!(
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
            return Err(Error::Usage(format!(
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
            return Err(Error::Usage("graphics programs take up to three storage buffers and a records image, at least one of them".into(),));
        }
        if self.rendering.is_some() {
            return Err(Error::Usage(
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
            return Err(Error::Usage(format!(
                "{} reads {} vertex buffers, not {}",
                program.name,
                program.vertex_buffers.len(),
                draw.vertex_buffers.len()
            )));
        }
        if draw.vertices.is_empty() || draw.instances.is_empty() {
            return Ok(());
        }
        // The vertex input reads element `end - 1` of each buffer: past its
        // end is undefined behaviour, which safe code must not reach.
        for (layout, buffer) in program.vertex_buffers.iter().zip(draw.vertex_buffers) {
            let end = match layout.per_instance {
                true => draw.instances.end,
                false => draw.vertices.end,
            };
            let needed = u64::from(end) * u64::from(layout.stride);
            if needed > buffer.size() {
                return Err(Error::Usage(format!(
                    "{} reads {needed} bytes of a vertex buffer of {} ({end} {} of {} bytes)",
                    program.name,
                    buffer.size(),
                    if layout.per_instance {
                        "instances"
                    } else {
                        "vertices"
                    },
                    layout.stride
                )));
            }
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
}
