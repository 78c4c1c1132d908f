//! The sections of a run, each labelled for debuggers and, under a
//! [`Profiler`](super::Profiler), timed on the device with timestamp queries.

use std::{sync::Arc, time::Instant};

use ash::vk;

use super::{
    context::Context,
    profile::{PassSpan, Profiler},
};
use crate::{
    error::{Result, VkContext},
    memory::Gather,
};

/// Timestamp queries in pools of this many.
const POOL_QUERIES: u32 = 256;

/// The sections of the run being recorded and the query pools that time them:
/// section `s` writes queries `2s` (start) and `2s + 1` (end).
pub(crate) struct Sections {
    ctx: Arc<Context>,
    /// Time each section on the device.
    timed: bool,
    pools: Vec<vk::QueryPool>,
    /// Pools reset in this run's command buffer so far.
    reset: usize,
    labels: Vec<String>,
    open: bool,
}

impl Sections {
    pub fn new(ctx: &Arc<Context>, timed: bool) -> Self {
        Self {
            ctx: ctx.clone(),
            timed: timed && ctx.timestamp_period.is_some(),
            pools: Vec::new(),
            reset: 0,
            labels: Vec::new(),
            open: false,
        }
    }

    /// Starts a run's recording.
    pub fn clear(&mut self) {
        self.labels.clear();
        self.reset = 0;
        self.open = false;
    }

    /// Opens a section labelled `label` (outside a rendering pass, where query
    /// pools can be reset).
    pub fn begin(&mut self, cmd: vk::CommandBuffer, label: &str) -> Result<()> {
        debug_assert!(!self.open, "sections do not nest");
        if self.timed {
            let query = 2 * self.labels.len() as u32;
            self.write(cmd, query, vk::PipelineStageFlags2::TOP_OF_PIPE)?;
        }
        self.ctx.begin_label(cmd, label);
        self.labels.push(label.to_string());
        self.open = true;
        Ok(())
    }

    /// Closes the open section; `label` replaces the one it was opened with
    /// when the section's content is known only at its end.
    pub fn end(&mut self, cmd: vk::CommandBuffer, label: Option<String>) -> Result<()> {
        if !self.open {
            return Ok(());
        }
        self.open = false;
        if let (Some(label), Some(last)) = (label, self.labels.last_mut()) {
            *last = label;
        }
        if self.timed {
            let query = 2 * (self.labels.len() as u32 - 1) + 1;
            self.write(cmd, query, vk::PipelineStageFlags2::ALL_COMMANDS)?;
        }
        self.ctx.end_label(cmd);
        Ok(())
    }

    /// Writes timestamp `query` after the work of `stage` before it, resetting
    /// its pool first if this run has not yet.
    fn write(
        &mut self,
        cmd: vk::CommandBuffer,
        query: u32,
        stage: vk::PipelineStageFlags2,
    ) -> Result<()> {
        let pool = (query / POOL_QUERIES) as usize;
        while self.pools.len() <= pool {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(POOL_QUERIES);
            // SAFETY: valid create info; destroyed in `Drop`.
            let created = unsafe { self.ctx.device.create_query_pool(&info, None) }
                .vk("vkCreateQueryPool")?;
            self.ctx.name_object(created, "pixgeo timestamps");
            self.pools.push(created);
        }
        let device = &self.ctx.device;
        while self.reset <= pool {
            // SAFETY: recording state outside a rendering pass; no query of the
            // pool is in use by this command buffer yet.
            unsafe { device.cmd_reset_query_pool(cmd, self.pools[self.reset], 0, POOL_QUERIES) };
            self.reset += 1;
        }
        // SAFETY: the query was reset above in this command buffer.
        unsafe { device.cmd_write_timestamp2(cmd, stage, self.pools[pool], query % POOL_QUERIES) };
        Ok(())
    }

    /// After the run's submission has completed: each section's span, the
    /// device's clock aligned to `submitted` on the profiler's.
    pub fn spans(&self, profiler: &Profiler, submitted: Instant) -> Result<Vec<PassSpan>> {
        let start_ms = profiler.ms_since_start(submitted);
        let Some(period_ns) = self.ctx.timestamp_period.filter(|_| self.timed) else {
            return self
                .labels
                .iter()
                .map(|label| PassSpan {
                    label: label.clone(),
                    start_ms,
                    gpu_ms: None,
                })
                .gather("gpu ms");
        };
        let queries = 2 * self.labels.len();
        let mut stamps = crate::memory::filled(queries, 0u64, "timestamps")?;
        for (chunk, pool) in stamps.chunks_mut(POOL_QUERIES as usize).zip(&self.pools) {
            // SAFETY: the queries were written by the completed submission.
            unsafe {
                self.ctx.device.get_query_pool_results(
                    *pool,
                    0,
                    chunk,
                    vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                )
            }
            .vk("vkGetQueryPoolResults")?;
        }
        let ms = |ticks: u64| ticks as f64 * period_ns as f64 * 1e-6;
        let first = stamps.first().copied().unwrap_or(0);
        self.labels
            .iter()
            .zip(stamps.chunks_exact(2))
            .map(|(label, pair)| PassSpan {
                label: label.clone(),
                start_ms: start_ms + ms(pair[0].wrapping_sub(first) & self.ctx.timestamp_mask),
                gpu_ms: Some(ms(pair[1].wrapping_sub(pair[0]) & self.ctx.timestamp_mask)),
            })
            .gather("gpu ms")
    }
}

impl Drop for Sections {
    fn drop(&mut self) {
        // SAFETY: the machine has waited for all work; each pool is destroyed once.
        unsafe {
            for pool in &self.pools {
                self.ctx.device.destroy_query_pool(*pool, None);
            }
        }
    }
}
