//! GPU timestamps: a query pool reset from the host before each use.

use std::sync::Arc;

use ash::vk;

use crate::error::{Result, VkContext};
use crate::gpu::{Gpu, Shared};

pub struct TimestampPool {
    shared: Arc<Shared>,
    raw: vk::QueryPool,
    capacity: u32,
    period_ns: f64,
}

impl TimestampPool {
    pub fn new(gpu: &Gpu, capacity: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(capacity);
        // SAFETY: valid device and create info.
        let raw = unsafe { gpu.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        Ok(TimestampPool {
            shared: gpu.shared.clone(),
            raw,
            capacity,
            period_ns: gpu.report().timestamp_period_ns as f64,
        })
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    pub(crate) fn raw(&self) -> vk::QueryPool {
        self.raw
    }

    /// Resets every query from the host (hostQueryReset); call before recording writes.
    pub fn reset(&self) {
        // SAFETY: no submission using the pool is pending (callers reset between frames).
        unsafe { self.shared.device.reset_query_pool(self.raw, 0, self.capacity) };
    }

    /// Reads the first `count` timestamps in nanoseconds, after the work completed.
    pub fn read_ns(&self, count: u32) -> Result<Vec<f64>> {
        let mut ticks = vec![0u64; count.min(self.capacity) as usize];
        if ticks.is_empty() {
            return Ok(vec![]);
        }
        // SAFETY: the queries were written by completed work; WAIT is not needed after a fence.
        unsafe {
            self.shared.device.get_query_pool_results(
                self.raw,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(ticks.into_iter().map(|t| t as f64 * self.period_ns).collect())
    }
}

impl Drop for TimestampPool {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pool.
        unsafe { self.shared.device.destroy_query_pool(self.raw, None) };
    }
}
