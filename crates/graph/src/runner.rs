//! Executing graphs with frames in flight: each frame records into its own slot (command
//! buffer, fence, timestamps, crash markers, per-frame resources); the host waits only when it
//! comes back to a slot whose frame is still running. Barriers are derived per pass, labels,
//! timestamps and crash markers bracket each pass under its name.

use std::time::Instant;

use ash::vk;
use leakless_device::{
    BoundFrameSet, Buffer, BufferDesc, Cmd, CommandSlot, DeviceError, Gpu, MemoryLocation, Result, SubmitSync,
    TimestampPool,
};

use crate::barrier::{ResourceState, Transition};
use crate::bindings::{PassContext, Resolved, Resource};
use crate::graph::{FrameSetUses, Graph, Pass, Source};
use crate::pool::{PoolKey, ResourcePool};

/// Time of one pass.
#[derive(Clone, Debug)]
pub struct PassTiming {
    pub name: String,
    /// The group of the pass's [`PassName`](crate::PassName).
    pub group: &'static str,
    /// GPU timestamp difference (end − start of the pass).
    pub ms: f64,
    /// Host wall-clock time of the pass's own submission, when the runner submits each pass
    /// separately (`Timing::PerPassSubmit`); otherwise `None`.
    pub wall_ms: Option<f64>,
}

/// How the runner measures passes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Timing {
    /// One submission per frame; per-pass GPU timestamps only.
    #[default]
    Timestamps,
    /// One submission per pass, each waited for and timed on the host as well. Slower, and it
    /// keeps no frame in flight, but exact on drivers whose timestamps do not bracket the work
    /// (lavapipe runs compute dispatches asynchronously to its timestamp writes).
    PerPassSubmit,
}

/// A frame that finished on the GPU: its index, the slot it ran in (whose per-frame buffers
/// now hold what it wrote) and what each pass took.
#[derive(Clone, Debug)]
pub struct CompletedFrame {
    pub index: u64,
    pub slot: usize,
    pub timings: Vec<PassTiming>,
    /// GPU time from the first pass's start to the last pass's end, ms: the frame's time on
    /// the device with `Timing::Timestamps` (with `PerPassSubmit` it includes the host's
    /// waits between submissions).
    pub span_ms: f64,
}

/// A frame on its way: [`GraphRunner::wait_for`] waits for it.
#[derive(Clone, Copy, Debug)]
#[must_use = "a submitted frame is waited for with GraphRunner::wait_for, or left in flight"]
pub struct Submitted {
    slot: usize,
}

/// Most passes one graph may hold (timestamps and crash markers are sized for it).
pub const MAX_PASSES: u32 = 256;

struct Running {
    frame: u64,
    /// Each pass's label and group.
    passes: Vec<(String, &'static str)>,
    wall_ms: Vec<Option<f64>>,
}

/// One frame in flight's own objects.
struct Slot {
    commands: CommandSlot,
    timestamps: TimestampPool,
    /// Two words per pass, set to 1 when the GPU starts and ends the pass: after a lost
    /// device they show which pass was running.
    markers: Buffer,
    running: Option<Running>,
}

/// What persists between graph executions: the frame slots and the resource pool.
pub struct GraphRunner {
    slots: Vec<Slot>,
    /// The slot the next graph records into.
    next: usize,
    /// Index of the next frame.
    frame: u64,
    /// Whether `next` was waited for and may be recorded into.
    acquired: bool,
    pub(crate) pool: ResourcePool,
    timing: Timing,
    /// Called when a wait finds the device lost, before the error returns.
    on_lost: Option<Box<dyn Fn()>>,
}

impl GraphRunner {
    /// A runner keeping up to `frames_in_flight` frames on the GPU at once.
    pub fn new(gpu: &Gpu, frames_in_flight: usize) -> Result<Self> {
        assert!(frames_in_flight >= 1, "at least one frame");
        let slots = (0..frames_in_flight)
            .map(|i| {
                Ok(Slot {
                    commands: CommandSlot::new(gpu, &format!("frame slot {i}"))?,
                    timestamps: TimestampPool::new(gpu, 2 * MAX_PASSES)?,
                    markers: Buffer::new(
                        gpu,
                        &BufferDesc {
                            name: "pass markers",
                            size: 8 * MAX_PASSES as u64,
                            usage: vk::BufferUsageFlags::TRANSFER_DST,
                            location: MemoryLocation::GpuToCpu,
                        },
                    )?,
                    running: None,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(GraphRunner {
            slots,
            next: 0,
            frame: 0,
            acquired: false,
            pool: ResourcePool::default(),
            timing: Timing::default(),
            on_lost: None,
        })
    }

    /// Runs `f` whenever a wait finds the device lost (a submission outlived
    /// `LEAKLESS_GPU_TIMEOUT`), before the error is returned: what must happen before anything
    /// waits for the device again (releasing a fault-injection stall).
    pub fn on_device_lost(&mut self, f: impl Fn() + 'static) {
        self.on_lost = Some(Box::new(f));
    }

    pub fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    pub fn set_timing(&mut self, timing: Timing) {
        self.timing = timing;
    }

    pub fn timing(&self) -> Timing {
        self.timing
    }

    pub(crate) fn slot(&self) -> usize {
        self.next
    }

    pub(crate) fn frame_index(&self) -> u64 {
        self.frame
    }

    /// The frame slot the next graph records into (per-frame objects outside the graph, such
    /// as a swapchain's acquire semaphores, are indexed by it).
    pub fn next_slot(&self) -> usize {
        self.next
    }

    /// The index the next submitted frame gets (frames count from 0 in submission order).
    pub fn next_frame(&self) -> u64 {
        self.frame
    }

    /// Forgets what every history image holds: the next frame that asks for one gets no valid
    /// history (a change of scene, method or settings that makes the last frames' images
    /// another estimate).
    pub fn invalidate_histories(&mut self) {
        self.pool.invalidate_histories();
    }

    /// The resources graphs made by name (read per-frame buffers of a completed frame here).
    pub fn pool(&self) -> &ResourcePool {
        &self.pool
    }

    /// Waits until the next frame's slot is free and returns the frame that ran in it, if
    /// any. [`GraphRunner::graph`] does this when it was not done.
    pub fn acquire_slot(&mut self, gpu: &Gpu) -> Result<Option<CompletedFrame>> {
        if self.acquired {
            return Ok(None);
        }
        let done = self.complete(gpu, self.next)?;
        self.acquired = true;
        Ok(done)
    }

    /// Starts the next frame's graph (waiting for its slot if needed).
    pub fn graph<'r>(&'r mut self, gpu: &'r Gpu) -> Result<Graph<'r>> {
        self.acquire_slot(gpu)?;
        let timing = self.timing;
        Ok(Graph {
            gpu,
            runner: self,
            sources: Vec::new(),
            passes: Vec::new(),
            pipelines: None,
            frame_set: None,
            timing,
        })
    }

    /// Waits for every frame in flight, oldest first, and returns them.
    pub fn wait_idle(&mut self, gpu: &Gpu) -> Result<Vec<CompletedFrame>> {
        let n = self.slots.len();
        let mut done = Vec::new();
        for k in 0..n {
            // From the oldest submission to the newest.
            let slot = (self.next + k) % n;
            if let Some(frame) = self.complete(gpu, slot)? {
                done.push(frame);
            }
        }
        if !self.slots.is_empty() {
            self.acquired = true; // `next` is idle now
        }
        Ok(done)
    }

    /// Waits for a submitted frame (and every frame before it).
    pub fn wait_for(&mut self, gpu: &Gpu, submitted: Submitted) -> Result<CompletedFrame> {
        // Earlier frames first, so their per-frame resources are collected in order.
        let n = self.slots.len();
        let mut last = None;
        for k in 0..n {
            let slot = (self.next + k) % n;
            let done = self.complete(gpu, slot)?;
            if slot == submitted.slot {
                last = done;
                break;
            }
        }
        if submitted.slot == self.next {
            self.acquired = true;
        }
        last.ok_or_else(|| DeviceError::Unsupported("wait_for: the frame was already collected".into()))
    }

    /// Waits for `slot`'s frame, if one is running, and collects it.
    fn complete(&mut self, gpu: &Gpu, slot: usize) -> Result<Option<CompletedFrame>> {
        let s = &mut self.slots[slot];
        let passes = s.running.as_ref().map_or(0, |r| r.passes.len());
        let markers = &s.markers;
        if let Err(e) = s.commands.wait_progressing(|| passes_reached(markers, passes)) {
            if let (DeviceError::DeviceLost { .. }, Some(f)) = (&e, &self.on_lost) {
                f();
            }
            return Err(match (e, &s.running) {
                (DeviceError::DeviceLost { cause, .. }, Some(r)) => {
                    DeviceError::DeviceLost { at: format!(" {}", last_pass(&s.markers, &r.passes)), cause }
                }
                (e, _) => e,
            });
        }
        let Some(running) = s.running.take() else { return Ok(None) };
        gpu.check_validation()?;
        let ns = s.timestamps.read_ns(2 * running.passes.len() as u32)?;
        let timings = running
            .passes
            .into_iter()
            .zip(running.wall_ms)
            .enumerate()
            .map(|(i, ((name, group), wall_ms))| PassTiming {
                name,
                group,
                ms: (ns[2 * i + 1] - ns[2 * i]).max(0.0) * 1e-6,
                wall_ms,
            })
            .collect();
        let span_ms = match (ns.first(), ns.last()) {
            (Some(start), Some(end)) => (end - start).max(0.0) * 1e-6,
            _ => 0.0,
        };
        // A fence covers every earlier submission too: all frames up to this one are done.
        self.pool.collect(running.frame);
        Ok(Some(CompletedFrame { index: running.frame, slot, timings, span_ms }))
    }
}

impl Graph<'_> {
    /// Records every pass in order with derived barriers into this frame's slot and submits
    /// it, waiting for `sync`'s semaphores and signalling its own; does not wait for the GPU.
    pub fn submit(self, sync: &SubmitSync<'_>) -> Result<Submitted> {
        let Graph { gpu, runner, sources, passes, frame_set, timing, .. } = self;
        let on_lost = runner.on_lost.as_deref();
        if passes.len() as u32 > MAX_PASSES {
            return Err(DeviceError::Capacity {
                name: "pass graph".into(),
                capacity: MAX_PASSES as u64,
                requested: passes.len() as u64,
            });
        }
        assert!(runner.acquired, "a graph records only into an acquired slot");
        let resources: Vec<Resource<'_>> = sources
            .iter()
            .map(|s| match s {
                Source::Buffer(b) => Resource::Buffer(b),
                Source::Image(i) | Source::Acquired(i, _) => Resource::Image(i),
                Source::PoolBuffer(key) => Resource::Buffer(runner.pool.buffer(key)),
                Source::PoolImage(key) => Resource::Image(runner.pool.image(key)),
            })
            .collect();
        let mut states: Vec<ResourceState> = resources
            .iter()
            .zip(&sources)
            .map(|(r, s)| match (r, s) {
                (_, Source::Acquired(_, stage)) => ResourceState::acquired_image(*stage),
                // This frame's copy of a per-frame buffer: the frame that used it last has completed.
                (Resource::Buffer(b), Source::PoolBuffer(PoolKey::PerFrame(..))) => {
                    ResourceState::buffer(b.device_written())
                }
                (Resource::Buffer(b), _) => ResourceState::shared_buffer(b.device_written()),
                (Resource::Image(i), _) => ResourceState::image(i.layout()),
            })
            .collect();
        let names: Vec<(String, &'static str)> = passes.iter().map(|p| (p.name.clone(), p.group)).collect();
        let (slot_index, slot_count) = (runner.next, runner.slots.len());
        let slot = &mut runner.slots[slot_index];
        slot.timestamps.reset();
        slot.markers.write(0, &vec![0u8; 8 * passes.len()])?;
        let res = Resolved { resources: &resources };
        let frame_set = match frame_set {
            Some(FrameSetUses { frame, groups, .. }) => {
                let mut bound = Vec::new();
                groups.bind(res, &mut bound);
                Some(slot.commands.write_frame_set(gpu, frame, &bound)?)
            }
            None => None,
        };
        let ctx =
            RecordContext { res, frame_set: frame_set.as_ref(), markers: &slot.markers, timestamps: &slot.timestamps };
        let mut wall_ms = vec![None; passes.len()];
        let frame = runner.frame;
        let recorded: Result<()> = match timing {
            Timing::Timestamps => slot
                .commands
                .record(gpu, |cmd| {
                    ctx.begin(cmd);
                    for (index, pass) in passes.into_iter().enumerate() {
                        ctx.record(cmd, index, pass, &mut states)?;
                    }
                    Ok(())
                })
                .and_then(|()| slot.commands.submit(gpu, sync)),
            Timing::PerPassSubmit => {
                let count = passes.len();
                passes.into_iter().enumerate().try_for_each(|(index, pass)| {
                    let start = Instant::now();
                    slot.commands.record(gpu, |cmd| {
                        ctx.begin(cmd);
                        ctx.record(cmd, index, pass, &mut states)
                    })?;
                    // The frame's semaphores go on its first and last submissions.
                    let part = SubmitSync {
                        wait: if index == 0 { sync.wait.clone() } else { vec![] },
                        signal: if index + 1 == count { sync.signal.clone() } else { vec![] },
                    };
                    slot.commands.submit(gpu, &part)?;
                    let markers = &slot.markers;
                    let waited = slot.commands.wait_progressing(|| passes_reached(markers, count));
                    wall_ms[index] = Some(start.elapsed().as_secs_f64() * 1e3);
                    waited.map_err(|e| match e {
                        DeviceError::DeviceLost { cause, .. } => {
                            if let Some(f) = on_lost {
                                f();
                            }
                            DeviceError::DeviceLost { at: format!(" during pass {}", names[index].0), cause }
                        }
                        e => e,
                    })
                })
            }
        };
        // Resources keep the state this frame leaves them in, for the next frame's barriers
        // (recorded later, so ordered after this one on the queue).
        for (r, s) in resources.iter().zip(&states) {
            match r {
                Resource::Image(i) => i.set_layout(s.layout()),
                Resource::Buffer(b) if s.written() => b.set_device_written(),
                Resource::Buffer(_) => {}
            }
        }
        if recorded.is_ok() {
            slot.running = Some(Running { frame, passes: names, wall_ms });
        }
        runner.acquired = false;
        runner.next = (slot_index + 1) % slot_count;
        runner.frame += 1;
        recorded?;
        gpu.check_validation()?;
        Ok(Submitted { slot: slot_index })
    }
}

/// What recording one pass needs besides the pass itself.
struct RecordContext<'a> {
    res: Resolved<'a>,
    /// The graph's frame set, written for this frame.
    frame_set: Option<&'a BoundFrameSet>,
    markers: &'a Buffer,
    timestamps: &'a TimestampPool,
}

impl RecordContext<'_> {
    /// Starts a command buffer of the frame: its passes bind the frame's set.
    fn begin(&self, cmd: &mut Cmd<'_>) {
        if let Some(set) = self.frame_set {
            cmd.use_frame_set(set);
        }
    }

    /// Derived barriers, then the pass between its label, timestamps and crash markers.
    fn record(&self, cmd: &mut Cmd<'_>, index: usize, pass: Pass<'_>, states: &mut [ResourceState]) -> Result<()> {
        let mut buffer_barriers = Vec::new();
        let mut image_barriers = Vec::new();
        for &(id, access) in &pass.uses {
            if let Some(t) = states[id].access(access) {
                match self.res.resources[id] {
                    Resource::Buffer(b) => buffer_barriers.push(buffer_barrier(b, &t)),
                    Resource::Image(i) => image_barriers.push(image_barrier(i, &t)),
                }
            }
        }
        cmd.barriers(&buffer_barriers, &image_barriers);
        let slot = 8 * index as u64;
        cmd.begin_label(&pass.name);
        cmd.fill_buffer(self.markers, slot, 4, 1);
        cmd.write_timestamp(self.timestamps, 2 * index as u32);
        let mut ctx = PassContext { cmd, res: self.res };
        (pass.record)(&mut ctx)?;
        cmd.write_timestamp(self.timestamps, 2 * index as u32 + 1);
        cmd.fill_buffer(self.markers, slot + 4, 4, 1);
        cmd.end_label();
        Ok(())
    }
}

/// Names the pass the GPU was in (or last finished) according to the markers.
/// How far a running frame got: the pass markers set so far (what a wait counts as progress).
fn passes_reached(markers: &Buffer, passes: usize) -> u64 {
    markers.read_vec::<u32>(2 * passes).map_or(0, |w| w.iter().filter(|&&m| m == 1).count() as u64)
}

fn last_pass(markers: &Buffer, names: &[(String, &'static str)]) -> String {
    let words: Vec<u32> = match markers.read_vec(2 * names.len()) {
        Ok(w) => w,
        Err(_) => return "(pass markers unreadable)".into(),
    };
    let started = (0..names.len()).rev().find(|&i| words[2 * i] == 1);
    match started {
        None => "before the first pass started".into(),
        Some(i) if words[2 * i + 1] == 0 => format!("during pass {}", names[i].0),
        Some(i) => format!("after pass {}", names[i].0),
    }
}

fn buffer_barrier<'a>(buffer: &Buffer, t: &Transition) -> vk::BufferMemoryBarrier2<'a> {
    vk::BufferMemoryBarrier2::default()
        .src_stage_mask(t.src_stage)
        .src_access_mask(t.src_access)
        .dst_stage_mask(t.dst_stage)
        .dst_access_mask(t.dst_access)
        .buffer(buffer.raw())
        .offset(0)
        .size(vk::WHOLE_SIZE)
}

fn image_barrier<'a>(image: &leakless_device::Image, t: &Transition) -> vk::ImageMemoryBarrier2<'a> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(t.src_stage)
        .src_access_mask(t.src_access)
        .dst_stage_mask(t.dst_stage)
        .dst_access_mask(t.dst_access)
        .old_layout(t.old_layout)
        .new_layout(t.new_layout)
        .image(image.raw())
        .subresource_range(
            vk::ImageSubresourceRange::default().aspect_mask(image.aspect()).level_count(1).layer_count(1),
        )
}
