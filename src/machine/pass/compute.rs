//! Compute dispatches and the reductions built on them.

use super::*;

impl<'m, 'r> Pass<'m, 'r> {
    /// Records `kernel` over `invocations` invocations (one dimension) with
    /// `buffers` as its storage buffers 0, 1, … (one per extent the kernel
    /// declares, each as long as its extent says), ordered after earlier
    /// host writes, copies and dispatches, and visible to the host and to
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
        self.check_extents(kernel, buffers, push)?;
        if self.rendering.is_some() {
            return Err(Error::Usage("dispatch inside a rendering pass".into()));
        }
        if width == 0 || height == 0 {
            return Ok(());
        }
        let groups = (width.div_ceil(kernel.group()), height);
        if groups.0 > MAX_GROUPS || groups.1 > MAX_GROUPS {
            return Err(Error::out_of_range(format!(
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

    /// Refuses a dispatch whose buffers are fewer or more than the kernel's,
    /// or shorter than its extents say it reaches, or whose kernel indexes a
    /// buffer by data on a device that does not bound such accesses.
    fn check_extents(
        &self,
        kernel: &ComputeProgram,
        buffers: &[&Buffer],
        push: &[u8],
    ) -> Result<()> {
        if buffers.len() != kernel.extents.len() {
            return Err(Error::Usage(format!(
                "{} takes {} storage buffers, not {}",
                kernel.name,
                kernel.extents.len(),
                buffers.len()
            )));
        }
        let mut words = [0u32; (COMPUTE_PUSH_BYTES / 4) as usize];
        for (word, bytes) in words.iter_mut().zip(push.chunks_exact(4)) {
            *word = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        }
        for (binding, (buffer, extent)) in buffers.iter().zip(kernel.extents).enumerate() {
            match *extent {
                Extent::Push(reach) => {
                    let needed = reach(&words);
                    if buffer.size() < needed {
                        return Err(Error::Usage(format!(
                            "{} reaches {needed} bytes into buffer {binding}, which holds {}",
                            kernel.name,
                            buffer.size()
                        )));
                    }
                }
                Extent::ByData if !self.machine.has_robust_buffer_access() => {
                    return Err(Error::Usage(format!(
                        "{} indexes buffer {binding} by what the buffers hold, and {} does not \
                         bound such accesses (robustBufferAccess)",
                        kernel.name,
                        self.machine.device_name()
                    )));
                }
                Extent::ByData => {}
            }
        }
        Ok(())
    }

    /// Records a compute dispatch; its buffers' and images' barriers are
    /// already recorded.
    pub(super) fn record_dispatch(
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
        let mut words = Vec::from([rect.x, rect.y, rect.width, rect.height]);
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
