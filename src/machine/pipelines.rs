//! The pipeline cache: each distinct (program, fragment build, targets, raster
//! state) becomes one `VkPipeline`, created on first use from the program's
//! declaration (`program.rs`).

use crate::memory::Gather;
use std::{cell::RefCell, collections::HashMap, path::Path, sync::Arc};

use ash::vk;

use super::{
    cache::PipelineCache,
    context::Context,
    conv,
    memory::Format,
    program::{ComputeProgram, GraphicsProgram, Shader, COMPUTE_PUSH_BYTES, GRAPHICS_PUSH_BYTES},
    shaders,
    state::{ColorUpdate, RasterState},
};
use crate::error::{Error, Result, VkContext};

/// Compute kernels of the reductions (thesis §1.7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Kernel {
    MinMax,
    Histogram,
}

impl Kernel {
    /// Workgroups covering a `width` x `height` rectangle (must match the shaders'
    /// local sizes: minmax runs 64 columns x 64-row strips, histogram 16 x 16).
    pub fn groups(self, width: u32, height: u32) -> (u32, u32) {
        match self {
            Kernel::MinMax => (width.div_ceil(64), height.div_ceil(64)),
            Kernel::Histogram => (width.div_ceil(16), height.div_ceil(16)),
        }
    }
}

/// Storage buffers a kernel may take in [`crate::machine::Pass::dispatch`];
/// a kernel uses those it declares.
pub const BUFFER_KERNEL_BINDINGS: u32 = 8;

/// The graphics layout's storage image (after its three storage buffers):
/// records fragment shaders read with `imageLoad`.
pub(crate) const GRAPHICS_RECORDS_BINDING: u32 = 3;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct GraphicsKey {
    /// The program's address: programs are `static`s.
    program: usize,
    /// The fragment build's index in `shaders::ALL`.
    fragment: usize,
    color: Option<Format>,
    depth: Option<Format>,
    state: RasterState,
}

pub(crate) struct Pipelines {
    ctx: Arc<Context>,
    pub cache: PipelineCache,
    /// One module per build, in the order of `shaders::ALL`, made when a
    /// pipeline first needs it (null until then): a machine uses few of them.
    modules: RefCell<Vec<vk::ShaderModule>>,
    pub graphics_layout: vk::PipelineLayout,
    /// Three storage buffers for vertex and fragment shaders (bindings 0, 1 and 2
    /// of set 0) and a storage image of records for fragment shaders (binding
    /// 3); a program uses those it declares.
    pub graphics_set_layout: vk::DescriptorSetLayout,
    pub compute_set_layout: vk::DescriptorSetLayout,
    pub compute_layout: vk::PipelineLayout,
    /// [`BUFFER_KERNEL_BINDINGS`] storage buffers for compute kernels.
    pub buffer_set_layout: vk::DescriptorSetLayout,
    pub buffer_layout: vk::PipelineLayout,
    graphics: RefCell<HashMap<GraphicsKey, vk::Pipeline>>,
    compute: RefCell<HashMap<(Kernel, Format), vk::Pipeline>>,
    /// By the kernel's address: kernels are `static`s.
    buffer_kernels: RefCell<HashMap<usize, vk::Pipeline>>,
}

impl Pipelines {
    pub fn new(ctx: &Arc<Context>, cache_folder: Option<&Path>) -> Result<Self> {
        let mut pipelines = Self {
            ctx: ctx.clone(),
            cache: PipelineCache::open(ctx, cache_folder)?,
            modules: RefCell::new(
                shaders::ALL
                    .iter()
                    .map(|_| vk::ShaderModule::null())
                    .gather("modules")?,
            ),
            graphics_layout: vk::PipelineLayout::null(),
            graphics_set_layout: vk::DescriptorSetLayout::null(),
            compute_set_layout: vk::DescriptorSetLayout::null(),
            compute_layout: vk::PipelineLayout::null(),
            buffer_set_layout: vk::DescriptorSetLayout::null(),
            buffer_layout: vk::PipelineLayout::null(),
            graphics: RefCell::default(),
            compute: RefCell::default(),
            buffer_kernels: RefCell::default(),
        };
        let device = &ctx.device;

        let buffers = [0, 1, 2].map(|binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
        });
        let records = vk::DescriptorSetLayoutBinding::default()
            .binding(GRAPHICS_RECORDS_BINDING)
            .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::FRAGMENT);
        let bindings = [buffers[0], buffers[1], buffers[2], records];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.graphics_set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let set_layouts = [pipelines.graphics_set_layout];
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .size(GRAPHICS_PUSH_BYTES)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&push);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.graphics_layout =
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;

        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(0)
                .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
            vk::DescriptorSetLayoutBinding::default()
                .binding(1)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.compute_set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let set_layouts = [pipelines.compute_set_layout];
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(COMPUTE_PUSH_BYTES)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&push);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.compute_layout =
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;

        let bindings: Vec<_> = (0..BUFFER_KERNEL_BINDINGS)
            .map(|binding| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .gather("bindings")?;
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.buffer_set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let set_layouts = [pipelines.buffer_set_layout];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&push);
        // SAFETY: valid create info; destroyed in `Drop`.
        pipelines.buffer_layout =
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        Ok(pipelines)
    }

    /// Refuses a build whose needs the device did not enable.
    fn check_needs(&self, shader: Shader) -> Result<()> {
        let lacks = if shader.needs.float64 && !self.ctx.float64 {
            "double precision shaders (shaderFloat64)"
        } else if shader.needs.int64_atomics && !self.ctx.fragment_atomics64 {
            "64-bit atomics (shaderBufferInt64Atomics)"
        } else {
            return Ok(());
        };
        Err(Error::Unsupported(format!(
            "{lacks}, which {} needs",
            shader.name
        )))
    }

    fn module(&self, shader: Shader) -> Result<vk::ShaderModule> {
        let mut modules = self.modules.borrow_mut();
        if modules[shader.index] == vk::ShaderModule::null() {
            let (name, code) = shaders::ALL[shader.index];
            let info = vk::ShaderModuleCreateInfo::default().code(code);
            // SAFETY: SPIR-V compiled and validated by build.rs; destroyed in `Drop`.
            let module = unsafe { self.ctx.device.create_shader_module(&info, None) }
                .vk("vkCreateShaderModule")?;
            self.ctx.name_object(module, name);
            modules[shader.index] = module;
        }
        Ok(modules[shader.index])
    }

    /// The pipeline drawing `program` with its build `fragment` into `color`
    /// and `depth` with `state`.
    pub(crate) fn graphics(
        &self,
        program: &'static GraphicsProgram,
        fragment: Shader,
        color: Option<Format>,
        depth: Option<Format>,
        state: &RasterState,
    ) -> Result<vk::Pipeline> {
        let key = GraphicsKey {
            program: std::ptr::from_ref(program) as usize,
            fragment: fragment.index,
            color,
            depth,
            state: *state,
        };
        if let Some(p) = self.graphics.borrow().get(&key) {
            return Ok(*p);
        }
        let pipeline = self.create_graphics(program, fragment, &key)?;
        self.graphics.borrow_mut().insert(key, pipeline);
        Ok(pipeline)
    }

    fn create_graphics(
        &self,
        program: &GraphicsProgram,
        fragment: Shader,
        key: &GraphicsKey,
    ) -> Result<vk::Pipeline> {
        let uint_target = key.color == Some(Format::R32Uint);
        if matches!(key.state.color, ColorUpdate::Blend(_)) && uint_target {
            return Err(Error::Usage("blending needs a float colour target (integer targets only overwrite or use logic ops)".into(),));
        }
        if matches!(key.state.color, ColorUpdate::Logic(_)) && !uint_target {
            return Err(Error::Usage(
                "logic operations need an integer colour target".into(),
            ));
        }
        if matches!(key.state.color, ColorUpdate::Logic(_)) && !self.ctx.logic_op {
            return Err(Error::Unsupported(format!(
                "logic operations (logicOp), which {} draws with",
                program.name
            )));
        }
        self.check_needs(program.vertex)?;
        self.check_needs(fragment)?;
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(self.module(program.vertex)?)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(self.module(fragment)?)
                .name(c"main"),
        ];
        let bindings: Vec<_> = (0u32..)
            .zip(program.vertex_buffers)
            .map(|(binding, buffer)| {
                vk::VertexInputBindingDescription::default()
                    .binding(binding)
                    .stride(buffer.stride)
                    .input_rate(if buffer.per_instance {
                        vk::VertexInputRate::INSTANCE
                    } else {
                        vk::VertexInputRate::VERTEX
                    })
            })
            .gather("values")?;
        let attributes: Vec<_> = (0u32..)
            .zip(program.vertex_buffers)
            .flat_map(|(binding, buffer)| {
                buffer.attributes.iter().map(move |a| {
                    vk::VertexInputAttributeDescription::default()
                        .location(a.location)
                        .binding(binding)
                        .offset(a.offset)
                        .format(a.format.vk())
                })
            })
            .gather("attributes")?;
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes);
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(program.topology.vk());
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth_stencil = conv::map_depth_stencil(&key.state)
            .depth_test_enable(key.depth.is_some())
            .stencil_test_enable(
                key.depth.is_some_and(Format::has_stencil)
                    && key.state.stencil != super::state::StencilTest::OFF,
            );
        let (attachment, logic_op) = conv::map_color_update(&key.state);
        let attachments = [attachment];
        let mut blend = vk::PipelineColorBlendStateCreateInfo::default();
        if key.color.is_some() {
            blend = blend.attachments(&attachments);
        }
        if let Some(op) = logic_op {
            blend = blend.logic_op_enable(true).logic_op(op);
        }
        let dynamic = [
            vk::DynamicState::VIEWPORT,
            vk::DynamicState::SCISSOR,
            vk::DynamicState::STENCIL_REFERENCE,
            vk::DynamicState::BLEND_CONSTANTS,
        ];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let color_formats: Vec<vk::Format> =
            key.color.iter().map(|f| f.vk()).gather("color formats")?;
        let depth_format = key.depth.map_or(vk::Format::UNDEFINED, Format::vk);
        let stencil_format = match key.depth {
            Some(f) if f.has_stencil() => f.vk(),
            _ => vk::Format::UNDEFINED,
        };
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(depth_format)
            .stencil_attachment_format(stencil_format);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_stencil)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(self.graphics_layout)
            .push_next(&mut rendering);
        // SAFETY: every pointer in `info` refers to locals alive during the call; the
        // pipeline is destroyed in `Drop`.
        let pipelines = unsafe {
            self.ctx
                .device
                .create_graphics_pipelines(self.cache.handle, &[info], None)
        }
        .map_err(|(_, result)| Error::vulkan("vkCreateGraphicsPipelines", result))?;
        self.cache.grew();
        self.ctx.name_object(pipelines[0], program.name);
        Ok(pipelines[0])
    }

    /// The compute pipeline of `kernel` reading pictures of `format`.
    pub fn compute(&self, kernel: Kernel, format: Format) -> Result<vk::Pipeline> {
        if let Some(p) = self.compute.borrow().get(&(kernel, format)) {
            return Ok(*p);
        }
        // The reductions' builds: R32UI, R32F, RGBA32F.
        let format_build = match format {
            Format::R32Uint => 0,
            Format::R32Float => 1,
            Format::Rgba32Float => 2,
            other => {
                return Err(Error::Usage(format!(
                    "reductions read R32Uint, R32Float or Rgba32Float pictures, not {other:?}"
                )))
            }
        };
        let shader = match kernel {
            Kernel::MinMax => shaders::MINMAX_COMP[format_build],
            Kernel::Histogram => shaders::HISTOGRAM_COMP[format_build],
        };
        let pipeline = self.create_compute(shader, self.compute_layout)?;
        self.compute.borrow_mut().insert((kernel, format), pipeline);
        Ok(pipeline)
    }

    /// The compute pipeline of a kernel over storage buffers.
    pub(crate) fn buffer_compute(&self, kernel: &'static ComputeProgram) -> Result<vk::Pipeline> {
        let key = std::ptr::from_ref(kernel) as usize;
        if let Some(p) = self.buffer_kernels.borrow().get(&key) {
            return Ok(*p);
        }
        let pipeline = self.create_compute(kernel.shader, self.buffer_layout)?;
        self.buffer_kernels.borrow_mut().insert(key, pipeline);
        Ok(pipeline)
    }

    fn create_compute(&self, shader: Shader, layout: vk::PipelineLayout) -> Result<vk::Pipeline> {
        self.check_needs(shader)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(self.module(shader)?)
            .name(c"main");
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout);
        // SAFETY: valid create info; the pipeline is destroyed in `Drop`.
        let pipelines = unsafe {
            self.ctx
                .device
                .create_compute_pipelines(self.cache.handle, &[info], None)
        }
        .map_err(|(_, result)| Error::vulkan("vkCreateComputePipelines", result))?;
        self.cache.grew();
        self.ctx.name_object(pipelines[0], shader.name);
        Ok(pipelines[0])
    }

    /// Number of graphics pipelines created so far (one per distinct state used).
    pub(crate) fn graphics_count(&self) -> usize {
        self.graphics.borrow().len()
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        let device = &self.ctx.device;
        // SAFETY: the machine has waited for all work; each object is destroyed once.
        unsafe {
            for p in self.graphics.get_mut().values() {
                device.destroy_pipeline(*p, None);
            }
            for p in self.compute.get_mut().values() {
                device.destroy_pipeline(*p, None);
            }
            for p in self.buffer_kernels.get_mut().values() {
                device.destroy_pipeline(*p, None);
            }
            device.destroy_pipeline_layout(self.buffer_layout, None);
            device.destroy_descriptor_set_layout(self.buffer_set_layout, None);
            device.destroy_pipeline_layout(self.graphics_layout, None);
            device.destroy_pipeline_layout(self.compute_layout, None);
            device.destroy_descriptor_set_layout(self.compute_set_layout, None);
            device.destroy_descriptor_set_layout(self.graphics_set_layout, None);
            // Destroying a null handle does nothing.
            for m in self.modules.get_mut() {
                device.destroy_shader_module(*m, None);
            }
        }
    }
}
