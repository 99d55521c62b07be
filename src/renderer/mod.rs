//! The renderer: one scene on one device, rendered frame after frame through the pass graph.
//! The CLI, the tests and (later) the app and the benchmarks all drive it the same way.

use ash::vk;
use glam::camera::rh::proj::vulkan;
use glam::Mat4;
use leakless_device::{Buffer, BufferDesc, Gpu, Image, ImageDesc, MemoryLocation};
use leakless_graph::{Graph, GraphRunner, PassTiming, Timing};
use leakless_scene::{Camera, Scene};

use crate::error::Result;
use crate::gpu_scene::GpuScene;
use crate::gpu_types::{Frame, ReferenceParams};
use crate::passes::compose::{ComposeImages, ComposePass};
use crate::passes::direct::DirectPass;
use crate::passes::gather::GatherOutputs;
use crate::passes::gbuffer::{self, GBuffer, GBufferPass};
use crate::passes::readback;
use crate::passes::reference::ReferencePass;
use crate::passes::ViewInputs;
use crate::settings::{Method, RenderSettings};
use crate::splatting::{PhotonSplatting, SplatStats};
use crate::trace::{Backend, TraceScene, TraceStats};

mod capture;
pub use capture::Capture;

/// The layers of one rendered frame, linear radiance, row-major from the top-left pixel.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    pub width: u32,
    pub height: u32,
    /// Final radiance: direct + indirect.
    pub radiance: Vec<[f32; 3]>,
    pub direct: Vec<[f32; 3]>,
    pub indirect: Vec<[f32; 3]>,
    /// Indirect light the visibility test removed (zero for methods without it).
    pub leaked: Vec<[f32; 3]>,
    /// Per-pass times, summed over the submissions of the frame (a reference frame runs its
    /// path tracer in several).
    pub timings: Vec<PassTiming>,
    /// Host wall-clock time of the whole frame.
    pub wall_ms: f64,
    /// What the photon method counted, for methods that splat.
    pub splat: Option<SplatStats>,
}

impl RenderedFrame {
    /// Fills the splat stats' leaked energy fraction from the layers.
    fn with_leaked_fraction(mut self) -> Self {
        if let Some(stats) = &mut self.splat {
            let lum = |l: &[[f32; 3]]| {
                l.iter().map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64).sum::<f64>()
            };
            let (lost, kept) = (lum(&self.leaked), lum(&self.indirect));
            stats.leaked_energy_fraction = if lost + kept > 0.0 { lost / (lost + kept) } else { 0.0 };
        }
        self
    }

    pub fn pixel(layer: &[[f32; 3]], width: u32, x: u32, y: u32) -> [f32; 3] {
        layer[(y * width + x) as usize]
    }
}

struct Passes {
    gbuffer: GBufferPass,
    direct: DirectPass,
    reference: ReferencePass,
    compose: ComposePass,
}

/// The images a frame writes, kept between frames.
struct Targets {
    gbuffer: GBuffer,
    direct: Image,
    indirect_sum: Image,
    indirect: Image,
    leaked: Image,
    radiance: Image,
}

impl Targets {
    fn new(gpu: &Gpu, extent: vk::Extent2D) -> Result<Targets> {
        let image = |name| {
            let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
            Image::new(gpu, &ImageDesc { name, extent, format: gbuffer::FORMAT, usage })
        };
        Ok(Targets {
            gbuffer: GBuffer::new(gpu, extent)?,
            direct: image("direct")?,
            indirect_sum: image("indirect sum")?,
            indirect: image("indirect")?,
            leaked: image("leaked")?,
            radiance: image("radiance")?,
        })
    }
}

/// The layers read back: radiance, direct, indirect, leaked.
const LAYERS: u64 = 4;

pub struct Renderer {
    settings: RenderSettings,
    camera: Camera,
    scene_name: String,
    scene: GpuScene,
    trace: TraceScene,
    frame: Buffer,
    targets: Targets,
    readback: Buffer,
    passes: Passes,
    /// The photon part of the frame, for methods that splat.
    splatting: Option<PhotonSplatting>,
    runner: GraphRunner,
    // Dropped last: every resource above belongs to this device.
    gpu: Gpu,
}

impl Renderer {
    pub fn new(gpu: Gpu, scene: &Scene, settings: RenderSettings) -> Result<Renderer> {
        settings.validate()?;
        let extent = vk::Extent2D { width: settings.width, height: settings.height };
        let backend = settings.backend.resolve(gpu.capabilities(), &gpu.report().name)?;
        let gpu_scene = GpuScene::upload(&gpu, scene)?;
        let trace = TraceScene::build(&gpu, scene, &gpu_scene, backend)?;
        let frame = Buffer::new(
            &gpu,
            &BufferDesc {
                name: "frame",
                size: std::mem::size_of::<Frame>() as u64,
                usage: vk::BufferUsageFlags::UNIFORM_BUFFER,
                location: MemoryLocation::CpuToGpu,
            },
        )?;
        let targets = Targets::new(&gpu, extent)?;
        let readback = Buffer::new(
            &gpu,
            &BufferDesc {
                name: "readback",
                size: LAYERS * extent.width as u64 * extent.height as u64 * 16,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        let passes = Passes {
            gbuffer: GBufferPass::new(&gpu)?,
            direct: DirectPass::new(&gpu, backend)?,
            reference: ReferencePass::new(&gpu, backend)?,
            compose: ComposePass::new(&gpu)?,
        };
        let splatting = match settings.photon_settings() {
            Some(photons) => {
                let s = &settings;
                Some(PhotonSplatting::new(&gpu, scene, backend, s.width, s.height, &photons, s.max_bounces, s.seed)?)
            }
            None => None,
        };
        let runner = GraphRunner::new(&gpu, 128)?;
        gpu.check_validation()?;
        Ok(Renderer {
            settings,
            camera: scene.camera_or_framing(),
            scene_name: scene.name.clone(),
            scene: gpu_scene,
            trace,
            frame,
            targets,
            readback,
            passes,
            splatting,
            runner,
            gpu,
        })
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The view-sample hierarchy, for methods that splat (tests and tools inspect it).
    pub fn hierarchy(&self) -> Option<&crate::passes::hierarchy::Hierarchy> {
        self.splatting.as_ref().map(|s| &s.hierarchy)
    }

    pub fn backend(&self) -> Backend {
        self.trace.backend()
    }

    /// What building the trace structures cost.
    pub fn trace_stats(&self) -> &TraceStats {
        self.trace.stats()
    }

    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    pub fn scene_name(&self) -> &str {
        &self.scene_name
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Per-pass timestamps in one submission (default), or one timed submission per pass.
    pub fn set_timing(&mut self, timing: Timing) {
        self.runner.set_timing(timing);
    }

    /// The camera's view-projection for the output aspect ratio (the glTF yfov is kept), in
    /// Vulkan's clip space: depth 0..1, y pointing down the image.
    fn view_proj(&self) -> Mat4 {
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        let c = &self.camera;
        let proj = match c.zfar {
            Some(zfar) => vulkan::perspective(c.yfov, aspect, c.znear, zfar),
            None => vulkan::perspective_infinite(c.yfov, aspect, c.znear),
        };
        proj * c.view_from_world()
    }

    /// Renders one frame and reads its layers back.
    pub fn render(&mut self) -> Result<RenderedFrame> {
        self.render_with_progress(&mut |_, _| {})
    }

    /// Renders one frame; `progress(done, total)` is called as reference samples accumulate.
    /// A splat frame whose node lists overflowed is rendered once more with lists large
    /// enough (unless the capacity was fixed by the user or is at its maximum, in which case
    /// the drops are reported in the frame's stats).
    pub fn render_with_progress(&mut self, progress: &mut dyn FnMut(u32, u32)) -> Result<RenderedFrame> {
        let frame = self.render_once(progress)?;
        let grew = match &mut self.splatting {
            Some(s) => s.grow_lists_after_drops(&self.gpu)?,
            None => false,
        };
        if grew {
            self.render_once(progress)
        } else {
            Ok(frame)
        }
    }

    fn render_once(&mut self, progress: &mut dyn FnMut(u32, u32)) -> Result<RenderedFrame> {
        let start = std::time::Instant::now();
        let (width, height) = (self.settings.width, self.settings.height);
        let frame = Frame {
            view_proj: self.view_proj().to_cols_array_2d(),
            camera_position: self.camera.position().extend(1.0).to_array(),
            width,
            height,
            light_count: self.scene.light_count,
            pad0: 0,
        };
        self.frame.write(0, bytemuck::bytes_of(&frame))?;
        let mut timings = Timings::default();

        // The view samples and their direct light; the reference's first samples ride along.
        let total = if self.settings.method == Method::Reference { self.settings.spp } else { 0 };
        let mut done = 0;
        let mut chunk = total.min(1);
        let t = std::time::Instant::now();
        timings.add(self.run(true, done, chunk, None)?);
        done += chunk;
        progress(done, total);
        // Size later submissions to about half a second each: responsive progress, few
        // submissions, and far from the lost-device timeout.
        let mut last_ms = t.elapsed().as_secs_f64() * 1e3;
        while done < total {
            let per_sample = last_ms / chunk.max(1) as f64;
            chunk = ((500.0 / per_sample.max(1e-3)) as u32).clamp(1, 256).min(total - done);
            let t = std::time::Instant::now();
            timings.add(self.run(false, done, chunk, None)?);
            last_ms = t.elapsed().as_secs_f64() * 1e3;
            done += chunk;
            progress(done, total);
        }
        let scale = match self.settings.method {
            Method::Reference => 1.0 / total as f32,
            Method::Splat | Method::LeakLessCapped | Method::LeakLess => 1.0,
            Method::Direct => 0.0,
        };
        timings.add(self.run(false, done, 0, Some(scale))?);

        let texels: Vec<[f32; 4]> = self.readback.read_vec(LAYERS as usize * (width * height) as usize)?;
        let layer = |i: usize| -> Vec<[f32; 3]> {
            texels[i * (width * height) as usize..(i + 1) * (width * height) as usize]
                .iter()
                .map(|t| [t[0], t[1], t[2]])
                .collect()
        };
        Ok(RenderedFrame {
            width,
            height,
            radiance: layer(0),
            direct: layer(1),
            indirect: layer(2),
            leaked: layer(3),
            timings: timings.0,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
            splat: self.splatting.as_ref().map(|s| s.read_stats()).transpose()?,
        }
        .with_leaked_fraction())
    }

    /// One submission: optionally the view samples and direct light, then `sample_count`
    /// reference samples after `first_sample`, then (with `compose`'s indirect scale) the
    /// final image and its readback.
    fn run(
        &mut self,
        view_samples: bool,
        first_sample: u32,
        sample_count: u32,
        compose: Option<f32>,
    ) -> Result<Vec<PassTiming>> {
        let mut graph = Graph::new();
        let frame = graph.import_buffer(&self.frame);
        let scene = self.scene.import(&mut graph);
        let trace = self.trace.import(&mut graph);
        let t = &self.targets;
        let mut gbuffer = t.gbuffer.import(&mut graph);
        let mut direct = graph.import_image(&t.direct);
        let mut indirect_sum = graph.import_image(&t.indirect_sum);
        let mut indirect = graph.import_image(&t.indirect);
        let mut radiance = graph.import_image(&t.radiance);
        let mut leaked = graph.import_image(&t.leaked);
        let mut readback = graph.import_buffer(&self.readback);

        if view_samples {
            self.passes.gbuffer.add(&mut graph, &frame, &scene, self.scene.vertex_count, &mut gbuffer);
        }
        let view = ViewInputs { frame: &frame, scene: &scene, trace: &trace, gbuffer: &gbuffer };
        if view_samples {
            self.passes.direct.add(&mut graph, &view, &mut direct);
            if let Some(splatting) = &self.splatting {
                let out = GatherOutputs { indirect_sum: &mut indirect_sum, leaked: &mut leaked };
                splatting.add(&mut graph, &frame, &scene, &trace, &gbuffer, out)?;
            }
        }
        if sample_count > 0 {
            let params = ReferenceParams {
                first_sample,
                sample_count,
                max_bounces: self.settings.max_bounces,
                seed: self.settings.seed,
                roulette_start: 3,
                ..Default::default()
            };
            self.passes.reference.add(&mut graph, &params, &view, &mut indirect_sum)?;
        }
        if let Some(scale) = compose {
            let images = ComposeImages {
                direct: &direct,
                indirect_sum: &indirect_sum,
                indirect: &mut indirect,
                radiance: &mut radiance,
                leaked: &mut leaked,
            };
            self.passes.compose.add(&mut graph, scale, self.splatting.is_some(), &frame, images)?;
            readback::add(&mut graph, &[&radiance, &direct, &indirect, &leaked], &mut readback);
        }
        Ok(self.runner.run(&self.gpu, graph)?)
    }
}

/// Per-pass times summed by pass name, in first-run order.
#[derive(Default)]
struct Timings(Vec<PassTiming>);

impl Timings {
    fn add(&mut self, run: Vec<PassTiming>) {
        for t in run {
            match self.0.iter_mut().find(|x| x.name == t.name) {
                Some(x) => {
                    x.ms += t.ms;
                    x.wall_ms = match (x.wall_ms, t.wall_ms) {
                        (Some(a), Some(b)) => Some(a + b),
                        (a, b) => a.or(b),
                    };
                }
                None => self.0.push(t),
            }
        }
    }
}
