//! Executing a graph: derived barriers, labels, timestamps and crash markers around each pass.

use std::time::Instant;

use ash::vk;
use leakless_device::{Buffer, BufferDesc, Cmd, DeviceError, Gpu, MemoryLocation, Result, TimestampPool};

use crate::barrier::{ResourceState, Transition};
use crate::graph::{Graph, Pass, Resource};

/// Time of one pass.
#[derive(Clone, Debug)]
pub struct PassTiming {
    pub name: String,
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
    /// One submission per pass, each waited for and timed on the host as well. Slower, but
    /// exact on drivers whose timestamps do not bracket the work (lavapipe runs compute
    /// dispatches asynchronously to its timestamp writes).
    PerPassSubmit,
}

/// What persists between graph executions: the timestamp pool and the crash-marker buffer.
pub struct GraphRunner {
    timestamps: TimestampPool,
    /// Two words per pass, set to 1 when the GPU starts and ends the pass: after a lost
    /// device they show which pass was running.
    markers: Buffer,
    max_passes: u32,
    timing: Timing,
}

/// What recording one pass needs besides the pass itself.
struct RecordContext<'a, 'r> {
    resources: &'a [Resource<'r>],
    markers: &'a Buffer,
    timestamps: &'a TimestampPool,
}

impl RecordContext<'_, '_> {
    /// Derived barriers, then the pass between its label, timestamps and crash markers.
    fn record(&self, cmd: &mut Cmd<'_>, index: usize, pass: Pass<'_>, states: &mut [ResourceState]) -> Result<()> {
        let mut buffer_barriers = Vec::new();
        let mut image_barriers = Vec::new();
        for &(id, access) in &pass.uses {
            if let Some(t) = states[id].access(access) {
                match &self.resources[id] {
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
        (pass.record)(cmd)?;
        cmd.write_timestamp(self.timestamps, 2 * index as u32 + 1);
        cmd.fill_buffer(self.markers, slot + 4, 4, 1);
        cmd.end_label();
        Ok(())
    }
}

impl GraphRunner {
    pub fn new(gpu: &Gpu, max_passes: u32) -> Result<Self> {
        let timestamps = TimestampPool::new(gpu, 2 * max_passes)?;
        let markers = Buffer::new(
            gpu,
            &BufferDesc {
                name: "pass markers",
                size: 8 * max_passes as u64,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        Ok(GraphRunner { timestamps, markers, max_passes, timing: Timing::default() })
    }

    pub fn set_timing(&mut self, timing: Timing) {
        self.timing = timing;
    }

    /// Records every pass in order with derived barriers, submits, waits, and returns the GPU
    /// time of each pass.
    pub fn run(&mut self, gpu: &Gpu, graph: Graph<'_>) -> Result<Vec<PassTiming>> {
        let Graph { resources, passes } = graph;
        if passes.len() as u32 > self.max_passes {
            return Err(DeviceError::Capacity {
                name: "pass graph".into(),
                capacity: self.max_passes as u64,
                requested: passes.len() as u64,
            });
        }
        let names: Vec<String> = passes.iter().map(|p| p.name.clone()).collect();
        let mut states: Vec<ResourceState> = resources
            .iter()
            .map(|r| match r {
                Resource::Buffer(b) => ResourceState::buffer(b.device_written()),
                Resource::Image(i) => ResourceState::image(i.layout()),
            })
            .collect();
        self.timestamps.reset();
        self.markers.write(0, &vec![0u8; 8 * passes.len()])?;
        let ctx = RecordContext { resources: &resources, markers: &self.markers, timestamps: &self.timestamps };

        let mut wall_ms = vec![None; names.len()];
        let submitted = match self.timing {
            Timing::Timestamps => gpu.submit(|cmd| {
                for (index, pass) in passes.into_iter().enumerate() {
                    ctx.record(cmd, index, pass, &mut states)?;
                }
                Ok(())
            }),
            Timing::PerPassSubmit => passes.into_iter().enumerate().try_for_each(|(index, pass)| {
                let start = Instant::now();
                gpu.submit(|cmd| ctx.record(cmd, index, pass, &mut states))?;
                wall_ms[index] = Some(start.elapsed().as_secs_f64() * 1e3);
                Ok(())
            }),
        };
        match submitted {
            Ok(()) => {}
            Err(DeviceError::DeviceLost { where_ }) => {
                return Err(DeviceError::DeviceLost { where_: format!("{where_} {}", self.last_pass(&names)) })
            }
            Err(e) => return Err(e),
        }
        for (r, s) in resources.iter().zip(&states) {
            match r {
                Resource::Image(i) => i.set_layout(s.layout()),
                Resource::Buffer(b) if s.written() => b.set_device_written(),
                Resource::Buffer(_) => {}
            }
        }
        gpu.check_validation()?;
        let ns = self.timestamps.read_ns(2 * names.len() as u32)?;
        Ok(names
            .into_iter()
            .zip(wall_ms)
            .enumerate()
            .map(|(i, (name, wall_ms))| PassTiming { name, ms: (ns[2 * i + 1] - ns[2 * i]).max(0.0) * 1e-6, wall_ms })
            .collect())
    }

    /// Names the pass the GPU was in (or last finished) according to the markers.
    fn last_pass(&self, names: &[String]) -> String {
        let words: Vec<u32> = match self.markers.read_vec(2 * names.len()) {
            Ok(w) => w,
            Err(_) => return "(pass markers unreadable)".into(),
        };
        let started = (0..names.len()).rev().find(|&i| words[2 * i] == 1);
        match started {
            None => "before the first pass started".into(),
            Some(i) if words[2 * i + 1] == 0 => format!("during pass {:?}", names[i]),
            Some(i) => format!("after pass {:?}", names[i]),
        }
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
