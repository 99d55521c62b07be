//! Hang: fault injection for the lost-device path (`hang.comp`; docs/architecture.md,
//! "Lost devices"). Debug builds read `LEAKLESS_FAULT_HANG=<pass>`; the named pass then
//! spins on the device until the host releases it, so the frame outlasts
//! `LEAKLESS_GPU_TIMEOUT` and must end in `device lost during pass <pass>`.

use std::rc::Rc;

use ash::vk;
use leakless_device::{Buffer, BufferDesc, ComputePipeline, Gpu, MemoryLocation};
use leakless_graph::{shader_bindings, Graph, GraphRunner, PassName, Stage};

use crate::error::Result;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

shader_bindings! {
    pub struct HangBindings {
        release: read_write words,
    }
    pub struct HangResources;
}

compute_pass! {
    /// The spin, appended to the pass it stalls (its own name labels no pass).
    pub static HANG in TOOL_PASSES: ComputePass<HangBindings, ()> =
        ComputePass::any(PassName::new("hang", group::TOOLS), &shaders::HANG_COMP, &[]);
}

/// A stall armed for one named pass.
pub struct HangPass {
    pass: String,
    pipeline: ComputePipeline,
    /// One host-visible word: non-zero lets the spinning invocation return. Shared with the
    /// graph runner, which releases the stall as soon as it finds the device lost.
    release: Rc<Buffer>,
}

impl HangPass {
    /// The stall `LEAKLESS_FAULT_HANG` asks for, in debug builds; `None` otherwise. Release
    /// builds never stall (and say so once when the variable is set).
    pub fn from_env(gpu: &Gpu) -> Result<Option<HangPass>> {
        let Some(pass) = std::env::var("LEAKLESS_FAULT_HANG").ok().filter(|p| !p.is_empty()) else {
            return Ok(None);
        };
        if !cfg!(debug_assertions) {
            eprintln!("warning: LEAKLESS_FAULT_HANG is ignored: fault injection exists in debug builds only");
            return Ok(None);
        }
        // It traces nothing and has no specialization constants.
        let pipeline = HANG.create(gpu, crate::trace::Backend::Compute, &crate::DeviceTuning::cpu())?;
        let release = Buffer::new(
            gpu,
            &BufferDesc {
                name: "hang release",
                size: 4,
                usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::CpuToGpu,
            },
        )?;
        release.write(0, &[0u8; 4])?;
        Ok(Some(HangPass { pass, pipeline, release: Rc::new(release) }))
    }

    /// Appends the spin to the graph's pass of that name, if the frame has one.
    pub fn add<'r>(&'r self, graph: &mut Graph<'r>) {
        let mut release = graph.import_buffer(&self.release);
        let Some(mut pass) = graph.extend_pass(&self.pass) else { return };
        let own = HangBindings::declare(&mut pass, Stage::Compute, HangResources { release: &mut release });
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &(), [1, 1, 1]));
    }

    /// Lets a spinning invocation return: before the device is waited on and torn down.
    pub fn release(&self) {
        let _ = self.release.store_word(0, 1);
    }

    /// Has `runner` release the stall the moment it finds the device lost: whatever waits for
    /// the device next (a swapchain's teardown, the renderer's) then finds it idle.
    pub fn release_on_device_lost(&self, runner: &mut GraphRunner) {
        let release = self.release.clone();
        runner.on_device_lost(move || {
            let _ = release.store_word(0, 1);
        });
    }
}
