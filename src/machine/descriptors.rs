//! Descriptor sets, made inside the layer for the resources a pass binds by
//! reference: a set lives until its run has completed, and sets of one run
//! with the same resources are one set.

use crate::memory::Gather;
use std::{cell::RefCell, collections::HashMap, sync::Arc};

use ash::vk;

use super::{context::Context, memory::Buffer, Image};
use crate::error::{Error, Result, VkContext};

/// Sets per pool; a run that binds more distinct sets opens another pool.
const SETS_PER_POOL: u32 = 64;

/// What a set holds: its layout, a storage image at a binding, and storage
/// buffers from a first binding on.
#[derive(Clone, PartialEq, Eq, Hash)]
struct SetKey {
    layout: vk::DescriptorSetLayout,
    image: Option<(vk::ImageView, u32)>,
    first_buffer: u32,
    buffers: Vec<vk::Buffer>,
}

pub(crate) struct DescriptorSets {
    ctx: Arc<Context>,
    /// Pools in order of use; those before `pools.len() - 1` are full.
    pools: RefCell<Vec<vk::DescriptorPool>>,
    /// The sets of the run being recorded.
    sets: RefCell<HashMap<SetKey, vk::DescriptorSet>>,
}

impl DescriptorSets {
    pub fn new(ctx: &Arc<Context>) -> Self {
        Self {
            ctx: ctx.clone(),
            pools: RefCell::default(),
            sets: RefCell::default(),
        }
    }

    /// A set of `layout` with `image` at its binding and `buffers` at the
    /// bindings from `first_buffer` on, valid until [`Self::release`].
    pub fn set(
        &self,
        layout: vk::DescriptorSetLayout,
        image: Option<(&Image, u32)>,
        first_buffer: u32,
        buffers: &[&Buffer],
    ) -> Result<vk::DescriptorSet> {
        let key = SetKey {
            layout,
            image: image.map(|(image, binding)| (image.view, binding)),
            first_buffer,
            buffers: buffers.iter().map(|b| b.raw).gather("image")?,
        };
        if let Some(set) = self.sets.borrow().get(&key) {
            return Ok(*set);
        }
        let set = self.allocate(layout)?;
        self.write(set, image, first_buffer, buffers);
        self.sets.borrow_mut().insert(key, set);
        Ok(set)
    }

    fn allocate(&self, layout: vk::DescriptorSetLayout) -> Result<vk::DescriptorSet> {
        let layouts = [layout];
        if let Some(&pool) = self.pools.borrow().last() {
            let alloc = vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(pool)
                .set_layouts(&layouts);
            // SAFETY: pool and layout are valid; the set is released with its
            // pool's reset after the run that used it has completed.
            match unsafe { self.ctx.device.allocate_descriptor_sets(&alloc) } {
                Ok(sets) => return Ok(sets[0]),
                Err(vk::Result::ERROR_OUT_OF_POOL_MEMORY | vk::Result::ERROR_FRAGMENTED_POOL) => {}
                Err(e) => return Err(Error::vulkan("vkAllocateDescriptorSets", e)),
            }
        }
        let pool = self.new_pool()?;
        self.pools.borrow_mut().push(pool);
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: as above, from a new, empty pool.
        let sets = unsafe { self.ctx.device.allocate_descriptor_sets(&alloc) }
            .vk("vkAllocateDescriptorSets")?;
        Ok(sets[0])
    }

    fn new_pool(&self) -> Result<vk::DescriptorPool> {
        // Room for every set layout of the machine at its largest: a storage
        // image and up to eight storage buffers per set.
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_IMAGE,
                descriptor_count: SETS_PER_POOL,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: 8 * SETS_PER_POOL,
            },
        ];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(SETS_PER_POOL)
            .pool_sizes(&sizes);
        // SAFETY: valid create info; destroyed in `Drop`.
        unsafe { self.ctx.device.create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")
    }

    #[expect(clippy::disallowed_methods, reason = "one set's bindings")]
    fn write(
        &self,
        set: vk::DescriptorSet,
        image: Option<(&Image, u32)>,
        first_buffer: u32,
        buffers: &[&Buffer],
    ) {
        let image_info: Vec<_> = image
            .iter()
            .map(|(image, _)| {
                vk::DescriptorImageInfo::default()
                    .image_view(image.view)
                    .image_layout(vk::ImageLayout::GENERAL)
            })
            .collect();
        let buffer_infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.raw)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let mut writes: Vec<vk::WriteDescriptorSet> = buffer_infos
            .iter()
            .enumerate()
            .map(|(k, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(first_buffer + k as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        if let Some((_, binding)) = image {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding)
                    .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                    .image_info(&image_info),
            );
        }
        // SAFETY: the set is new and not in use; the infos outlive the call.
        unsafe { self.ctx.device.update_descriptor_sets(&writes, &[]) };
    }

    /// Frees every set, once no submission that used them is pending.
    pub fn release(&self) -> Result<()> {
        self.sets.borrow_mut().clear();
        for &pool in self.pools.borrow().iter() {
            // SAFETY: the run that used the pool's sets has completed or was
            // never submitted.
            unsafe {
                self.ctx
                    .device
                    .reset_descriptor_pool(pool, vk::DescriptorPoolResetFlags::empty())
            }
            .vk("vkResetDescriptorPool")?;
        }
        Ok(())
    }
}

impl Drop for DescriptorSets {
    fn drop(&mut self) {
        for &pool in self.pools.get_mut().iter() {
            // SAFETY: the machine has waited for all work; each pool is
            // destroyed once.
            unsafe { self.ctx.device.destroy_descriptor_pool(pool, None) };
        }
    }
}
