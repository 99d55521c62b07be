//! The renderer: one scene on one device, rendered frame after frame through the pass graph.
//! The CLI, the tests and (later) the app and the benchmarks all drive it the same way.

use ash::vk;
use glam::Mat4;
use leakless_device::{Buffer, BufferDesc, Gpu, Image, ImageDesc, MemoryLocation};
use leakless_graph::{Graph, GraphRunner, PassTiming, Timing};
use leakless_scene::{Camera, Scene};

use crate::error::{RenderError, Result};
use crate::gpu_scene::GpuScene;
use crate::gpu_types::Frame;
use crate::passes::direct::DirectPass;
use crate::passes::gbuffer::{self, GBuffer, GBufferPass, SceneInputs};
use crate::passes::readback;

/// What to render and how.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
        }
    }
}

/// Largest image side accepted: bounds memory (a 16k² frame of this renderer's layers would
/// need tens of GiB).
pub const MAX_SIDE: u32 = 8192;

impl RenderSettings {
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 || self.width > MAX_SIDE || self.height > MAX_SIDE {
            return Err(RenderError::Settings(format!(
                "size {}x{} must be within 1..={MAX_SIDE} per side",
                self.width, self.height
            )));
        }
        Ok(())
    }
}

/// The layers of one rendered frame, linear radiance, row-major from the top-left pixel.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    pub width: u32,
    pub height: u32,
    /// Final radiance (direct + indirect).
    pub radiance: Vec<[f32; 3]>,
    pub direct: Vec<[f32; 3]>,
    pub timings: Vec<PassTiming>,
    /// Host wall-clock time from the start of recording to the end of the last wait.
    pub wall_ms: f64,
}

impl RenderedFrame {
    pub fn pixel(layer: &[[f32; 3]], width: u32, x: u32, y: u32) -> [f32; 3] {
        layer[(y * width + x) as usize]
    }
}

struct Passes {
    gbuffer: GBufferPass,
    direct: DirectPass,
}

pub struct Renderer {
    settings: RenderSettings,
    camera: Camera,
    scene_name: String,
    scene: GpuScene,
    frame: Buffer,
    gbuffer: GBuffer,
    direct: Image,
    readback: Buffer,
    passes: Passes,
    runner: GraphRunner,
    // Dropped last: every resource above belongs to this device.
    gpu: Gpu,
}

impl Renderer {
    pub fn new(gpu: Gpu, scene: &Scene, settings: RenderSettings) -> Result<Renderer> {
        settings.validate()?;
        let extent = vk::Extent2D {
            width: settings.width,
            height: settings.height,
        };
        let gpu_scene = GpuScene::upload(&gpu, scene)?;
        let frame = Buffer::new(
            &gpu,
            &BufferDesc {
                name: "frame",
                size: std::mem::size_of::<Frame>() as u64,
                usage: vk::BufferUsageFlags::UNIFORM_BUFFER,
                location: MemoryLocation::CpuToGpu,
            },
        )?;
        let gbuffer = GBuffer::new(&gpu, extent)?;
        let direct = Image::new(
            &gpu,
            &ImageDesc {
                name: "direct",
                extent,
                format: gbuffer::FORMAT,
                usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            },
        )?;
        let readback = Buffer::new(
            &gpu,
            &BufferDesc {
                name: "readback",
                size: extent.width as u64 * extent.height as u64 * 16,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        let passes = Passes {
            gbuffer: GBufferPass::new(&gpu)?,
            direct: DirectPass::new(&gpu)?,
        };
        let runner = GraphRunner::new(&gpu, 64)?;
        gpu.check_validation()?;
        Ok(Renderer {
            settings,
            camera: scene.camera_or_framing(),
            scene_name: scene.name.clone(),
            scene: gpu_scene,
            frame,
            gbuffer,
            direct,
            readback,
            passes,
            runner,
            gpu,
        })
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Per-pass timestamps in one submission (default), or one timed submission per pass.
    pub fn set_timing(&mut self, timing: Timing) {
        self.runner.set_timing(timing);
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

    /// The camera's view-projection for the output aspect ratio (the glTF yfov is kept).
    fn view_proj(&self) -> Mat4 {
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        let c = &self.camera;
        let proj = match c.zfar {
            Some(zfar) => Mat4::perspective_rh(c.yfov, aspect, c.znear, zfar),
            None => Mat4::perspective_infinite_rh(c.yfov, aspect, c.znear),
        };
        proj * c.view_from_world()
    }

    /// Renders one frame and reads its layers back.
    pub fn render(&mut self) -> Result<RenderedFrame> {
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

        let mut graph = Graph::new();
        let frame = graph.import_buffer(&self.frame);
        let vertices = graph.import_buffer(&self.scene.vertices);
        let materials = graph.import_buffer(&self.scene.materials);
        let triangle_materials = graph.import_buffer(&self.scene.triangle_materials);
        let texels = graph.import_buffer(&self.scene.texels);
        let lights = graph.import_buffer(&self.scene.lights);
        let mut gbuffer = self.gbuffer.import(&mut graph);
        let mut direct = graph.import_image(&self.direct);
        let mut readback = graph.import_buffer(&self.readback);

        let scene = SceneInputs {
            vertices: &vertices,
            vertex_count: self.scene.vertex_count,
            materials: &materials,
            triangle_materials: &triangle_materials,
            texels: &texels,
        };
        self.passes
            .gbuffer
            .add(&mut graph, &frame, scene, &mut gbuffer);
        self.passes
            .direct
            .add(&mut graph, &frame, &lights, &gbuffer, &mut direct);
        readback::add(&mut graph, &[&direct], &mut readback);
        let start = std::time::Instant::now();
        let timings = self.runner.run(&self.gpu, graph)?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;

        let texels: Vec<[f32; 4]> = self.readback.read_vec((width * height) as usize)?;
        let direct: Vec<[f32; 3]> = texels.iter().map(|t| [t[0], t[1], t[2]]).collect();
        Ok(RenderedFrame {
            width,
            height,
            radiance: direct.clone(),
            direct,
            timings,
            wall_ms,
        })
    }
}
