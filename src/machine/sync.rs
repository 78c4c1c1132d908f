//! Barriers derived from declared use: each image records its last `Usage` and
//! each buffer its last `BufferUse`, and `image_barrier` and `buffer_barrier`
//! turn a change of use into the one barrier it needs.

use ash::vk;

/// What a pass does with an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Usage {
    /// Contents are undefined (new image, or about to be cleared).
    Undefined,
    ColorAttachment,
    DepthStencilAttachment,
    /// Source of a copy to the host.
    TransferSrc,
    /// Destination of a copy from a buffer.
    TransferDst,
    /// Read as a storage image by a compute pass (reductions).
    ComputeRead,
    /// Read as a storage image by fragment shaders.
    FragmentRead,
}

struct Access {
    stage: vk::PipelineStageFlags2,
    access: vk::AccessFlags2,
    layout: vk::ImageLayout,
    writes: bool,
}

fn access(usage: Usage) -> Access {
    match usage {
        Usage::Undefined => Access {
            stage: vk::PipelineStageFlags2::NONE,
            access: vk::AccessFlags2::NONE,
            layout: vk::ImageLayout::UNDEFINED,
            writes: false,
        },
        Usage::ColorAttachment => Access {
            stage: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            access: vk::AccessFlags2::COLOR_ATTACHMENT_READ
                | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            writes: true,
        },
        Usage::DepthStencilAttachment => Access {
            stage: vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            access: vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            writes: true,
        },
        Usage::TransferSrc => Access {
            stage: vk::PipelineStageFlags2::COPY,
            access: vk::AccessFlags2::TRANSFER_READ,
            layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            writes: false,
        },
        Usage::TransferDst => Access {
            stage: vk::PipelineStageFlags2::COPY,
            access: vk::AccessFlags2::TRANSFER_WRITE,
            layout: vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            writes: true,
        },
        Usage::ComputeRead => Access {
            stage: vk::PipelineStageFlags2::COMPUTE_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_READ,
            layout: vk::ImageLayout::GENERAL,
            writes: false,
        },
        Usage::FragmentRead => Access {
            stage: vk::PipelineStageFlags2::FRAGMENT_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_READ,
            layout: vk::ImageLayout::GENERAL,
            writes: false,
        },
    }
}

/// The barrier that makes an image used as `from` ready to be used as `to`, or
/// `None` when two uses only read.
pub(crate) fn image_barrier(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    from: Usage,
    to: Usage,
) -> Option<vk::ImageMemoryBarrier2<'static>> {
    let (a, b) = (access(from), access(to));
    if from == to && !a.writes {
        return None;
    }
    Some(
        vk::ImageMemoryBarrier2::default()
            .src_stage_mask(a.stage)
            .src_access_mask(a.access)
            .dst_stage_mask(b.stage)
            .dst_access_mask(b.access)
            .old_layout(a.layout)
            .new_layout(b.layout)
            .image(image)
            .subresource_range(range),
    )
}

/// The layout an image has while used as `usage`.
pub fn layout(usage: Usage) -> vk::ImageLayout {
    access(usage).layout
}

/// What a pass does with a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BufferUse {
    /// Written or read by the host between runs: a submission makes host
    /// writes visible, and each run ends by making device writes visible to it.
    Host,
    /// Vertices or instances of draws.
    VertexInput,
    /// Storage read and written by vertex and fragment shaders.
    GraphicsStorage,
    /// Storage read and written by compute kernels.
    ComputeStorage,
    /// Source of a copy into an image.
    TransferSrc,
    /// Destination of a copy from an image.
    TransferDst,
}

fn buffer_access(usage: BufferUse) -> Access {
    let (stage, access, writes) = match usage {
        // The host writes only between runs, after the fence.
        BufferUse::Host => (
            vk::PipelineStageFlags2::HOST,
            vk::AccessFlags2::HOST_READ,
            false,
        ),
        BufferUse::VertexInput => (
            vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT,
            vk::AccessFlags2::VERTEX_ATTRIBUTE_READ,
            false,
        ),
        BufferUse::GraphicsStorage => (
            vk::PipelineStageFlags2::VERTEX_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            true,
        ),
        BufferUse::ComputeStorage => (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            true,
        ),
        BufferUse::TransferSrc => (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
            false,
        ),
        BufferUse::TransferDst => (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
            true,
        ),
    };
    Access {
        stage,
        access,
        layout: vk::ImageLayout::UNDEFINED,
        writes,
    }
}

/// The barrier that orders a buffer's use as `from` before its use as `to`, or
/// `None` when neither writes, or when the host wrote it before the
/// submission (which the submission itself makes visible).
pub(crate) fn buffer_barrier(
    buffer: vk::Buffer,
    from: BufferUse,
    to: BufferUse,
) -> Option<vk::BufferMemoryBarrier2<'static>> {
    let (a, b) = (buffer_access(from), buffer_access(to));
    if from == BufferUse::Host || (!a.writes && !b.writes) {
        return None;
    }
    Some(
        vk::BufferMemoryBarrier2::default()
            .src_stage_mask(a.stage)
            .src_access_mask(a.access)
            .dst_stage_mask(b.stage)
            .dst_access_mask(b.access)
            .buffer(buffer)
            .size(vk::WHOLE_SIZE),
    )
}
