//! Images and buffers: owners of a Vulkan object and its memory, destroyed in `Drop`.
//! Each image remembers how it was last used, so barriers are derived in one place
//! (`sync.rs`) from what a pass declares instead of being placed by hand.

use std::{cell::Cell, sync::Arc};

use ash::vk;
use gpu_allocator::{
    vulkan::{Allocation, AllocationCreateDesc, AllocationScheme},
    MemoryLocation,
};

use super::{
    context::Context,
    sync::{BufferUse, Usage},
};
use crate::error::{Error, Result, VkContext};

/// Pixel formats of the picture's buffers (thesis Fig. 1.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Integer labels; logic operations work on it.
    R32Uint,
    /// One float counter or distance per pixel.
    R32Float,
    /// Four float counters per pixel (red, green, blue, alpha).
    Rgba32Float,
    /// Four words per texel: records that fragment shaders read with
    /// `imageLoad` (one vector load each on lavapipe, where storage-buffer
    /// loads go lane by lane).
    Rgba32Uint,
    /// A picture for people.
    Rgba8Unorm,
    /// The z buffer and the stencil.
    DepthStencil,
    /// The z buffer alone, for algorithms that need no stencil (half the bytes
    /// per pixel of `DepthStencil` to test and write).
    Depth,
}

impl Format {
    pub(crate) fn vk(self) -> vk::Format {
        match self {
            Format::R32Uint => vk::Format::R32_UINT,
            Format::R32Float => vk::Format::R32_SFLOAT,
            Format::Rgba32Float => vk::Format::R32G32B32A32_SFLOAT,
            Format::Rgba32Uint => vk::Format::R32G32B32A32_UINT,
            Format::Rgba8Unorm => vk::Format::R8G8B8A8_UNORM,
            Format::DepthStencil => vk::Format::D32_SFLOAT_S8_UINT,
            Format::Depth => vk::Format::D32_SFLOAT,
        }
    }

    /// Bytes per pixel of one readback (for depth/stencil: the depth aspect).
    pub(crate) fn texel_bytes(self) -> u64 {
        match self {
            Format::Rgba32Float | Format::Rgba32Uint => 16,
            _ => 4,
        }
    }

    pub(crate) fn is_depth(self) -> bool {
        matches!(self, Format::DepthStencil | Format::Depth)
    }

    pub(crate) fn has_stencil(self) -> bool {
        self == Format::DepthStencil
    }

    pub(crate) fn aspect(self) -> vk::ImageAspectFlags {
        match self {
            Format::DepthStencil => vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL,
            Format::Depth => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        }
    }
}

/// An offscreen picture buffer in device memory.
pub struct Image {
    /// The machine's context it was made on; passes of other machines refuse it.
    pub(crate) ctx: Arc<Context>,
    pub(crate) raw: vk::Image,
    pub(crate) view: vk::ImageView,
    allocation: Option<Allocation>,
    format: Format,
    width: u32,
    height: u32,
    /// How the image was last used; barriers start from here.
    pub(crate) last_use: Cell<Usage>,
}

impl Image {
    pub(crate) fn new(ctx: &Arc<Context>, format: Format, width: u32, height: u32) -> Result<Self> {
        let limit = ctx.properties.limits.max_image_dimension2_d;
        if width == 0 || height == 0 {
            return Err(Error::out_of_range(format!(
                "picture size {width}x{height}: both sides must be at least 1"
            )));
        }
        if width > limit || height > limit {
            return Err(Error::PictureTooLarge {
                width,
                height,
                limit,
            });
        }
        let usage = if format.is_depth() {
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST
        } else {
            let storage = if format == Format::Rgba8Unorm {
                vk::ImageUsageFlags::empty()
            } else {
                vk::ImageUsageFlags::STORAGE
            };
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST
                | storage
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format.vk())
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let device = &ctx.device;
        // SAFETY: valid create info; the image is destroyed in `Drop` or below.
        let raw = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut image = Self {
            ctx: ctx.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
            format,
            width,
            height,
            last_use: Cell::new(Usage::Undefined),
        };
        // SAFETY: `raw` is a valid image of this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name: "pixgeo image",
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| {
                let what = format!("an image of {width}x{height}");
                Error::memory_for(e, &what, requirements.size)
            })?;
        // SAFETY: memory allocated for this image's requirements, bound once.
        unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindImageMemory")?;
        image.allocation = Some(allocation);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format.vk())
            .subresource_range(image.subresource_range());
        // SAFETY: the image is bound to memory; the view is destroyed in `Drop`.
        image.view =
            unsafe { device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        let name = format!("{format:?} {width}x{height}");
        ctx.name_object(raw, &name);
        ctx.name_object(image.view, &name);
        Ok(image)
    }

    pub fn format(&self) -> Format {
        self.format
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub(crate) fn subresource_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange::default()
            .aspect_mask(self.format.aspect())
            .level_count(1)
            .layer_count(1)
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the machine waits for its submissions before returning, so the GPU
        // no longer uses the image; view, image and memory are released once.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.ctx.device.destroy_image_view(self.view, None);
            }
            self.ctx.device.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}

/// What a buffer is for; decides its usage flags and memory location.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferKind {
    /// Vertex and instance data written by the host.
    Vertices,
    /// Read back to the host: the target of copies and of reductions.
    Readback,
}

/// A buffer in host-visible memory.
pub struct Buffer {
    /// The machine's context it was made on; passes of other machines refuse it.
    pub(crate) ctx: Arc<Context>,
    pub(crate) raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    /// How the run being recorded last used it (`Host` between runs).
    pub(crate) last_use: Cell<BufferUse>,
}

impl Buffer {
    pub(crate) fn new(ctx: &Arc<Context>, kind: BufferKind, size: u64) -> Result<Self> {
        let size = size.max(4);
        let (usage, location) = match kind {
            BufferKind::Vertices => (
                vk::BufferUsageFlags::VERTEX_BUFFER,
                MemoryLocation::CpuToGpu,
            ),
            BufferKind::Readback => (
                vk::BufferUsageFlags::TRANSFER_DST
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::GpuToCpu,
            ),
        };
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &ctx.device;
        // SAFETY: valid create info; the buffer is destroyed in `Drop`.
        let raw = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        ctx.name_object(raw, &format!("{kind:?} {size} bytes"));
        let mut buffer = Self {
            ctx: ctx.clone(),
            raw,
            allocation: None,
            size,
            last_use: Cell::new(BufferUse::Host),
        };
        // SAFETY: `raw` is a valid buffer of this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name: "pixgeo buffer",
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| Error::memory_for(e, "a buffer", requirements.size))?;
        // SAFETY: memory allocated for this buffer's requirements, bound once.
        unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindBufferMemory")?;
        buffer.allocation = Some(allocation);
        Ok(buffer)
    }

    /// A host-visible buffer holding `data`.
    pub(crate) fn with_data<T: bytemuck::Pod>(
        ctx: &Arc<Context>,
        kind: BufferKind,
        data: &[T],
    ) -> Result<Self> {
        let mut buffer = Self::new(ctx, kind, std::mem::size_of_val(data) as u64)?;
        buffer.write(data);
        Ok(buffer)
    }

    pub fn size(&self) -> u64 {
        self.size
    }

    pub(crate) fn mapped(&self) -> &[u8] {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .unwrap_or(&[])
    }

    /// Copies `data` to the start of the buffer.
    pub(crate) fn write<T: bytemuck::Pod>(&mut self, data: &[T]) {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if let Some(slice) = self.allocation.as_mut().and_then(|a| a.mapped_slice_mut()) {
            let n = bytes.len().min(slice.len());
            slice[..n].copy_from_slice(&bytes[..n]);
        }
    }

    /// Sets every byte of the buffer to `byte`.
    pub(crate) fn fill(&mut self, byte: u8) {
        if let Some(slice) = self.allocation.as_mut().and_then(|a| a.mapped_slice_mut()) {
            slice.fill(byte);
        }
    }

    /// Reads `count` values of `T` from the start of the buffer.
    #[expect(
        clippy::disallowed_macros,
        reason = "a copy of a device buffer the caller made"
    )]
    pub(crate) fn read<T: bytemuck::Pod>(&self, count: usize) -> Vec<T> {
        let bytes = self.mapped();
        let n = count.min(bytes.len() / std::mem::size_of::<T>());
        let mut out = vec![T::zeroed(); n];
        bytemuck::cast_slice_mut::<T, u8>(&mut out)
            .copy_from_slice(&bytes[..n * std::mem::size_of::<T>()]);
        out
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: no submission using the buffer is pending (the machine waits).
        unsafe { self.ctx.device.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}
