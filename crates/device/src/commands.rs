//! Command buffers that outlive their submission: one [`CommandSlot`] per frame in flight, each
//! with its own pool and fence, so the host records frame N+1 while the GPU runs frame N and
//! waits only when it comes back to a slot whose frame has not finished. [`Semaphore`]s order
//! submissions against the presentation engine.

use std::sync::Arc;
use std::time::Duration;

use ash::vk;

use crate::bind::Bound;
use crate::error::{DeviceError, Result, VkContext};
use crate::frame_set::{BoundFrameSet, FrameBinding, FrameSet};
use crate::gpu::{Gpu, Shared};
use crate::Cmd;

/// A binary semaphore (swapchain acquire and present).
pub struct Semaphore {
    shared: Arc<Shared>,
    raw: vk::Semaphore,
}

impl Semaphore {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        // SAFETY: valid device and create info.
        let raw = unsafe { gpu.device().create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
            .vk("vkCreateSemaphore")?;
        gpu.set_name(raw, name);
        Ok(Semaphore { shared: gpu.shared.clone(), raw })
    }

    pub fn raw(&self) -> vk::Semaphore {
        self.raw
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        // SAFETY: owners drop semaphores only after the device is idle or their last use waited.
        unsafe { self.shared.device.destroy_semaphore(self.raw, None) };
    }
}

/// What a submission waits for and signals besides its fence.
#[derive(Default)]
pub struct SubmitSync<'a> {
    /// Semaphores to wait for, each before the given stages.
    pub wait: Vec<(&'a Semaphore, vk::PipelineStageFlags2)>,
    pub signal: Vec<&'a Semaphore>,
}

/// One reusable command buffer with its pool and fence.
pub struct CommandSlot {
    shared: Arc<Shared>,
    pool: vk::CommandPool,
    raw: vk::CommandBuffer,
    fence: vk::Fence,
    /// Whether a submission's fence has not been waited for yet.
    in_flight: bool,
    timeout: Duration,
    /// The frame set its frames bind, made by the first that writes one (dropped after the
    /// wait in `drop`).
    frame_set: Option<FrameSet>,
}

impl CommandSlot {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = gpu.device();
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(gpu.report().queue_family);
        // SAFETY: valid device and create info.
        let pool = unsafe { device.create_command_pool(&info, None) }.vk("vkCreateCommandPool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool was just created from this device.
        let raw = match unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers") {
            Ok(buffers) => buffers[0],
            Err(e) => {
                // SAFETY: nothing was allocated from the pool.
                unsafe { device.destroy_command_pool(pool, None) };
                return Err(e);
            }
        };
        // SAFETY: valid device and create info.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        gpu.set_name(raw, name);
        gpu.set_name(fence, name);
        let timeout = gpu.timeout();
        Ok(CommandSlot { shared: gpu.shared.clone(), pool, raw, fence, in_flight: false, timeout, frame_set: None })
    }

    /// Writes the slot's frame set, declared by `frame`, with `bound` (each resource by its
    /// binding's name; [`FrameSet::write`]) once the slot's last submission, which may still
    /// read the set it wrote before, has completed.
    pub fn write_frame_set(
        &mut self,
        gpu: &Gpu,
        frame: &'static [FrameBinding],
        bound: &[(&'static str, Bound<'_>)],
    ) -> Result<BoundFrameSet> {
        self.wait()?;
        let set = match &mut self.frame_set {
            Some(set) if std::ptr::eq(set.frame(), frame) => set,
            made => made.insert(FrameSet::new(gpu, frame)?),
        };
        set.write(gpu, bound)
    }

    /// Whether the slot's last submission may still be running.
    pub fn in_flight(&self) -> bool {
        self.in_flight
    }

    /// Waits for the slot's last submission. A submission that does not complete within
    /// `LEAKLESS_GPU_TIMEOUT` counts as a lost device.
    pub fn wait(&mut self) -> Result<()> {
        self.wait_progressing(|| 0)
    }

    /// Waits for the slot's last submission for as long as it makes progress: `progress` reads
    /// how far the submission got (the pass graph counts its crash markers), and a submission
    /// whose progress stays the same for `LEAKLESS_GPU_TIMEOUT` counts as a lost device. A long
    /// frame of many passes on a slow or busy device is not lost; a pass that never ends is.
    pub fn wait_progressing(&mut self, mut progress: impl FnMut() -> u64) -> Result<()> {
        if !self.in_flight {
            return Ok(());
        }
        let mut reached = progress();
        loop {
            // SAFETY: the fence belongs to this device and was submitted.
            match unsafe { self.shared.device.wait_for_fences(&[self.fence], true, self.timeout.as_nanos() as u64) } {
                Ok(()) => break,
                Err(vk::Result::TIMEOUT) => {
                    let now = progress();
                    if now != reached {
                        reached = now;
                        continue;
                    }
                    return Err(DeviceError::DeviceLost {
                        at: String::new(),
                        cause: format!("no progress within {} s, LEAKLESS_GPU_TIMEOUT", self.timeout.as_secs()),
                    });
                }
                Err(e) => return Err(e).vk("vkWaitForFences"),
            }
        }
        // SAFETY: the fence is signalled and no longer in use.
        unsafe { self.shared.device.reset_fences(&[self.fence]) }.vk("vkResetFences")?;
        self.in_flight = false;
        Ok(())
    }

    /// Waits for the slot, then records a fresh command buffer with `record`.
    pub fn record<T>(&mut self, gpu: &Gpu, record: impl FnOnce(&mut Cmd<'_>) -> Result<T>) -> Result<T> {
        self.wait()?;
        let device = gpu.device();
        // SAFETY: the slot's last submission completed (waited above), so the pool is idle.
        unsafe { device.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty()) }.vk("vkResetCommandPool")?;
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the buffer is in the initial state after the pool reset.
        unsafe { device.begin_command_buffer(self.raw, &begin) }.vk("vkBeginCommandBuffer")?;
        let mut cmd = Cmd { gpu, raw: self.raw, frame: None, frame_bound: [false; 2] };
        let value = record(&mut cmd);
        // SAFETY: recording state (ended even when `record` failed, so the pool reset next time
        // finds no buffer left recording).
        let ended = unsafe { device.end_command_buffer(self.raw) }.vk("vkEndCommandBuffer");
        let value = value?;
        ended?;
        Ok(value)
    }

    /// Submits what was last recorded, signalling the slot's fence; does not wait.
    pub fn submit(&mut self, gpu: &Gpu, sync: &SubmitSync<'_>) -> Result<()> {
        let waits: Vec<_> = sync
            .wait
            .iter()
            .map(|(s, stage)| vk::SemaphoreSubmitInfo::default().semaphore(s.raw).stage_mask(*stage))
            .collect();
        let signals: Vec<_> = sync
            .signal
            .iter()
            .map(|s| {
                vk::SemaphoreSubmitInfo::default().semaphore(s.raw).stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            })
            .collect();
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.raw)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals);
        // SAFETY: the buffer is executable (recorded by `record`), the fence unsignalled (reset
        // by `wait`), and the queue is used from this thread only (Gpu is not Sync).
        unsafe { gpu.device().queue_submit2(gpu.queue, &[submit], self.fence) }.vk("vkQueueSubmit2")?;
        self.in_flight = true;
        Ok(())
    }
}

impl Drop for CommandSlot {
    fn drop(&mut self) {
        // SAFETY: a pending submission is waited for (or the device is lost) before the pool
        // and fence go away.
        unsafe {
            if self.in_flight {
                let _ = self.shared.device.wait_for_fences(&[self.fence], true, self.timeout.as_nanos() as u64);
            }
            self.shared.device.destroy_fence(self.fence, None);
            self.shared.device.destroy_command_pool(self.pool, None);
        }
    }
}
