//! Transfers between images and buffers, and uploads for the fragment
//! programs.

use super::*;

impl<'m, 'r> Pass<'m, 'r> {
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
            return Err(Error::Usage(
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
            return Err(Error::Usage(
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
            return Err(Error::Usage(
                "an upload needs a colour image and a buffer that holds all of it".into(),
            ));
        }
        self.record_upload(buffer, 0, image, vk::ImageAspectFlags::COLOR)?;
        self.use_image(image, Usage::FragmentRead)?;
        Ok(())
    }

    /// Records the copy of `buffer` from byte `offset` into `aspect` of all of
    /// `image`.
    pub(super) fn record_upload(
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
            return Err(Error::Usage("readback buffer too small".into()));
        }
        self.record_copy(image, rect, buffer, 0)
    }

    /// Records the copy of `rect` of `image` into `buffer` at byte `offset`.
    pub(super) fn record_copy(
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
            return Err(Error::Usage(
                "stencil readback needs a DepthStencil image and room for a byte per pixel".into(),
            ));
        }
        self.record_aspect_copy(image, rect, buffer, 0, vk::ImageAspectFlags::STENCIL)
    }

    pub(super) fn record_aspect_copy(
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
}
