//! The pipeline cache, kept on disk between processes: a driver compiles each
//! pipeline state once per machine, not once per process (lavapipe compiles
//! with LLVM, so a process's first diagram waits for it).
//!
//! The file lives in [`MachineOptions::pipeline_cache`](super::MachineOptions),
//! named by the device, the driver's version and its pipeline cache UUID, so that another device or
//! driver never reads it. It is written whole to a temporary name and renamed,
//! so processes sharing it see one version or the other. A cache that cannot
//! be read or written costs time, never a result: such failures are ignored.

use std::{
    cell::Cell,
    path::{Path, PathBuf},
    sync::{
        atomic::{AtomicU64, Ordering},
        Arc,
    },
};

use ash::vk;

use super::context::Context;
use crate::error::{Result, VkContext};

/// A `VkPipelineCache` loaded from and saved to its file.
pub(crate) struct PipelineCache {
    ctx: Arc<Context>,
    pub handle: vk::PipelineCache,
    path: Option<PathBuf>,
    /// Pipelines were made since the file was last written.
    unsaved: Cell<bool>,
}

impl PipelineCache {
    /// The cache kept in `folder`, or in memory only.
    pub fn open(ctx: &Arc<Context>, folder: Option<&Path>) -> Result<Self> {
        let path = folder.map(|dir| dir.join(file_name(&ctx.properties)));
        let data = path
            .as_deref()
            .and_then(|p| std::fs::read(p).ok())
            .filter(|data| written_by(data, &ctx.properties))
            .unwrap_or_default();
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
        // SAFETY: valid create info, with data that this device and driver
        // wrote (its header checked above). Destroyed in `Drop`.
        let handle =
            unsafe { ctx.device.create_pipeline_cache(&info, None) }.vk("vkCreatePipelineCache")?;
        Ok(Self {
            ctx: ctx.clone(),
            handle,
            path,
            unsaved: Cell::new(false),
        })
    }

    /// Notes that a pipeline was made through the cache.
    pub(crate) fn grew(&self) {
        self.unsaved.set(true);
    }

    /// Writes the cache to its file if pipelines were made since the last write.
    pub fn save(&self) {
        if !self.unsaved.replace(false) {
            return;
        }
        let Some(path) = &self.path else { return };
        // SAFETY: a live cache of this device.
        let Ok(data) = (unsafe { self.ctx.device.get_pipeline_cache_data(self.handle) }) else {
            return;
        };
        let _ = write_whole(path, &data);
    }
}

impl Drop for PipelineCache {
    fn drop(&mut self) {
        self.save();
        // SAFETY: no pipeline creation is in flight; destroyed once.
        unsafe { self.ctx.device.destroy_pipeline_cache(self.handle, None) };
    }
}

/// `pipelines-VENDOR-DEVICE-DRIVER-UUID.bin`, all in hexadecimal.
#[expect(clippy::disallowed_methods, reason = "a 16-byte UUID")]
fn file_name(properties: &vk::PhysicalDeviceProperties) -> String {
    let uuid: String = properties
        .pipeline_cache_uuid
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    format!(
        "pipelines-{:04x}-{:04x}-{:x}-{uuid}.bin",
        properties.vendor_id, properties.device_id, properties.driver_version
    )
}

/// Whether `data` starts with the header that `vkGetPipelineCacheData` writes
/// on this device and driver; a torn, foreign or stale file is not handed to
/// the driver.
fn written_by(data: &[u8], properties: &vk::PhysicalDeviceProperties) -> bool {
    let word = |i: usize| {
        data.get(4 * i..4 * i + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    const HEADER_BYTES: u32 = 32;
    word(0) == Some(HEADER_BYTES)
        && word(1) == Some(vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32)
        && word(2) == Some(properties.vendor_id)
        && word(3) == Some(properties.device_id)
        && data.get(16..32) == Some(&properties.pipeline_cache_uuid[..])
}

fn write_whole(path: &Path, data: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    // Unique per machine, also between machines of one process.
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let n = WRITES.fetch_add(1, Ordering::Relaxed);
    let temporary = dir.join(format!(".pipelines-{}-{n}.tmp", std::process::id()));
    std::fs::write(&temporary, data)?;
    std::fs::rename(&temporary, path)
}
