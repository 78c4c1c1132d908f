//! Shader programs and the pipeline cache: each distinct (program, targets, raster
//! state) becomes one `VkPipeline`, created on first use.
//!
//! The file is long because each program's stages, topology and vertex layout are
//! spelled out in one `match`, beside the shader builds they name.

use std::{cell::RefCell, collections::HashMap, path::Path, sync::Arc};

use ash::vk;

use super::{
    cache::PipelineCache,
    context::Context,
    conv,
    memory::Format,
    shaders,
    state::{ColorUpdate, RasterState},
};
use crate::error::{Error, Result, VkContext};

/// The vertex and fragment shaders of a draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Program {
    /// Instanced triangle-fan cones; depth is the interpolated cone height.
    ConeFan,
    /// Instanced cone footprints; depth is the exact squared distance per fragment.
    ConeExact,
    /// An axis-aligned rectangle of constant depth and colour.
    Rect,
    /// Up to eight exact cones in one bounding rectangle, the envelope taken per
    /// fragment; see [`crate::machine::ConeBatch`].
    ConeExactBatch,
    /// The lower envelope of exact cones from screen-tile lists: one triangle
    /// over the target, each fragment taking the nearest of the sites binned to
    /// its tile, read from the records image (`glsl/nearest_tiles.frag`).
    NearestTiles,
    /// Instanced exact cone footprints inserting `(squared distance, id)` keys into
    /// each pixel's sorted list of the k nearest, a storage buffer bound with
    /// [`crate::machine::Pass::bind_fragment_buffers`]; writes no attachment.
    ConeKNearest,
    /// [`Program::ConeKNearest`] with triangle-fan cones: the key's distance is the
    /// fan's interpolated height.
    ConeKNearestFan,
    /// Exact cones peeled against the previous level's depth and site, held in
    /// the fragment storage buffer (thesis §3.7).
    ConePeel,
    /// One rectangle per screen tile whose fragments keep the k lowest layers of
    /// the cones binned to the tile (tile records and cones in the second storage
    /// buffer, keys written to the first). The number is the longest list the
    /// shader keeps: 1, 2, 4, 8, 16 or 32.
    KNearestTiles(u32),
    /// The settle point's discs (thesis §3.10.3): one square per source pixel,
    /// instanced without vertex buffers; the fragment shader keeps the disc and
    /// reads each pixel's radius from the bound storage buffer. Built for the
    /// given kind of distance function (`ConePush::metric`'s kind).
    SettleDisc(u32),
    /// One rectangle per site with weights; the fragment writes the exact
    /// weighted distance (see [`crate::machine::SiteInstance`]). Built for one
    /// shape of site: the fragment shader then carries no other shape's code,
    /// which lavapipe would run under masks.
    SiteExact(SiteShape),
    /// Up to eight sites of one shape (not arcs) in one rectangle, the envelope
    /// taken per fragment; see [`crate::machine::SiteBatch`]. Built for L2, L1
    /// and L∞.
    SiteExactBatch(SiteShape),
    /// The lower envelope of sites of one shape under L2, L1 or L∞ from
    /// screen-tile lists: one triangle over the target, each fragment taking the lowest
    /// weighted distance of the sites listed for its tile, read from the
    /// records image (`glsl/site_tiles.frag`).
    SiteTiles(SiteShape),
    /// Triangles of fan surfaces with per-vertex position, depth and site id
    /// (two per-vertex buffers: `[f32; 3]` and `u32`), drawn as a list.
    SiteFan,
    /// [`Program::SiteFan`] for folded surfaces: vertices `[x, y, depth of a
    /// signed value, depth of zero]`, and each fragment's depth is the zero's
    /// plus the magnitude of the value's difference from it.
    SiteFanFolded,
    /// Saddle roofs over pairs of sites (thesis §7.3), one per instance without
    /// vertex buffers, reading the sites (`f64` pairs) and the site drawn in each
    /// pixel from storage buffers 0 and 1: the area as depth, the pair as colour.
    Roof,
    /// [`Program::Roof`] keeping per pair and side of its line the nearest (or
    /// farthest) site in storage buffer 2; writes no attachment.
    RoofSides,
    /// Closed discs, one per instance of a `[f32; 4]` buffer (centre, radius and
    /// the value written to a float target); see [`crate::machine::Pass::draw_discs`].
    Disc,
}

/// The shapes of sites that [`Program::SiteExact`] is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SiteShape {
    Point,
    Segment,
    Circle,
    Arc,
}

impl SiteShape {
    /// The shape drawn for a [`crate::machine::SiteInstance`]'s kind (0 point, 1
    /// segment, 2 circle, 3 arc).
    pub fn of_kind(kind: u32) -> Self {
        match kind {
            0 => SiteShape::Point,
            1 => SiteShape::Segment,
            2 => SiteShape::Circle,
            _ => SiteShape::Arc,
        }
    }
}

impl Program {
    /// The build of the fragment shader for the distance function of kind
    /// `kind` (`glsl/metric.glsl`); `None` for programs with a single build.
    fn metric_build(self, kind: u32) -> Option<u32> {
        match self {
            Program::SiteExact(_)
            | Program::SiteExactBatch(_)
            | Program::SiteTiles(_)
            | Program::ConeExact
            | Program::SettleDisc(_)
            | Program::ConeExactBatch
            | Program::NearestTiles
            | Program::ConeKNearest
            | Program::ConeKNearestFan
            | Program::ConePeel
            | Program::KNearestTiles(_) => Some(kind),
            _ => None,
        }
    }

    /// Whether the program's vertices come from vertex buffers (a mesh and
    /// per-instance data), rather than being made by its vertex shader.
    pub fn reads_vertex_buffers(self) -> bool {
        !matches!(
            self,
            Program::Rect
                | Program::KNearestTiles(_)
                | Program::NearestTiles
                | Program::SiteTiles(_)
                | Program::SettleDisc(_)
                | Program::Roof
                | Program::RoofSides
        )
    }
}

/// Compute kernels of the reductions (thesis §1.7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
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

/// Compute kernels over storage buffers (bindings 0, 1, … in the order
/// [`crate::machine::Pass::dispatch`] is given them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BufferKernel {
    /// The settle point's span counting: every disc's parts into seven
    /// difference pictures of `i32` in buffers 1 to 7, one invocation per source
    /// pixel, built for the given kind of distance function
    /// (`ConePush::metric`'s kind).
    SettleSpans(u32),
    /// The counts from those difference pictures, into the first (push
    /// `[width, height, phase]`, one invocation per column, per diagonal, per
    /// antidiagonal and per row in phases 0 to 3).
    SettleSums,
    /// The extremes of a float picture and their first indices, in two phases
    /// (push `[width, height, phase]`, one invocation per 64 rows of a column).
    Extremum,
    /// One pass of jump flooding from buffer 0 into buffer 1 (push `[width,
    /// height, step, first pixel]`, one invocation per pixel).
    JumpFlood,
    /// The dual triangles of a colouring in buffer 0, appended to buffer 1
    /// (push `[width, height, capacity]`, one invocation per strip of 64 pixel
    /// corners of a column, a grid of (width + 1) columns by strips).
    Dualize,
    /// The exact Euclidean colouring of the seed map in buffer 0 into buffer 1
    /// (both twice the pixels; push `[width, height, phase, scale]`, one
    /// invocation per column in phase 0, per row in phase 1, per strip of 64
    /// rows of a column in phases 2 and 3 (a grid of columns by strips): debris
    /// roots, or scaled distances).
    EuclideanColouring,
}

impl BufferKernel {
    /// Invocations per workgroup (the shader's `local_size_x`).
    pub fn group(self) -> u32 {
        match self {
            BufferKernel::SettleSpans(_) => 64,
            BufferKernel::SettleSums => 64,
            BufferKernel::Extremum => 64,
            BufferKernel::JumpFlood => 64,
            BufferKernel::Dualize => 64,
            BufferKernel::EuclideanColouring => 64,
        }
    }

    fn shader(self) -> Result<String> {
        Ok(match self {
            BufferKernel::SettleSpans(kind) => {
                format!("settle_spans.comp:{}", build_name(kind)?)
            }
            BufferKernel::SettleSums => "settle_sums.comp".into(),
            BufferKernel::Extremum => "extremum.comp".into(),
            BufferKernel::JumpFlood => "jump_flood.comp".into(),
            BufferKernel::Dualize => "dualize.comp".into(),
            BufferKernel::EuclideanColouring => "euclidean.comp".into(),
        })
    }
}

/// The name of a shader's build for a kind of distance function
/// (`glsl/metric.glsl`: 0 Euclidean, 1 L1, 2 L-infinity, 3 L_p, 4 L_p with keys
/// that are sums of powers, built for exact point cones only).
fn build_name(kind: u32) -> Result<&'static str> {
    match kind {
        0 => Ok("metric_l2"),
        1 => Ok("metric_l1"),
        2 => Ok("metric_linf"),
        3 => Ok("metric_lp"),
        4 => Ok("metric_lp_sum"),
        other => Err(Error::InvalidInput(format!(
            "no distance function of kind {other}"
        ))),
    }
}

/// Bytes of push constants shared by all graphics programs.
pub const GRAPHICS_PUSH_BYTES: u32 = 64;
/// Bytes of push constants of the compute kernels.
pub const COMPUTE_PUSH_BYTES: u32 = 32;
/// The graphics layout's storage image (after its three storage buffers):
/// records fragment shaders read with `imageLoad`.
pub const GRAPHICS_RECORDS_BINDING: u32 = 3;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct GraphicsKey {
    program: Program,
    /// The build of a metric-dependent fragment shader
    /// ([`Program::metric_build`]); `None` for the other programs.
    metric: Option<u32>,
    color: Option<Format>,
    depth: Option<Format>,
    state: RasterState,
}

pub(crate) struct Pipelines {
    ctx: Arc<Context>,
    pub cache: PipelineCache,
    modules: HashMap<&'static str, vk::ShaderModule>,
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
    buffer_kernels: RefCell<HashMap<BufferKernel, vk::Pipeline>>,
}

impl Pipelines {
    pub fn new(ctx: &Arc<Context>, cache_folder: Option<&Path>) -> Result<Self> {
        let mut pipelines = Self {
            ctx: ctx.clone(),
            cache: PipelineCache::open(ctx, cache_folder)?,
            modules: HashMap::new(),
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
        for (name, code) in shaders::ALL {
            let info = vk::ShaderModuleCreateInfo::default().code(code);
            // SAFETY: SPIR-V compiled and validated by build.rs; destroyed in `Drop`.
            let module =
                unsafe { device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
            ctx.name_object(module, name);
            pipelines.modules.insert(name, module);
        }

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
            .collect();
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

    fn module(&self, name: &str) -> vk::ShaderModule {
        // Every name used below is a build in `shaders::ALL`; a missing one is a
        // bug that the first draw of its program reveals.
        *self
            .modules
            .get(name)
            .unwrap_or_else(|| panic!("shader {name} is not built"))
    }

    /// The pipeline for `program` drawing into `color` and `depth` with `state`;
    /// `metric` is the kind of distance function of the draw's push constants.
    pub fn graphics(
        &self,
        program: Program,
        metric: u32,
        color: Option<Format>,
        depth: Option<Format>,
        state: &RasterState,
    ) -> Result<vk::Pipeline> {
        let key = GraphicsKey {
            program,
            metric: program.metric_build(metric),
            color,
            depth,
            state: *state,
        };
        if let Some(p) = self.graphics.borrow().get(&key) {
            return Ok(*p);
        }
        let pipeline = self.create_graphics(&key)?;
        self.graphics.borrow_mut().insert(key, pipeline);
        Ok(pipeline)
    }

    fn create_graphics(&self, key: &GraphicsKey) -> Result<vk::Pipeline> {
        let uint_target = key.color == Some(Format::R32Uint);
        if matches!(key.state.color, ColorUpdate::Blend(_)) && uint_target {
            return Err(Error::InvalidInput(
                "blending needs a float colour target (integer targets only overwrite or use logic ops)".into(),
            ));
        }
        if matches!(key.state.color, ColorUpdate::Logic(_)) && !uint_target {
            return Err(Error::InvalidInput(
                "logic operations need an integer colour target".into(),
            ));
        }
        let (vertex, fragment, topology) = match key.program {
            Program::ConeFan => (
                "cone.vert",
                "cone_fan.frag",
                vk::PrimitiveTopology::TRIANGLE_FAN,
            ),
            Program::ConeExact => (
                "cone.vert",
                "cone_exact.frag",
                vk::PrimitiveTopology::TRIANGLE_FAN,
            ),
            Program::ConeExactBatch => (
                "cone_batch.vert",
                "cone_batch.frag",
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::NearestTiles => (
                "picture.vert",
                "nearest_tiles.frag",
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::ConeKNearest => (
                "cone.vert",
                "cone_knearest.frag:exact",
                vk::PrimitiveTopology::TRIANGLE_FAN,
            ),
            Program::ConeKNearestFan => (
                "cone.vert",
                "cone_knearest.frag:fan",
                vk::PrimitiveTopology::TRIANGLE_FAN,
            ),
            Program::ConePeel => (
                "cone.vert",
                "cone_peel.frag",
                vk::PrimitiveTopology::TRIANGLE_FAN,
            ),
            Program::KNearestTiles(levels) => (
                "tiles.vert",
                match levels {
                    0..=1 => "cone_tiles.frag:k1",
                    2 => "cone_tiles.frag:k2",
                    3 => "cone_tiles.frag:k3",
                    4 => "cone_tiles.frag:k4",
                    5..=6 => "cone_tiles.frag:k6",
                    7..=8 => "cone_tiles.frag:k8",
                    9..=12 => "cone_tiles.frag:k12",
                    13..=16 => "cone_tiles.frag:k16",
                    17..=24 => "cone_tiles.frag:k24",
                    _ => "cone_tiles.frag:k32",
                },
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),

            Program::SiteExact(shape) => (
                "site.vert",
                match shape {
                    SiteShape::Point => "site_exact.frag:point",
                    SiteShape::Segment => "site_exact.frag:segment",
                    SiteShape::Circle => "site_exact.frag:circle",
                    SiteShape::Arc => "site_exact.frag:arc",
                },
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::SiteExactBatch(shape) => (
                "site_batch.vert",
                match shape {
                    SiteShape::Point => "site_batch.frag:point",
                    SiteShape::Segment => "site_batch.frag:segment",
                    SiteShape::Circle => "site_batch.frag:circle",
                    SiteShape::Arc if key.metric == Some(0) => "site_batch.frag:arc",
                    SiteShape::Arc => {
                        return Err(Error::InvalidInput(
                            "only Euclidean arcs are drawn in batches".into(),
                        ))
                    }
                },
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::SiteTiles(shape) => (
                "picture.vert",
                match shape {
                    SiteShape::Point => "site_tiles.frag:point",
                    SiteShape::Segment => "site_tiles.frag:segment",
                    SiteShape::Circle => "site_tiles.frag:circle",
                    SiteShape::Arc => "site_tiles.frag:arc",
                },
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::SiteFan => (
                "site_fan.vert:plain",
                "site_fan.frag:plain",
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::SiteFanFolded => (
                "site_fan.vert:folded",
                "site_fan.frag:folded",
                vk::PrimitiveTopology::TRIANGLE_LIST,
            ),
            Program::Roof => (
                "roof.vert",
                "roof.frag:triangle",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
            Program::RoofSides => (
                "roof.vert",
                "roof.frag:sides",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
            Program::Disc => (
                "disc.vert",
                "disc.frag",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
            Program::SettleDisc(_) => (
                "settle_disc.vert",
                "settle_disc.frag",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
            Program::Rect if uint_target => (
                "rect.vert",
                "rect.frag:uint",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
            Program::Rect => (
                "rect.vert",
                "rect.frag:float",
                vk::PrimitiveTopology::TRIANGLE_STRIP,
            ),
        };
        if !matches!(
            key.program,
            Program::Rect
                | Program::ConeKNearest
                | Program::ConeKNearestFan
                | Program::KNearestTiles(_)
                | Program::SettleDisc(_)
                | Program::Disc
                | Program::RoofSides
        ) && !uint_target
            && key.color.is_some()
        {
            // Without a colour target a pass draws depth alone.
            return Err(Error::InvalidInput(
                "cones write site ids and need an R32Uint colour target (or none)".into(),
            ));
        }
        if key.program == Program::Disc && (uint_target || key.color.is_none()) {
            return Err(Error::InvalidInput(
                "discs write a value to a float colour target".into(),
            ));
        }
        if matches!(key.program, Program::SiteExactBatch(_)) && key.metric == Some(3) {
            return Err(Error::InvalidInput(
                "L_p sites are not drawn in batches".into(),
            ));
        }
        let fragment = match key.metric {
            None => fragment.to_string(),
            Some(kind) => format!("{fragment}:{}", build_name(kind)?),
        };
        if !self.modules.contains_key(fragment.as_str()) {
            return Err(Error::InvalidInput(format!(
                "{:?} has no build for distance kind {}",
                key.program,
                key.metric.unwrap_or(0)
            )));
        }
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(self.module(vertex))
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(self.module(&fragment))
                .name(c"main"),
        ];
        let cone_bindings = [
            vk::VertexInputBindingDescription::default()
                .binding(0)
                .stride(12)
                .input_rate(vk::VertexInputRate::VERTEX),
            vk::VertexInputBindingDescription::default()
                .binding(1)
                .stride(std::mem::size_of::<super::pass::ConeInstance>() as u32)
                .input_rate(vk::VertexInputRate::INSTANCE),
        ];
        let cone_attributes = [
            vk::VertexInputAttributeDescription::default()
                .location(0)
                .binding(0)
                .format(vk::Format::R32G32B32_SFLOAT),
            vk::VertexInputAttributeDescription::default()
                .location(1)
                .binding(1)
                .format(vk::Format::R32G32B32A32_SFLOAT),
            vk::VertexInputAttributeDescription::default()
                .location(2)
                .binding(1)
                .offset(32)
                .format(vk::Format::R32_UINT),
            vk::VertexInputAttributeDescription::default()
                .location(3)
                .binding(1)
                .offset(16)
                .format(vk::Format::R32G32B32A32_SFLOAT),
        ];
        let instance_bindings = |stride: usize| {
            [
                cone_bindings[0],
                vk::VertexInputBindingDescription::default()
                    .binding(1)
                    .stride(stride as u32)
                    .input_rate(vk::VertexInputRate::INSTANCE),
            ]
        };
        // Instances of consecutive vec4 words from location 1, unsigned from
        // `first_uint` on: glsl/cone_batch.vert (the rectangle, four vec4 of site
        // pairs, two of squared radii, two uvec4 of ids) and glsl/site_batch.vert
        // (the rectangle, eight shapes, four vec4 of weight pairs, two of ids).
        let vec4_attributes = |words: u32, first_uint: u32| -> Vec<_> {
            std::iter::once(cone_attributes[0])
                .chain((1..=words).map(|location| {
                    vk::VertexInputAttributeDescription::default()
                        .location(location)
                        .binding(1)
                        .offset(16 * (location - 1))
                        .format(if location < first_uint {
                            vk::Format::R32G32B32A32_SFLOAT
                        } else {
                            vk::Format::R32G32B32A32_UINT
                        })
                }))
                .collect()
        };
        let batch_bindings = instance_bindings(std::mem::size_of::<super::pass::ConeBatch>());
        let batch_attributes = vec4_attributes(9, 8);
        let site_batch_bindings = instance_bindings(std::mem::size_of::<super::pass::SiteBatch>());
        let site_batch_attributes = vec4_attributes(15, 14);
        let site_bindings = [
            cone_bindings[0],
            vk::VertexInputBindingDescription::default()
                .binding(1)
                .stride(std::mem::size_of::<super::pass::SiteInstance>() as u32)
                .input_rate(vk::VertexInputRate::INSTANCE),
        ];
        // glsl/site.vert: rectangle, two vec4 of shape, vec2 of weights, uvec2.
        let site_formats = [
            (16, vk::Format::R32G32B32A32_SFLOAT),
            (16, vk::Format::R32G32B32A32_SFLOAT),
            (16, vk::Format::R32G32B32A32_SFLOAT),
            (8, vk::Format::R32G32_SFLOAT),
            (8, vk::Format::R32G32_UINT),
        ];
        let site_attributes: Vec<_> = std::iter::once(cone_attributes[0])
            .chain(
                site_formats
                    .iter()
                    .scan(0u32, |offset, &(size, format)| {
                        let at = *offset;
                        *offset += size;
                        Some((at, format))
                    })
                    .enumerate()
                    .map(|(k, (offset, format))| {
                        vk::VertexInputAttributeDescription::default()
                            .location(1 + k as u32)
                            .binding(1)
                            .offset(offset)
                            .format(format)
                    }),
            )
            .collect();
        let fan_attributes = [
            cone_attributes[0],
            vk::VertexInputAttributeDescription::default()
                .location(1)
                .binding(1)
                .format(vk::Format::R32_UINT),
        ];
        let fan_bindings = [
            cone_bindings[0],
            vk::VertexInputBindingDescription::default()
                .binding(1)
                .stride(4)
                .input_rate(vk::VertexInputRate::VERTEX),
        ];
        // Folded fans: four words a vertex.
        let folded_attributes = [
            fan_attributes[0].format(vk::Format::R32G32B32A32_SFLOAT),
            fan_attributes[1],
        ];
        let folded_bindings = [fan_bindings[0].stride(16), fan_bindings[1]];
        let disc_bindings = [vk::VertexInputBindingDescription::default()
            .binding(0)
            .stride(16)
            .input_rate(vk::VertexInputRate::INSTANCE)];
        let disc_attributes = [vk::VertexInputAttributeDescription::default()
            .location(0)
            .binding(0)
            .format(vk::Format::R32G32B32A32_SFLOAT)];
        let vertex_input = match key.program {
            Program::Disc => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&disc_bindings)
                .vertex_attribute_descriptions(&disc_attributes),
            Program::SiteFan => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&fan_bindings)
                .vertex_attribute_descriptions(&fan_attributes),
            Program::SiteFanFolded => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&folded_bindings)
                .vertex_attribute_descriptions(&folded_attributes),
            Program::SiteExact(_) => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&site_bindings)
                .vertex_attribute_descriptions(&site_attributes),
            Program::ConeExactBatch => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&batch_bindings)
                .vertex_attribute_descriptions(&batch_attributes),
            Program::SiteExactBatch(_) => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&site_batch_bindings)
                .vertex_attribute_descriptions(&site_batch_attributes),
            program if !program.reads_vertex_buffers() => {
                vk::PipelineVertexInputStateCreateInfo::default()
            }
            _ => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&cone_bindings)
                .vertex_attribute_descriptions(&cone_attributes),
        };
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
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
        let color_formats: Vec<vk::Format> = key.color.iter().map(|f| f.vk()).collect();
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
        self.ctx
            .name_object(pipelines[0], &format!("{:?}", key.program));
        Ok(pipelines[0])
    }

    /// The compute pipeline of `kernel` reading pictures of `format`.
    pub fn compute(&self, kernel: Kernel, format: Format) -> Result<vk::Pipeline> {
        if let Some(p) = self.compute.borrow().get(&(kernel, format)) {
            return Ok(*p);
        }
        let suffix = match format {
            Format::R32Uint => "r32ui",
            Format::R32Float => "r32f",
            Format::Rgba32Float => "rgba32f",
            other => {
                return Err(Error::InvalidInput(format!(
                    "reductions read R32Uint, R32Float or Rgba32Float pictures, not {other:?}"
                )))
            }
        };
        let name = match kernel {
            Kernel::MinMax => format!("minmax.comp:{suffix}"),
            Kernel::Histogram => format!("histogram.comp:{suffix}"),
        };
        let pipeline = self.create_compute(&name, self.compute_layout)?;
        self.compute.borrow_mut().insert((kernel, format), pipeline);
        Ok(pipeline)
    }

    /// The compute pipeline of a kernel over storage buffers.
    pub fn buffer_compute(&self, kernel: BufferKernel) -> Result<vk::Pipeline> {
        if let Some(p) = self.buffer_kernels.borrow().get(&kernel) {
            return Ok(*p);
        }
        let pipeline = self.create_compute(&kernel.shader()?, self.buffer_layout)?;
        self.buffer_kernels.borrow_mut().insert(kernel, pipeline);
        Ok(pipeline)
    }

    fn create_compute(&self, shader: &str, layout: vk::PipelineLayout) -> Result<vk::Pipeline> {
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(self.module(shader))
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
        self.ctx.name_object(pipelines[0], shader);
        Ok(pipelines[0])
    }

    /// Number of graphics pipelines created so far (one per distinct state used).
    pub fn graphics_count(&self) -> usize {
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
            for m in self.modules.values() {
                device.destroy_shader_module(*m, None);
            }
        }
    }
}
